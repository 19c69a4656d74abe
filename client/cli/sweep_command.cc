// `mbstream sweep MODEL [--spec FILE] [overrides] (--grid PATH=VALUES ... | --list FILE.csv)
//  [--keep summary|final|every:N|all] [--window N] --out DIR`: one sweep, stored whole and
// fed by the server (StartSweep); this command prints its id and follows it: its table in
// DIR/sweep.csv (sweep_table.h) and, when more than the summary is kept, each run's results in
// DIR/runs/RUN_ID/, its progress as the server reports it (GetSweep). Ctrl-C detaches: the
// sweep goes on. `mbstream sweep --wait SWEEP_ID --out DIR` follows a sweep started before
// (by any client) and writes its whole table; `--status SWEEP_ID` prints its progress,
// `--cancel SWEEP_ID` (or `mbstream cancel --sweep SWEEP_ID`) cancels it (CancelSweep: a
// command following it exits 1).
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>

#include "client/cli/exit_codes.h"
#include "client/cli/result_download.h"
#include "client/cli/run_overrides.h"
#include "client/cli/server_commands.h"
#include "client/cli/sweep_axes.h"
#include "client/cli/sweep_progress_line.h"
#include "client/cli/sweep_table.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

struct SweepOptions {
  std::string model, spec_path, out_dir, list_path;
  std::vector<std::string> grid;
  RunOverrides overrides;
  int window = 32;
  // --status, --cancel, --wait: of a sweep started before
  std::string status_id, cancel_id, wait_id;
};

// Runs asked of GetSweep at a time while following.
constexpr int kFollowPage = 64;

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
  request.set_window(options.window);
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
    request.set_max_runs(1);  // the counts only, whatever the sweep's size
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

// Ctrl-C while following: the sweep goes on on the server; say how to pick it up again.
char detach_message[512];
void DetachOnInterrupt(int) {
  const ssize_t written = write(STDERR_FILENO, detach_message, std::strlen(detach_message));
  (void)written;
  _exit(130);
}

class DetachOnCtrlC {
 public:
  DetachOnCtrlC(const std::string& id, const std::string& out) {
    const std::string message = "\nmbstream sweep: detached; sweep " + id +
                                " goes on on the server (follow it again: mbstream sweep "
                                "--wait " +
                                id + " --out " + out + "; cancel: mbstream sweep --cancel " + id +
                                ")\n";
    std::snprintf(detach_message, sizeof(detach_message), "%s", message.c_str());
    struct sigaction action {};
    action.sa_handler = DetachOnInterrupt;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_);
  }
  ~DetachOnCtrlC() { sigaction(SIGINT, &previous_, nullptr); }

 private:
  struct sigaction previous_ {};
};

grpc::Status GetSweepPage(v1::Simulation::Stub& stub, const std::string& id, int from,
                          v1::SweepProgress* page) {
  v1::GetSweepRequest request;
  request.set_sweep_id(id);
  request.set_runs_from(from);
  request.set_max_runs(kFollowPage);
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
  return stub.GetSweep(&context, request, page);
}

// Follows sweep `id` from its first point: each run's row in DIR/sweep.csv as it ends (its
// results in DIR/runs/RUN_ID/ when it keeps frames), until every point has ended or the sweep
// was cancelled. The server feeds the sweep: this only reads.
int Follow(const ClientOptions& client, v1::Simulation::Stub& stub, const std::string& id,
           const std::filesystem::path& out) {
  v1::SweepProgress page;
  if (grpc::Status s = GetSweepPage(stub, id, 0, &page); !s.ok()) {
    return ReportRpcError("sweep", client, s);
  }
  std::ofstream table(out / "sweep.csv");
  if (!table) throw InputError((out / "sweep.csv").string() + ": cannot be written");
  const std::vector<std::string> paths(page.paths().begin(), page.paths().end());
  int total = page.total_points(), next = 0, finished = 0;
  bool cancelled = false, fresh = true;
  std::optional<bool> keeps_frames;  // from the sweep's first run's spec
  {
    SweepProgressDisplay display(stub, id);
    for (;;) {
      if (!fresh) {
        if (grpc::Status s = GetSweepPage(stub, id, next, &page); !s.ok()) {
          return ReportRpcError("sweep", client, s);
        }
      }
      fresh = false;
      total = page.total_points();
      cancelled = cancelled || page.cancelled();
      if (page.run_ids_size() == 0) {
        if (cancelled || next >= total) break;
        // The next point is not queued yet (the server queues it once a place in the
        // sweep's window frees up): ask again in a moment.
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        continue;
      }
      for (int i = 0; i < page.run_ids_size(); ++i) {
        const std::string& run_id = page.run_ids(i);
        if (!keeps_frames) {
          v1::GetRunRequest request;
          request.set_run_id(run_id);
          v1::RunInfo first;
          grpc::ClientContext context;
          if (grpc::Status s = stub.GetRun(&context, request, &first); !s.ok()) {
            return ReportRpcError("sweep", client, s);
          }
          keeps_frames = first.spec().keep() != "summary";
        }
        v1::RunInfo info;
        const std::string directory = *keeps_frames ? (out / "runs" / run_id).string() : "";
        if (grpc::Status s = DownloadResult(stub, run_id, directory, &info, "", nullptr, true);
            !s.ok()) {
          return ReportRpcError("sweep", client, s);
        }
        if (next == 0) {
          table << SweepTableHeader(paths, {info.joint_names().begin(), info.joint_names().end()})
                << "\n";
        }
        const auto& values = page.points(i).values();
        table << SweepTableRow(info, {values.begin(), values.end()}) << "\n" << std::flush;
        ++next;
        if (info.state() == v1::FINISHED) ++finished;
        if (display.Show(next, total, false)) cancelled = true;
      }
      if (next >= total) break;
    }
    display.Show(next, total, true);
  }
  std::cerr << "sweep " << id << (cancelled ? " was cancelled" : "") << ": " << finished << " of "
            << total << " runs finished"
            << (finished < total ? " (the others: see the state column)" : "") << "; table in "
            << (out / "sweep.csv").string() << "\n";
  return cancelled ? kExitRunFailed : kExitOk;
}

