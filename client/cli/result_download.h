// Fetching a run's stored result and writing the results directory of the contract.
#pragma once

#include <string>

#include "client/cli/result_mcap.h"
#include "client/cli/server_connection.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream::cli {

// Streams GetResult for `run_id` and writes joints.csv, velocities.csv, tcp.csv,
// torques.csv, probes.csv and stats.json into `directory` (the same files, bit for bit, as
// `mbstream simulate` writes for the same model and spec). Fills *info. Returns the RPC's
// status; throws InputError when the directory cannot be written. probes.csv holds the live
// run's probe reports, or those of the replay probe set `probe_set` when one is given.
// An empty `directory` writes no files; `mcap` (when given, with a path) saves the run as
// MCAP too, as the server writes it (result_mcap.h; without a directory the frames are then
// not fetched at all). `wait`: a run not ended yet is waited for (else
// FAILED_PRECONDITION).
grpc::Status DownloadResult(v1::Simulation::Stub& stub, const std::string& run_id,
                            const std::string& directory, v1::RunInfo* info,
                            const std::string& probe_set = "",
                            const ResultMcapOptions* mcap = nullptr, bool wait = false);

}  // namespace mbstream::cli
