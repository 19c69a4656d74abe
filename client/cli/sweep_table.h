// A sweep's table (DIR/sweep.csv): a row per run, its id, the swept values, then the run's
// summary (state, trust, cost, accuracy, and per joint the largest tracking error and the
// peak and RMS effort), all from the run's info: no frame is needed.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/run.pb.h"

namespace mbstream::cli {

// The header line (no newline) for `paths` and the model's `joints`.
std::string SweepTableHeader(const std::vector<std::string>& paths,
                             const std::vector<std::string>& joints);

// One run's line (no newline): `values` are its swept values, in the header's order.
std::string SweepTableRow(const v1::RunInfo& info, const std::vector<std::string>& values);

}  // namespace mbstream::cli
