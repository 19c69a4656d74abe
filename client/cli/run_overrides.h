// The command-line flags that override a run spec's fields (`simulate` and, later, `run`).
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "mbstream/v1/run_spec.pb.h"

namespace mbstream::cli {

struct RunOverrides {
  std::optional<double> duration, output_interval, max_step, rtol, atol, step;
  std::optional<std::string> formulation, method, erk_table, keep;
  // The accuracy target (m, rad, relative) and whether to verify it.
  std::optional<double> target_tcp, target_joint, target_energy;
  std::optional<bool> verify;

  // Declares --duration, --output-interval, --max-step, --formulation, --method,
  // --erk-table, --rtol, --atol, --step, --target-tcp, --target-joint, --target-energy and
  // --verify and --keep on `command`.
  void AddTo(CLI::App& command);
  // Writes the given flags into `spec` (validation happens in ToRunConfig).
  void ApplyTo(v1::RunSpec& spec) const;
};

}  // namespace mbstream::cli
