// `mbstream simulate MODEL.urdf [--spec FILE.json] [overrides] --out DIR`: the engine
// in-process, no server.
#pragma once

#include <CLI/CLI.hpp>

namespace mbstream::cli {

// Adds the subcommand to `app`; its callback stores the exit code in *exit_code.
void AddSimulateCommand(CLI::App& app, int* exit_code);

}  // namespace mbstream::cli
