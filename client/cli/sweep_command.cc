// `mbstream sweep MODEL [--spec FILE] [overrides] (--grid PATH=VALUES ... | --list FILE.csv)
//  [--keep summary|final|every:N|all] [--window N] --out DIR`: one sweep on the server,
// its table in DIR/sweep.csv (sweep_table.h) and, when more than the summary is kept, each
// run's results in DIR/runs/RUN_ID/.
#include <unistd.h>

#include <deque>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "client/cli/exit_codes.h"
#include "client/cli/result_download.h"
#include "client/cli/run_overrides.h"
#include "client/cli/server_commands.h"
#include "client/cli/sweep_axes.h"
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
  const std::vector<std::string> paths(slice.paths().begin(), slice.paths().end());
  std::cerr << "sweep " << slice.sweep_id() << ": " << total << " runs\n";
  const bool terminal = isatty(STDERR_FILENO);
  int ended = 0, finished = 0;
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
    std::cerr << (terminal ? "\r\033[K" : "") << "sweep " << slice.sweep_id() << ": " << ended
              << "/" << total << " runs ended, " << finished << " finished"
              << (terminal ? "" : "\n") << std::flush;
    // Refill half a window at a time: few calls, and the queue never holds more than a window.
    const int room = options.window - static_cast<int>(pending.size());
    if (request.first_point() < total && room >= std::max(1, options.window / 2)) {
      if (grpc::Status s = StartSlice(*stub, request, room, &slice, &pending); !s.ok()) {
        return ReportRpcError("sweep", client, s);
      }
    }
  }
  if (terminal) std::cerr << "\n";
  std::cerr << "sweep " << slice.sweep_id() << ": " << finished << " of " << total
            << " runs finished" << (finished < total ? " (the others: see the state column)" : "")
            << "; table in " << (out / "sweep.csv").string() << "\n";
  return kExitOk;
}

}  // namespace

void AddSweepCommand(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto options = std::make_shared<SweepOptions>();
  CLI::App* command = app.add_subcommand(
      "sweep", "run a parameter sweep on the server; writes DIR/sweep.csv, a row per run");
  command->add_option("model", options->model, "model id or name")->required();
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
  command->add_option("--out", options->out_dir, "where sweep.csv (and runs/) are written")
      ->required();
  command->callback([client, options, exit_code] {
    try {
      *exit_code = Sweep(*client, *options);
    } catch (const InputError& error) {
      std::cerr << "mbstream sweep: " << error.what() << "\n";
      *exit_code = kExitBadRequest;
    }
  });
}

}  // namespace mbstream::cli
