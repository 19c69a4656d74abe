// Many runs at once: a sweep through a real mbstream-server process against the same runs
// in-process (docs/performance.md, "Many runs at once").
//
//   sweep_bench --server build/server/app/mbstream-server [--runs 1000] [--scene seed-servo]
//               [--duration 0] [--window 32]
//
// In-process: `--runs` Simulate calls of the scene (what `mbstream simulate` runs) on 2
// threads, the model imported once. Server: a fresh mbstream-server (2 workers, a fresh data
// directory) and one client that keeps up to `--window` runs submitted (StartRun), waits for
// the oldest to end (WatchRun) and fetches its result (GetResult, every frame), then submits
// the next (`--watch`: waits with WatchRun first, as a client did before GetResult's `wait`;
// `--batch N`: StartRuns of N runs at a time and GetResults of each batch, two calls per batch).
// Prints wall time, runs per second and CPU time per run of each side (the server
// process's from /proc, the client's and the in-process threads' from getrusage), and the
// server's overhead. `--duration D` (s) shortens the scene: the 10,000 short kinematic runs
// are `--runs 10000 --scene seed-run --duration 1`. `--rounds N` alternates the two sides N
// times (a fresh server each round) and prints the median of each round's ratios, so that a
// machine whose load changes affects both sides alike; `--baseline-server B` adds a third
// side to each round, the same sweep through binary B (e.g. the previous build), for a
// before/after comparison in one invocation. `--files`: both sides end each run as a user's
// command would, with its results directory (the CSV files and stats.json, then removed):
// in-process as `mbstream simulate --out` writes it, the client as `mbstream results --out`
// writes a fetched result; without it the in-process side keeps the frames in memory only.
// `--sweep`: the client is one sweep (StartSweep, then GetSweep pages and GetResults of each), as
// `mbstream sweep` runs it; `--keep summary|all` (both sides): the sweep baselines of issue 33,
//   sweep_bench --server S --sweep --keep all --files     vs `mbstream simulate --out`
//   sweep_bench --server S --sweep --keep summary         vs the engine alone (Simulate)
#include <grpcpp/grpcpp.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/engine/engine.h"
#include "server/parse/urdf_import.h"
#include "server/results/results_files.h"
#include "server/spec/run_spec_json.h"
#include "server/wire/frame_conversion.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// CPU time (user + system, s) of this process's threads so far.
double OwnCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

