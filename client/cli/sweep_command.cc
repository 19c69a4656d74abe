// `mbstream sweep MODEL [--spec FILE] [overrides] (--grid PATH=VALUES ... | --list FILE.csv)
//  [--keep summary|final|every:N|all] [--window N] --out DIR`: one sweep on the server,
// its table in DIR/sweep.csv (sweep_table.h) and, when more than the summary is kept, each
// run's results in DIR/runs/RUN_ID/; its progress as the server reports it (GetSweep).
// `mbstream sweep --status SWEEP_ID` prints a sweep's progress, `--cancel SWEEP_ID` (or
// `mbstream cancel --sweep SWEEP_ID`) cancels it (CancelSweep: the command that started it
// stops starting runs and exits 1).
#include <unistd.h>

#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "client/cli/exit_codes.h"
#include "client/cli/result_download.h"
#include "client/cli/run_overrides.h"
#include "client/cli/server_commands.h"
#include "client/cli/sweep_axes.h"
#include "client/cli/sweep_progress_line.h"
#include "client/cli/sweep_table.h"
#include "common/check.h"
#include "server/spec/run_spec_json.h"

namespace mbstream::cli {

namespace {

struct SweepOptions {
  std::string model, spec_path, out_dir, list_path;
  std::vector<std::string> grid;
  RunOverrides overrides;
  int window = 32;
  std::string status_id, cancel_id;  // --status, --cancel: of a sweep started before
};

struct Pending {
  std::string run_id;
  std::vector<std::string> values;
};

// Starts the sweep's next slice (at most `count` runs) and queues its runs in *pending.
grpc::Status StartSlice(v1::Simulation::Stub& stub, v1::StartSweepRequest& request, int count,
                        v1::StartSweepResponse* response, std::deque<Pending>* pending) {
  request.set_max_runs(count);
  grpc::ClientContext context;
  const grpc::Status status = stub.StartSweep(&context, request, response);
  if (!status.ok()) return status;
  request.set_sweep_id(response->sweep_id());
  request.set_first_point(response->next_point());
  for (int k = 0; k < response->runs_size(); ++k) {
    const auto& values = response->points(k).values();
    pending->push_back({response->runs(k).id(), {values.begin(), values.end()}});
  }
  return status;
}

v1::StartSweepRequest SweepRequest(const SweepOptions& options) {
  v1::StartSweepRequest request;
  request.set_model(options.model);
  if (!options.spec_path.empty()) *request.mutable_base() = LoadRunSpecFile(options.spec_path);
  if (request.base().keep().empty()) request.mutable_base()->set_keep("summary");
  options.overrides.ApplyTo(*request.mutable_base());
  for (const std::string& axis : options.grid) *request.add_grid() = ParseGridAxis(axis);
  if (!options.list_path.empty()) ReadSweepList(options.list_path, &request);
  if (request.grid_size() == 0 && request.list_size() == 0) {
    throw InputError(
        "give what the sweep varies: --grid PATH=VALUES (one per axis) or --list "
        "FILE.csv");
  }
  return request;
}

// The sweep's progress as the server reports it (GetSweep), at most twice a second unless
// `now`; the line of the runs this command has fetched when the server cannot tell.
class SweepProgressDisplay {
 public:
  SweepProgressDisplay(v1::Simulation::Stub& stub, std::string sweep_id)
      : stub_(stub), sweep_id_(std::move(sweep_id)), terminal_(isatty(STDERR_FILENO)) {}
  ~SweepProgressDisplay() {
    if (terminal_ && shown_) std::cerr << "\n";
  }

  // Returns whether the server says the sweep was cancelled (when it was asked).
  bool Show(int ended, int total, bool now) {
    const auto clock = std::chrono::steady_clock::now();
    if (!now && shown_ && clock - last_ < std::chrono::milliseconds(500)) return false;
    last_ = clock;
    shown_ = true;
    v1::GetSweepRequest request;
    request.set_sweep_id(sweep_id_);
    v1::SweepProgress progress;
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
    const bool known = stub_.GetSweep(&context, request, &progress).ok();
    const std::string line = known ? SweepProgressLine(progress)
                                   : "sweep " + sweep_id_ + ": " + std::to_string(ended) + "/" +
                                         std::to_string(total) + " runs ended";
    std::cerr << (terminal_ ? "\r\033[K" : "") << line << (terminal_ ? "" : "\n") << std::flush;
    return known && progress.cancelled();
  }