std::filesystem::path OutDirectory(const std::string& dir) {
  const std::filesystem::path out(dir);
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) throw InputError(out.string() + ": cannot be created (" + error.message() + ")");
  return out;
}

int Sweep(const ClientOptions& client, const SweepOptions& options) {
  v1::StartSweepRequest request = SweepRequest(options);
  const std::filesystem::path out = OutDirectory(options.out_dir);
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    if (grpc::Status s = stub->StartSweep(&context, request, &started); !s.ok()) {
      return ReportRpcError("sweep", client, s);
    }
  }
  const std::string& id = started.sweep_id();
  std::cerr << "sweep " << id << ": " << started.total_points()
            << " runs, fed by the server (Ctrl-C detaches; follow again: mbstream sweep --wait "
            << id << " --out " << options.out_dir << "; cancel: mbstream sweep --cancel " << id
            << ")\n";
  std::cout << id << "\n" << std::flush;
  DetachOnCtrlC detach(id, options.out_dir);
  return Follow(client, *stub, id, out);
}

int Wait(const ClientOptions& client, const std::string& id, const std::string& out_dir) {
  const std::filesystem::path out = OutDirectory(out_dir);
  std::unique_ptr<v1::Simulation::Stub> stub = ConnectSimulation(client);
  DetachOnCtrlC detach(id, out_dir);
  return Follow(client, *stub, id, out);
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
  command
      ->add_option("--window", options->window,
                   "most runs of the sweep queued or running at once on the server "
                   "(default 32)")
      ->check(CLI::Range(1, 10000));
  command->add_option("--out", options->out_dir, "where sweep.csv (and runs/) are written");
  command->add_option("--status", options->status_id,
                      "print the progress of sweep ID (started before, by anyone) and exit");
  command->add_option("--cancel", options->cancel_id,
                      "cancel sweep ID: its queued and running runs, and the points not queued");
  command->add_option("--wait", options->wait_id,
                      "follow sweep ID (started before, by anyone) until it ends; with --out, "
                      "its whole table");
  command->callback([client, options, exit_code] {
    try {
      if (!options->cancel_id.empty() || !options->status_id.empty()) {
        const bool cancel = !options->cancel_id.empty();
        *exit_code =
            SweepCall(*client, cancel ? options->cancel_id : options->status_id, cancel, "sweep");
        return;
      }
      if (!options->wait_id.empty()) {
        if (options->out_dir.empty()) {
          throw InputError("give --out DIR: where sweep " + options->wait_id +
                           "'s table (sweep.csv) is written");
        }
        *exit_code = Wait(*client, options->wait_id, options->out_dir);
        return;
      }
      if (options->model.empty() || options->out_dir.empty()) {
        throw InputError(
            "give the MODEL and --out DIR to start a sweep (or --status / --cancel / --wait "
            "SWEEP_ID)");
      }
      *exit_code = Sweep(*client, *options);
    } catch (const InputError& error) {
      std::cerr << "mbstream sweep: " << error.what() << "\n";
      *exit_code = kExitBadRequest;
    }
  });
}

}  // namespace mbstream::cli
