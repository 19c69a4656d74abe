// `mbstream result RUN --out DIR` and `mbstream cancel RUN` (or `cancel --sweep SWEEP_ID`).
#include <iostream>

#include "client/cli/exit_codes.h"
#include "client/cli/result_download.h"
#include "client/cli/server_commands.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

int Result(const ClientOptions& client, const std::string& run_id, const std::string& out_dir,
           const std::string& probe_set, const ResultMcapOptions& mcap) {
  if (out_dir.empty() && mcap.path.empty()) {
    throw InputError("nothing to write: give --out DIR (the results files), --mcap FILE, or both");
  }
  CheckResultMcapOptions(mcap);
  v1::RunInfo info;
  const grpc::Status status =
      DownloadResult(*ConnectSimulation(client), run_id, out_dir, &info, probe_set, &mcap);
  if (!status.ok()) return ReportRpcError("result", client, status);
  std::cerr << run_id << " " << v1::RunState_Name(info.state()) << ": " << info.frames()
            << " frames, " << info.probe_reports() << " probe reports";
  if (!out_dir.empty()) std::cerr << "; results in " << out_dir;
  if (!mcap.path.empty()) std::cerr << "; MCAP in " << mcap.path;
  std::cerr << "\n";
  return info.state() == v1::FINISHED ? 0 : 1;
}

int Cancel(const ClientOptions& client, const std::string& run_id) {
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(run_id);
  v1::RunInfo info;
  const grpc::Status status = ConnectSimulation(client)->CancelRun(&context, request, &info);
  if (!status.ok()) return ReportRpcError("cancel", client, status);
  std::cout << run_id << " " << v1::RunState_Name(info.state()) << "\n";
  return 0;
}

}  // namespace

void AddResultCommands(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto run_id = std::make_shared<std::string>();
  auto out_dir = std::make_shared<std::string>();
  CLI::App* result = app.add_subcommand("result", "fetch an ended run's results files");
  result->add_option("run", *run_id, "run id")->required();
  result->add_option("--out", *out_dir, "results directory");
  auto mcap = std::make_shared<ResultMcapOptions>();
  result->add_option("--mcap", mcap->path,
                     "write the run as one MCAP file (ROS 2 topics /joint_states, /tf, "
                     "/robot_description; docs/mcap.md)");
  result
      ->add_option("--mcap-compression", mcap->compression,
                   "the MCAP file's chunk compression: zstd, lz4 or none")
      ->capture_default_str();
  result->add_option("--mcap-start", mcap->start,
                     "the MCAP stamps' time of t = 0, UTC: 2026-11-26T12:00:00Z or seconds "
                     "since the Unix epoch (default: the run's start)");
  auto probe_set = std::make_shared<std::string>();
  result->add_option("--probe-set", *probe_set,
                     "probes.csv from this replay's probe set (`mbstream probe-sets RUN`) "
                     "instead of the live run's");
  result->callback([client, run_id, out_dir, probe_set, mcap, exit_code] {
    try {
      *exit_code = Result(*client, *run_id, *out_dir, *probe_set, *mcap);
    } catch (const InputError& error) {
      std::cerr << "mbstream result: " << error.what() << "\n";
      *exit_code = 2;
    }
  });

  auto cancel_id = std::make_shared<std::string>();
  auto sweep_id = std::make_shared<std::string>();
  CLI::App* cancel =
      app.add_subcommand("cancel", "stop a queued or running run, or every run of a sweep");
  CLI::Option* run = cancel->add_option("run", *cancel_id, "run id");
  cancel
      ->add_option("--sweep", *sweep_id,
                   "cancel sweep ID instead: its queued and running runs, and the slices not "
                   "started (as `mbstream sweep --cancel ID`)")
      ->excludes(run);
  cancel->callback([client, cancel_id, sweep_id, exit_code] {
    if (cancel_id->empty() == sweep_id->empty()) {
      std::cerr << "mbstream cancel: give a RUN id or --sweep SWEEP_ID\n";
      *exit_code = kExitBadRequest;
      return;
    }
    *exit_code = sweep_id->empty() ? Cancel(*client, *cancel_id)
                                   : SweepCall(*client, *sweep_id, true, "cancel");
  });
}

}  // namespace mbstream::cli
