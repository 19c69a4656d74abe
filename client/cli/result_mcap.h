// `mbstream result RUN --mcap FILE`: the run as one MCAP file, written by the server
// (ExportMcap: server/mcap/stored_run_mcap.h, the one MCAP writer) and saved here as its bytes
// come, so memory is a message, not the run.
#pragma once

#include <string>

#include "mbstream/v1/run.pb.h"
#include "mbstream/v1/simulation_service.grpc.pb.h"

namespace mbstream::cli {

struct ResultMcapOptions {
  std::string path;                  // empty: no MCAP file
  std::string compression = "zstd";  // zstd, lz4, none
  std::string start;  // --mcap-start's text; empty: the run's start (RunInfo.started_unix_ms)
};

// Checks the options before anything is downloaded; throws InputError naming the flag.
void CheckResultMcapOptions(const ResultMcapOptions& options);

// Streams ExportMcap for `run_id` (the probe reports of `probe_set`, or the live run's) into
// options.path, written as options.path + ".tmp" and renamed once whole. Fills *info. Returns
// the RPC's status (no file then); throws InputError when the file cannot be written.
grpc::Status SaveResultMcap(v1::Simulation::Stub& stub, const std::string& run_id,
                            const std::string& probe_set, bool wait,
                            const ResultMcapOptions& options, v1::RunInfo* info);

}  // namespace mbstream::cli
