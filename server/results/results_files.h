// Writes a run's results directory (design.md section 4): joints.csv, velocities.csv,
// tcp.csv, torques.csv (when dynamics ran), stats.json. Numbers are printed with 17
// significant digits, so the same run gives bit-identical files.
#pragma once

#include <string>

#include "server/sim/run_result.h"

namespace mbstream {

// What stats.json records beside the run's statistics, so a run can be reproduced.
struct RunProvenance {
  std::string model_name;
  std::string model_source;  // the URDF file or the model id
  std::string spec_json;     // the run spec as protobuf JSON (empty: omitted)
};

// Writes the files into `directory` (created if missing). Each file is written to a
// temporary name and renamed, so no half-written file is left behind. Throws InputError
// naming the path when the directory cannot be created or written.
void WriteResultsDirectory(const RunResult& result, const RunProvenance& provenance,
                           const std::string& directory);

// stats.json's text for a run.
std::string StatsJson(const RunResult& result, const RunProvenance& provenance);

}  // namespace mbstream
