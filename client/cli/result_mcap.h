// `mbstream result RUN --mcap FILE`: a downloaded run as one MCAP file (server/mcap/run_mcap.h).
// The links' poses need the model: its text comes from the server (GetModel with its bundle)
// and is imported here as `mbstream simulate` imports a file.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/results/results_files.h"
#include "server/sim/run_result.h"

namespace mbstream::cli {

struct ResultMcapOptions {
  std::string path;                  // empty: no MCAP file
  std::string compression = "zstd";  // zstd, lz4, none
  std::string start;  // --mcap-start's text; empty: the run's start (RunInfo.started_unix_ms)
};

// Checks the options before anything is downloaded; throws InputError naming the flag.
void CheckResultMcapOptions(const ResultMcapOptions& options);

// Writes `result` (with its probe reports and stats.json's text) to options.path. Returns
// GetModel's status; throws InputError when the file cannot be written.
grpc::Status WriteResultMcap(v1::Simulation::Stub& stub, const v1::RunInfo& info,
                             const RunResult& result, const std::vector<ProbeRecord>& probes,
                             const std::string& stats_json, const ResultMcapOptions& options);

}  // namespace mbstream::cli