 private:
  v1::Simulation::Stub& stub_;
  const std::string sweep_id_;
  const bool terminal_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point last_;
};

int Sweep(const ClientOptions& client, const SweepOptions& options) {
  v1::StartSweepRequest request = SweepRequest(options);
  const bool keeps_frames = request.base().keep() != "summary";
  const std::filesystem::path out(options.out_dir);
  std::error_code error;
  std::filesystem::create_directories(out, error);
  std::ofstream table(out / "sweep.csv");
  if (error || !table) throw InputError((out / "sweep.csv").string() + ": cannot be written");
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  std::deque<Pending> pending;
  v1::StartSweepResponse slice;
  if (grpc::Status s = StartSlice(*stub, request, options.window, &slice, &pending); !s.ok()) {
    return ReportRpcError("sweep", client, s);
  }
  const int total = slice.total_points();
  const std::string id = slice.sweep_id();
  const std::vector<std::string> paths(slice.paths().begin(), slice.paths().end());
  std::cerr << "sweep " << id << ": " << total << " runs (cancel: mbstream sweep --cancel " << id
            << ")\n";
  int ended = 0, finished = 0;
  bool cancelled = false;
  {
    SweepProgressDisplay display(*stub, id);
    while (!pending.empty()) {
      const Pending run = pending.front();
      pending.pop_front();
      v1::RunInfo info;
      const std::string directory = keeps_frames ? (out / "runs" / run.run_id).string() : "";
      if (grpc::Status s = DownloadResult(*stub, run.run_id, directory, &info, "", nullptr, true);
          !s.ok()) {
        return ReportRpcError("sweep", client, s);
      }
      if (ended == 0) {
        table << SweepTableHeader(paths, {info.joint_names().begin(), info.joint_names().end()})
              << "\n";
      }
      table << SweepTableRow(info, run.values) << "\n" << std::flush;
      ++ended;
      if (info.state() == v1::FINISHED) ++finished;
      // Refill half a window at a time: few calls, and the queue never holds more than a window.
      const int room = options.window - static_cast<int>(pending.size());
      if (!cancelled && request.first_point() < total && room >= std::max(1, options.window / 2)) {
        grpc::Status s = StartSlice(*stub, request, room, &slice, &pending);
        cancelled = s.error_code() == grpc::StatusCode::FAILED_PRECONDITION;  // CancelSweep
        if (!s.ok() && !cancelled) return ReportRpcError("sweep", client, s);
      }
      // Cancelled after its last slice started: the server's count says so at the end.
      if (display.Show(ended, total, pending.empty())) cancelled = true;
    }
  }
  std::cerr << "sweep " << id << (cancelled ? " was cancelled" : "") << ": " << finished << " of "
            << total << " runs finished"
            << (finished < total ? " (the others: see the state column)" : "") << "; table in "
            << (out / "sweep.csv").string() << "\n";
  return cancelled ? kExitRunFailed : kExitOk;
}

}  // namespace

int SweepCall(const ClientOptions& client, const std::string& id, bool cancel,
              const std::string& command) {
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  v1::SweepProgress progress;
  grpc::ClientContext context;
  grpc::Status status;
  if (cancel) {
    v1::CancelSweepRequest request;
    request.set_sweep_id(id);
    status = stub->CancelSweep(&context, request, &progress);
  } else {
    v1::GetSweepRequest request;
    request.set_sweep_id(id);
    status = stub->GetSweep(&context, request, &progress);
  }
  if (!status.ok()) return ReportRpcError(command, client, status);
  std::cout << SweepProgressLine(progress) << "\n";
  return kExitOk;
}

void AddSweepCommand(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* command = app.add_subcommand(
      "sweep", "run a parameter sweep on the server; writes DIR/sweep.csv, a row per run");
  command->add_option("model", options->model, "model id or name (to start a sweep)");
  command->add_option("--spec", options->spec_path, "base run spec (protobuf JSON of RunSpec)")
      ->check(CLI::ExistingFile);
  options->overrides.AddTo(*command);  // --keep among them: summary unless the spec says
  command->add_option("--grid", options->grid,
                      "an axis: PATH=START:STOP:COUNT[:log] or PATH=V1,V2,... (PATH: a spec "
                      "field, e.g. rtol or drives[joint=joint2].pd_servo.kp); repeat per axis");
  command
      ->add_option("--list", options->list_path,
                   "the points as CSV: a header of paths, a row of values per run")
      ->check(CLI::ExistingFile);
  command->add_option("--window", options->window, "most runs queued at once (default 32)")
      ->check(CLI::Range(1, 10000));
  command->add_option("--out", options->out_dir, "where sweep.csv (and runs/) are written");
  command->add_option("--status", options->status_id,
                      "print the progress of sweep ID (started before, by anyone) and exit");
  command->add_option("--cancel", options->cancel_id,
                      "cancel sweep ID: its queued and running runs, and the slices not started");
  command->callback([client, options, exit_code] {
    try {
      if (!options->cancel_id.empty() || !options->status_id.empty()) {
        const bool cancel = !options->cancel_id.empty();
        *exit_code =
            SweepCall(*client, cancel ? options->cancel_id : options->status_id, cancel, "sweep");
        return;
      }
      if (options->model.empty() || options->out_dir.empty()) {
        throw InputError(
            "give the MODEL and --out DIR to start a sweep (or --status / --cancel SWEEP_ID)");
      }
      *exit_code = Sweep(*client, *options);
    } catch (const InputError& error) {
      std::cerr << "mbstream sweep: " << error.what() << "\n";
      *exit_code = kExitBadRequest;
    }
  });
}

}  // namespace mbstream::cli
