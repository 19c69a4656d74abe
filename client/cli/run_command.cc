// `mbstream run MODEL [--spec FILE] [overrides] [--realtime F] [--watch] [--out DIR]`
#include <unistd.h>

#include <chrono>
#include <iostream>

#include "client/cli/exit_codes.h"
#include "client/cli/progress_line.h"
#include "client/cli/result_download.h"
#include "client/cli/run_overrides.h"
#include "client/cli/server_commands.h"
#include "client/cli/summary_line.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

struct RunOptions {
  std::string model, spec_path, out_dir;
  RunOverrides overrides;
  std::optional<double> realtime;
  bool watch = false;
  bool accept_untrusted = false;
};

// Follows the run to its end, showing progress on stderr; returns the final info.
grpc::Status Watch(v1::Simulation::Stub& stub, const std::string& run_id, v1::RunInfo* final) {
  const bool terminal = isatty(STDERR_FILENO);
  grpc::ClientContext context;
  v1::WatchRunRequest request;
  request.set_run_id(run_id);
  request.set_progress_interval_s(terminal ? 0.2 : 1.0);
  auto reader = stub.WatchRun(&context, request);
  v1::WatchEvent event;
  using Clock = std::chrono::steady_clock;
  Clock::time_point running_since{};
  while (reader->Read(&event)) {
    if (!event.has_progress()) continue;
    *final = event.progress();
    if (final->state() == v1::RUNNING && running_since == Clock::time_point{}) {
      running_since = Clock::now();
    }
    const double elapsed =
        running_since == Clock::time_point{}
            ? 0.0
            : std::chrono::duration<double>(Clock::now() - running_since).count();
    const std::string line = ProgressLine(*final, elapsed);
    if (terminal) {
      std::cerr << "\r\033[K" << line << std::flush;
    } else {
      std::cerr << line << "\n";
    }
  }
  if (terminal) std::cerr << "\n";
  return reader->Finish();
}

int RunOnServer(const ClientOptions& client, const RunOptions& options) {
  v1::StartRunRequest request;
  request.set_model(options.model);
  if (!options.spec_path.empty()) *request.mutable_spec() = LoadRunSpecFile(options.spec_path);
  options.overrides.ApplyTo(*request.mutable_spec());
  if (options.realtime) request.mutable_spec()->set_realtime(*options.realtime);
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  v1::RunInfo info;
  {
    grpc::ClientContext context;
    const grpc::Status status = stub->StartRun(&context, request, &info);
    if (!status.ok()) return ReportRpcError("run", client, status);
  }
  std::cout << info.id() << std::endl;
  for (const std::string& warning : info.warnings()) {
    std::cerr << "mbstream run: warning: " << warning << "\n";
  }
  if (!options.watch && options.out_dir.empty()) return 0;
  const grpc::Status watched = Watch(*stub, info.id(), &info);
  if (!watched.ok()) return ReportRpcError("run", client, watched);
  // A copy: DownloadResult below assigns a new RunInfo to `info`, which deletes the stats
  // message a reference would point at (found by UBSan's vptr check under --asan).
  const v1::RunStats s = info.stats();
  std::cerr << SummaryLine(v1::RunState_Name(info.state()), info.frames(), s) << "\n";
  if (!options.out_dir.empty()) {
    const grpc::Status downloaded = DownloadResult(*stub, info.id(), options.out_dir, &info);
    if (!downloaded.ok()) return ReportRpcError("run", client, downloaded);
    std::cerr << "results in " << options.out_dir << "\n";
  }
  if (info.state() != v1::FINISHED) {
    std::cerr << "mbstream run: run " << v1::RunState_Name(info.state()) << ": " << info.message()
              << "\n";
  }
  const bool finished = info.state() == v1::FINISHED;
  const bool missed = finished && s.has_target_met() && !s.target_met();
  if (finished && s.has_target_met()) {
    std::cerr << TargetLine(s.target_met(), info.message()) << "\n";
  }
  std::cerr << TrustLine(s.trust(), s.trust_reason()) << std::endl;
  if (!finished) return kExitRunFailed;
  if ((s.trust() == "low" || missed) && !options.accept_untrusted) return kExitUntrusted;
  return kExitOk;
}

}  // namespace

void AddRunCommand(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand("run", "start a run on the server; prints its id");
  command->add_option("model", options->model, "model id or name")->required();
  command->add_option("--spec", options->spec_path, "run spec (protobuf JSON of RunSpec)")
      ->check(CLI::ExistingFile);
  options->overrides.AddTo(*command);
  command->add_option("--realtime", options->realtime,
                      "pacing: simulated s per wall s (1 = real time, 0 = as fast as possible)");
  command->add_flag("--watch", options->watch, "show progress and wait for the end");
  command->add_flag("--accept-untrusted", options->accept_untrusted,
                    "with --watch/--out: exit 0 even when the finished run's trust is low or "
                    "it missed its accuracy target (else exit 4)");
  command->add_option("--out", options->out_dir, "write the results files here (implies waiting)");
  command->callback([client, options, exit_code] {
    try {
      *exit_code = RunOnServer(*client, *options);
    } catch (const InputError& error) {
      std::cerr << "mbstream run: " << error.what() << "\n";
      *exit_code = 2;
    }
  });
}

}  // namespace mbstream::cli
