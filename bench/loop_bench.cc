// The Delta robot (models/linkages/delta.sdf: 18 tree joints, five ball joints cut, 15
// constraint equations) against its own spanning tree without the loops, run for run:
//
//   build/bench/loop_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
//
// BM_DeltaLoop/driven: SimulateLoops with models/linkages/delta-driven.json (the motors
//   prescribed, kinematic: Newton on the loops at each of 201 frames over 2 s, inverse
//   dynamics and multipliers for the motor torques).
// BM_DeltaTree/driven: SimulateTree of the same 18-joint tree with no loops, every joint
//   prescribed along the loop run's own motion (natural cubic splines through its frames):
//   the same motion and torques asked for, closed form (forward kinematics, RNEA).
// BM_DeltaLoop/passive: SimulateLoops with delta-passive.json (released at rest; joint space,
//   Baumgarte and CVODE BDF with projection, rtol 1e-9, 0.15 s).
// BM_DeltaTree/passive: SimulateTree of the tree with no loops released at rest, the same spec
//   (joint space, CVODE BDF, rtol 1e-9): an 18-joint chain that falls apart freely.
// Counters: ms_per_sim_s (CPU ms of the benchmark's thread for one run, per simulated
// second: the machine is shared, its wall time is not the run's), steps (internal steps).
#include <benchmark/benchmark.h>

#include <time.h>

#include <string>
#include <vector>

#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"
#include "server/sim/simulate.h"
#include "server/spec/run_spec_json.h"

namespace mbstream {
namespace {

const std::string kDir = MBSTREAM_SOURCE_DIR "/models/linkages/";

const SdfImport& Delta() {
  static const SdfImport delta = ImportSdfFile(kDir + "delta.sdf");
  return delta;
}

RunConfig DeltaConfig(const std::string& spec) {
  std::vector<std::string> joints;
  for (const Body& body : Delta().model.bodies) joints.push_back(body.joint.name);
  const std::string path = kDir + spec;
  return ToRunConfig(LoadRunSpecFile(path), joints, path);
}

// Every tree joint prescribed along the driven loop run's motion.
RunConfig TreeAlongLoopRun() {
  const RunConfig loop_config = DeltaConfig("delta-driven.json");
  const RunResult loop = SimulateLoops(Delta().model, Delta().loops, loop_config);
  const int n = Delta().model.num_dofs();
  const int columns = loop.num_dofs;  // the tree's joints first, then the cut joints'
  RunConfig config = loop_config;
  for (int j = 0; j < n; ++j) {
    DriveConfig& drive = config.drives[j];
    drive.kind = DriveConfig::Kind::kPrescribed;
    drive.trajectory = Trajectory{};
    drive.trajectory.kind = Trajectory::Kind::kSpline;
    for (int f = 0; f < loop.num_frames(); ++f) {
      drive.trajectory.times.push_back(loop.t[f]);
      drive.trajectory.values.push_back(loop.q[static_cast<size_t>(f) * columns + j]);
    }
  }
  return config;
}

double ThreadCpuMs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

template <typename Run>
void TimeRuns(benchmark::State& state, double duration_s, Run run) {
  RunStats stats;
  double cpu_ms = 0.0;
  for (auto _ : state) {
    const double start = ThreadCpuMs();
    RunResult result = run();
    cpu_ms += ThreadCpuMs() - start;
    benchmark::DoNotOptimize(result.q.data());
    stats = result.stats;
  }
  if (stats.status != RunStatus::kFinished) {
    state.SkipWithError((std::string(RunStatusName(stats.status)) + ": " + stats.message).c_str());
    return;
  }
  state.counters["ms_per_sim_s"] = cpu_ms / static_cast<double>(state.iterations()) / duration_s;
  state.counters["steps"] = static_cast<double>(stats.solver.steps);
}

void BM_DeltaLoop(benchmark::State& state, const char* spec) {
  const RunConfig config = DeltaConfig(spec);
  TimeRuns(state, config.duration,
           [&] { return SimulateLoops(Delta().model, Delta().loops, config); });
}

void BM_DeltaTreeDriven(benchmark::State& state) {
  const RunConfig config = TreeAlongLoopRun();
  TimeRuns(state, config.duration, [&] { return SimulateTree(Delta().model, config); });
}

void BM_DeltaTreePassive(benchmark::State& state) {
  const RunConfig config = DeltaConfig("delta-passive.json");
  TimeRuns(state, config.duration, [&] { return SimulateTree(Delta().model, config); });
}

BENCHMARK_CAPTURE(BM_DeltaLoop, driven, "delta-driven.json")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeltaTreeDriven)->Name("BM_DeltaTree/driven")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_DeltaLoop, passive, "delta-passive.json")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DeltaTreePassive)->Name("BM_DeltaTree/passive")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace mbstream

BENCHMARK_MAIN();