// CPU time (user + system, s) of process `pid`, from /proc/PID/stat.
double ProcessCpuSeconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  long ticks = 0;
  for (int i = 3; i <= 15; ++i) {  // fields 14 (utime) and 15 (stime), 1-based
    fields >> field;
    if (i >= 14) ticks += std::stol(field);
  }
  return static_cast<double>(ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

struct Measured {
  double wall_s = 0.0;
  double cpu_s = 0.0;         // in-process threads, or the server process
  double client_cpu_s = 0.0;  // the client (server case)
  long frames = 0;
};

// Writes a results directory (the CSV files and stats.json) and removes it again.
void WriteAndRemove(const RunResult& result, const RunProvenance& provenance,
                    const std::string& directory) {
  WriteResultsDirectory(result, provenance, directory);
  fs::remove_all(directory);
}

// With --files, the client writes each result it fetches as `mbstream results RUN --out DIR`
// does (cli/result_download.cc): the frames of one result, from the chunk with its info to
// the next such chunk, become a RunResult and its results directory.
class ResultFiles {
 public:
  explicit ResultFiles(std::string directory) : directory_(std::move(directory)) {}

  void Add(v1::ResultChunk& chunk) {
    if (directory_.empty()) return;
    if (chunk.has_info()) {
      Flush();
      info_ = chunk.info();
      started_ = true;
    }
    for (v1::Frame& frame : *chunk.mutable_frames()) frames_.push_back(std::move(frame));
  }

  // Writes the last result's directory (call after the stream's last chunk).
  void Flush();

 private:
  std::string directory_;
  v1::RunInfo info_;
  std::vector<v1::Frame> frames_;
  bool started_ = false;
};

void ResultFiles::Flush() {
  if (!started_) return;
  const RunResult result = ResultFromFrames(info_, frames_);
  const std::string spec_json =
      RunSpecToJson(ToRunSpec(ToRunConfig(info_.spec(), result.joint_names, "spec")));
  WriteAndRemove(result,
                 RunProvenance{info_.model_name(), "model " + info_.model_id(), spec_json,
                               info_.model_id(), info_.id()},
                 directory_ + "/" + info_.id());
  frames_.clear();
  started_ = false;
}

// `files` (empty: none): each run also writes its results directory under it, as `mbstream
// simulate --out` does (the CSV files and stats.json), then the directory is removed.
Measured InProcess(const Model& model, const RunConfig& config, int runs,
                   const std::string& files) {
  Measured m;
  std::atomic<int> next{0};
  std::atomic<long> frames{0};
  const double cpu0 = OwnCpuSeconds();
  const Clock::time_point start = Clock::now();
  std::vector<std::thread> threads;
  for (int t = 0; t < 2; ++t) {
    threads.emplace_back([&] {
      for (int run; (run = next.fetch_add(1)) < runs;) {
        const RunResult result = Simulate(model, config);
        if (result.stats.status != RunStatus::kFinished) throw std::runtime_error("run failed");
        frames += static_cast<long>(result.t.size());
        if (!files.empty()) {  // as `mbstream simulate MODEL --spec F --out DIR` ends
          const RunProvenance provenance{model.name, "irb1600.urdf",
                                         RunSpecToJson(ToRunSpec(config)), "", ""};
          WriteAndRemove(result, provenance, files + "/run-" + std::to_string(run));
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  m.wall_s = Seconds(start);
  if (!files.empty()) fs::remove_all(files);
  m.cpu_s = OwnCpuSeconds() - cpu0;
  m.frames = frames;
  return m;
}

void Check(const grpc::Status& status, const char* what) {
  if (!status.ok()) throw std::runtime_error(std::string(what) + ": " + status.error_message());
}

// GetResults (waiting) of the runs `ids`, each written under `files` when given.
void FetchBatch(v1::Simulation::Stub& stub, const std::vector<std::string>& ids,
                const std::string& files, Measured& m) {
  grpc::ClientContext context;
  v1::GetResultsRequest request;
  for (const std::string& id : ids) request.add_run_ids(id);
  request.set_wait(true);
  auto reader = stub.GetResults(&context, request);
  v1::ResultChunk chunk;
  ResultFiles results(files);
  while (reader->Read(&chunk)) {
    if (chunk.has_info() && chunk.info().state() != v1::FINISHED) {
      throw std::runtime_error("run " + chunk.info().id() + " did not finish");
    }
    m.frames += chunk.frames_size();
    results.Add(chunk);
  }
  Check(reader->Finish(), "GetResults");
  results.Flush();
}

// The sweep in batches: StartRuns of `batch` runs while at most `window` are in flight, then
// GetResults (waiting) of the oldest batch: two calls per batch.
void BatchedSweep(v1::Simulation::Stub& stub, const v1::RunSpec& spec, int runs, int window,
                  int batch, const std::string& files, Measured& m) {
  std::deque<std::vector<std::string>> in_flight;
  int submitted = 0, flying = 0;
  while (submitted < runs || !in_flight.empty()) {
    while (submitted < runs && flying + std::min(batch, runs - submitted) <= window) {
      grpc::ClientContext context;
      v1::StartRunsRequest request;
      request.set_model("irb1600");
      const int n = std::min(batch, runs - submitted);
      for (int i = 0; i < n; ++i) *request.add_specs() = spec;
      v1::StartRunsResponse response;
      Check(stub.StartRuns(&context, request, &response), "StartRuns");
      std::vector<std::string>& ids = in_flight.emplace_back();
      for (const v1::RunInfo& info : response.runs()) ids.push_back(info.id());
      submitted += n;
      flying += n;
    }
    flying -= static_cast<int>(in_flight.front().size());
    FetchBatch(stub, in_flight.front(), files, m);
    in_flight.pop_front();
  }
}

// The sweep as one job (`mbstream sweep`'s calls, client/cli/sweep_command.cc): one
// StartSweep of `runs` points (a list of the same duration: the same runs as the other sides)
// that the server feeds, at most `window` queued or running at once, followed a page of half
// a window at a time (GetSweep from the next point) with GetResults (waiting) of each page.
// The spec's `keep` says what the runs keep and send (every frame, or the summary only).
void OneJobSweep(v1::Simulation::Stub& stub, const v1::RunSpec& spec, int runs, int window,
                 const std::string& files, Measured& m) {
  v1::StartSweepRequest start;
  start.set_model("irb1600");
  *start.mutable_base() = spec;
  start.add_list_paths("duration_s");
  const std::string duration = std::to_string(spec.duration_s());
  for (int i = 0; i < runs; ++i) start.add_list()->add_values(duration);
  start.set_window(window);
  v1::StartSweepResponse response;
  {
    grpc::ClientContext context;
    Check(stub.StartSweep(&context, start, &response), "StartSweep");
  }
  const int page = std::max(1, window / 2);
  for (int next = 0; next < runs;) {
    grpc::ClientContext context;
    v1::GetSweepRequest request;
    request.set_sweep_id(response.sweep_id());
    request.set_runs_from(next);
    request.set_max_runs(page);
    v1::SweepProgress progress;
    Check(stub.GetSweep(&context, request, &progress), "GetSweep");
    if (progress.run_ids_size() == 0) {  // not queued yet
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    FetchBatch(stub, {progress.run_ids().begin(), progress.run_ids().end()}, files, m);
    next += progress.run_ids_size();
  }
}

// The sweep a call per run: StartRun while fewer than `window` runs are in flight, then
// GetResult (waiting, or after WatchRun with `watch`) of the oldest.
void PerRunSweep(v1::Simulation::Stub& stub, const v1::RunSpec& spec, int runs, int window,
                 bool watch, const std::string& files, Measured& m) {
  std::deque<std::string> in_flight;
  int submitted = 0;
  while (submitted < runs || !in_flight.empty()) {
    while (submitted < runs && static_cast<int>(in_flight.size()) < window) {
      grpc::ClientContext context;
      v1::StartRunRequest request;
      request.set_model("irb1600");
      *request.mutable_spec() = spec;
      v1::RunInfo info;
      Check(stub.StartRun(&context, request, &info), "StartRun");
      in_flight.push_back(info.id());
      ++submitted;
    }
    const std::string id = in_flight.front();
    in_flight.pop_front();
    if (watch) {  // wait for its end
      grpc::ClientContext context;
      v1::WatchRunRequest request;
      request.set_run_id(id);
      request.set_progress_interval_s(10.0);
      auto reader = stub.WatchRun(&context, request);
      v1::WatchEvent event;
      v1::RunState state = v1::RUN_STATE_UNSPECIFIED;
      while (reader->Read(&event)) {
        if (event.has_progress()) state = event.progress().state();
      }
      Check(reader->Finish(), "WatchRun");
      if (state != v1::FINISHED) throw std::runtime_error("run " + id + " did not finish");
    }
    {  // fetch every frame (waiting for the run's end, unless watched)
      grpc::ClientContext context;
      v1::GetResultRequest request;
      request.set_run_id(id);
      request.set_wait(!watch);
      auto reader = stub.GetResult(&context, request);
      v1::ResultChunk chunk;
      ResultFiles results(files);
      while (reader->Read(&chunk)) {
        m.frames += chunk.frames_size();
        results.Add(chunk);
      }
      Check(reader->Finish(), "GetResult");
      results.Flush();
    }
  }
}

struct ClientPattern {
  int window = 32;
  int batch = 0;
  bool watch = false;
  bool sweep = false;  // one StartSweep, followed (OneJobSweep)
  std::string files;   // with --files: where the client writes each result
};

Measured ThroughServer(const std::string& server_binary, const v1::RunSpec& spec, int runs,
                       const ClientPattern& client) {
  const fs::path data = fs::temp_directory_path() / ("mbstream-sweep-" + std::to_string(getpid()));
  fs::remove_all(data);
  testing::ServerProcess server(
      server_binary, data.string(),
      {"--models", MBSTREAM_SOURCE_DIR "/models", "--workers", "2", "--log-level", "warn"});
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(256 << 20);
  auto stub = v1::Simulation::NewStub(
      grpc::CreateCustomChannel(server.address(), grpc::InsecureChannelCredentials(), arguments));
  // One short run first, unmeasured: the server compiles a model at its first use (the
  // in-process side imports it before its clock starts too).
  {
    grpc::ClientContext context;
    v1::StartRunsRequest request;
    request.set_model("irb1600");
    v1::RunSpec& warm = *request.add_specs() = spec;
    warm.set_duration_s(std::min(spec.duration_s(), 0.1));
    v1::StartRunsResponse response;
    Check(stub->StartRuns(&context, request, &response), "StartRuns (warm-up)");
    grpc::ClientContext fetch;
    v1::GetResultsRequest results;
    results.add_run_ids(response.runs(0).id());
    results.set_wait(true);
    auto reader = stub->GetResults(&fetch, results);
    for (v1::ResultChunk chunk; reader->Read(&chunk);) {
    }
    Check(reader->Finish(), "GetResults (warm-up)");
  }
  Measured m;
  const double server_cpu0 = ProcessCpuSeconds(server.pid());
  const double client_cpu0 = OwnCpuSeconds();
  const Clock::time_point start = Clock::now();
  if (client.sweep) {
    OneJobSweep(*stub, spec, runs, client.window, client.files, m);
  } else if (client.batch > 0) {
    BatchedSweep(*stub, spec, runs, client.window, client.batch, client.files, m);
  } else {
    PerRunSweep(*stub, spec, runs, client.window, client.watch, client.files, m);
  }
  m.wall_s = Seconds(start);
  m.cpu_s = ProcessCpuSeconds(server.pid()) - server_cpu0;
  m.client_cpu_s = OwnCpuSeconds() - client_cpu0;
  server.Stop();
  fs::remove_all(data);
  return m;
}

double Median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// Per round: a server side against the round's in-process side.
struct Ratios {
  std::vector<double> wall, server_cpu, total_cpu;
  void Add(const Measured& local, const Measured& served) {
    wall.push_back(served.wall_s / local.wall_s);
    server_cpu.push_back(served.cpu_s / local.cpu_s);
    total_cpu.push_back((served.cpu_s + served.client_cpu_s) / local.cpu_s);
  }
  void Print(const char* what) const {
    std::printf(
        "%-10s median of %zu rounds: wall time %.3fx in-process (runs/s %.3fx); CPU per run: "
        "server %.3fx, server + client %.3fx in-process\n",
        what, wall.size(), Median(wall), 1.0 / Median(wall), Median(server_cpu), Median(total_cpu));
  }
};

void Print(const char* what, const Measured& m, int runs) {
  std::printf("%-10s %8.3f s wall  %8.1f runs/s  CPU per run %8.1f us", what, m.wall_s,
              runs / m.wall_s, 1e6 * m.cpu_s / runs);
  if (m.client_cpu_s > 0) std::printf(" + client %6.1f us", 1e6 * m.client_cpu_s / runs);
  std::printf("  frames %ld\n", m.frames);
  std::fflush(stdout);
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  using namespace mbstream;
  CLI::App app{"A sweep through a real mbstream-server against the same runs in-process"};
  std::string server_binary, baseline_binary, scene = "seed-servo";
  int runs = 1000, window = 32, rounds = 1, batch = 0, baseline_batch = -1;
  double duration = 0.0;
  bool server_only = false, watch = false, simulate_files = false, sweep = false;
  std::string keep;
  app.add_option("--server", server_binary, "the mbstream-server binary")->required();
  app.add_option("--runs", runs, "runs on each side");
  app.add_option("--scene", scene, "models/irb1600/SCENE.json");
  app.add_option("--duration", duration, "s; 0 = the scene's");
  app.add_option("--window", window, "runs submitted and not yet fetched (at most 64 queue)");
  app.add_option("--batch", batch,
                 "runs per StartRuns and GetResults call (two calls per batch, --window runs in "
                 "flight); 0 = StartRun and GetResult for each run");
  app.add_option("--baseline-batch", baseline_batch,
                 "--batch for the baseline server (default: the same; 0 for a binary without "
                 "StartRuns, or to compare the two patterns on one binary)");
  app.add_flag("--sweep", sweep,
               "the server side is one sweep (one StartSweep of --window, then GetSweep pages of "
               "half a window and GetResults of each), as `mbstream sweep` runs it");
  app.add_option("--keep", keep,
                 "RunSpec.keep of every run on both sides (all, summary, final, every:N; "
                 "default the scene's: all)");
  app.add_flag("--server-only", server_only, "skip the in-process side (for profiling)");
  app.add_flag("--files", simulate_files,
               "both sides write each run's results directory (CSV files and stats.json) and "
               "remove it: in-process as `mbstream simulate --out`, the client as `mbstream "
               "results --out` after fetching");
  app.add_flag("--watch", watch,
               "wait for each run's end with WatchRun before GetResult (three calls per run, "
               "as before GetResult could wait)");
  app.add_option("--rounds", rounds, "alternate the sides this many times; medians of ratios")
      ->check(CLI::PositiveNumber);
  app.add_option("--baseline-server", baseline_binary,
                 "also measure this mbstream-server binary in each round (before/after)");
  CLI11_PARSE(app, argc, argv);
  try {
    const std::string path = MBSTREAM_SOURCE_DIR "/models/irb1600/" + scene + ".json";
    v1::RunSpec spec = LoadRunSpecFile(path);
    if (duration > 0) spec.set_duration_s(duration);
    if (!keep.empty()) spec.set_keep(keep);
    const Model model = ImportUrdfFile(MBSTREAM_SOURCE_DIR "/models/irb1600/irb1600.urdf").model;
    std::vector<std::string> joints;
    for (const Body& body : model.bodies) joints.push_back(body.joint.name);
    const RunConfig config = ToRunConfig(spec, joints, path);
    std::printf("%d runs of %s (%.3g s simulated), 2 threads / 2 workers, load %s\n", runs,
                scene.c_str(), spec.duration_s(), [] {
                  static char text[64] = "?";
                  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
                    if (std::fgets(text, sizeof text, f) == nullptr) text[0] = 0;
                    std::fclose(f);
                  }
                  return text;
                }());
    // Beside the server's data directory (ThroughServer), on the same file system.
    const std::string files =
        simulate_files
            ? (fs::temp_directory_path() / ("mbstream-simulate-" + std::to_string(getpid())))
                  .string()
            : "";
    const ClientPattern client{window, batch, watch, sweep, files.empty() ? "" : files + "-client"};
    Ratios ratios, baseline_ratios;
    for (int round = 0; round < rounds; ++round) {
      if (rounds > 1) std::printf("round %d\n", round + 1);
      Measured local;
      if (!server_only) {
        local = InProcess(model, config, runs, files);
        Print("in-process", local, runs);
      }
      auto baseline = [&] {
        if (baseline_binary.empty()) return;
        ClientPattern pattern = client;
        if (baseline_batch >= 0) pattern.batch = baseline_batch;
        const Measured before = ThroughServer(baseline_binary, spec, runs, pattern);
        Print("baseline", before, runs);
        if (!server_only) baseline_ratios.Add(local, before);
      };
      if (round % 2 == 0) baseline();  // the two servers take turns to go first
      const Measured served = ThroughServer(server_binary, spec, runs, client);
      Print("server", served, runs);
      if (round % 2 == 1) baseline();
      if (!server_only) {
        ratios.Add(local, served);
        std::printf(
            "server overhead: %+.1f %% wall time; %+.1f us CPU per run (server + client - "
            "in-process)\n",
            100.0 * (served.wall_s / local.wall_s - 1.0),
            1e6 * (served.cpu_s + served.client_cpu_s - local.cpu_s) / runs);
      }
      std::fflush(stdout);
    }
    if (!server_only && !baseline_binary.empty()) baseline_ratios.Print("baseline");
    if (!server_only) ratios.Print("server");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweep_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
