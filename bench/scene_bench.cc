// Whole-scene timings on the IRB 1600 reference scenes (models/irb1600/*.json):
//
//   build/bench/scene_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only
//
// BM_Scene/<scene>/<formulation>/<method>: one Simulate of the scene per iteration, the
// spec as shipped except for the formulation and method in the name ("auto" and "none"
// keep the spec's choice; kinematic runs report drive torques by inverse dynamics at each
// of the 401 outputs). Counters: the run's internal steps and its own CPU time (RunStats).
// BM_ResultsDirectory/seed-servo: the results directory of a seed-servo run (401 frames, every
// CSV and stats.json), as `mbstream simulate --out` writes it after the run.
// BM_RhsEval/seed-servo: one evaluation of the joint-space ODE's right-hand side;
// BM_ResidualEval/seed-run/body-index2 and BM_RhsEval/seed-servo/body-baumgarte: one
// evaluation of the body formulations' DAE residual and ODE right-hand side.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "server/body/body_baumgarte_ode.h"
#include "server/body/body_dae.h"
#include "server/body/consistent_init.h"
#include "server/drives/drive_set.h"
#include "server/engine/engine.h"
#include "server/parse/urdf_import.h"
#include "server/results/results_files.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/run_config.h"
#include "server/spec/run_spec_json.h"

namespace mbstream {
namespace {

const Model& Irb1600() {
  static const Model model =
      ImportUrdfFile(MBSTREAM_SOURCE_DIR "/models/irb1600/irb1600.urdf").model;
  return model;
}

RunConfig LoadScene(const std::string& scene) {
  std::vector<std::string> joints;
  for (const Body& body : Irb1600().bodies) joints.push_back(body.joint.name);
  const std::string path = MBSTREAM_SOURCE_DIR "/models/irb1600/" + scene + ".json";
  return ToRunConfig(LoadRunSpecFile(path), joints, path);
}

void BM_Scene(benchmark::State& state, const RunConfig& config) {
  const Model& model = Irb1600();
  RunStats stats;
  for (auto _ : state) {
    RunResult result = Simulate(model, config);
    benchmark::DoNotOptimize(result.tcp.data());
    stats = result.stats;
  }
  if (stats.status != RunStatus::kFinished) {
    state.SkipWithError((std::string(RunStatusName(stats.status)) + ": " + stats.message).c_str());
    return;
  }
  state.counters["steps"] = static_cast<double>(stats.solver.steps);
  state.counters["cpu_ms"] = stats.cpu_s * 1e3;
}

void BM_RhsEval(benchmark::State& state, const RunConfig& config) {
  Model model = Irb1600();
  model.gravity = config.gravity;
  const DriveSet drives(model, config.drives);
  JointSpaceOde ode(model, drives);
  const int size = ode.size();
  std::vector<double> y(size, 0.0), ydot(size, 0.0);
  for (int i = 0; i < model.num_dofs(); ++i) {
    y[i] = 0.1 * (i + 1);
    y[model.num_dofs() + i] = 0.3 - 0.05 * i;
  }
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(ode.Rhs(t, y.data(), ydot.data()));
    benchmark::ClobberMemory();
    t += 1e-3;
  }
}

struct SceneCase {
  const char* scene;
  const char* formulation;  // "auto", "kinematic", "joint", "body-index2", ...
  const char* method;       // "none" = the spec's (and unused by kinematic)
};

constexpr SceneCase kCases[] = {
    {"seed-run", "auto", "bdf"},
    {"seed-run", "kinematic", "none"},
    {"seed-run", "joint", "bdf"},
    {"seed-servo", "joint", "bdf"},
    {"seed-servo", "joint", "erk"},
    {"passive-swing", "joint", "bdf"},
    {"stiff-servo", "joint", "bdf"},
    {"stiff-servo", "joint", "erk"},
    // Body coordinates (the seed's kind of model): the DAE with IDA, the Baumgarte ODE.
    {"seed-run", "body-index2", "ida"},
    {"seed-servo", "body-baumgarte", "bdf"},
};

// One evaluation of the body-index2 DAE residual (seed-run) or of the body-baumgarte
// right-hand side (seed-servo), at the consistent initial state.
void BM_BodyEval(benchmark::State& state, const RunConfig& config, bool dae) {
  Model model = Irb1600();
  model.gravity = config.gravity;
  const DriveSet drives(model, config.drives);
  Eigen::VectorXd q0(6), qd0(6);
  for (int i = 0; i < 6; ++i) {
    q0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).q : 0.1 * (i + 1);
    qd0(i) = drives.prescribed(i) ? drives.Reference(i, 0.0).qd : 0.3 - 0.05 * i;
  }
  const BodyModel bm = MakeBodyModel(model, drives, q0);
  BodyDae body_dae(bm, drives, ConstraintLevel::kVelocity);
  BodyBaumgarteOde ode(bm, drives, config.baumgarte);
  BodyInitialState init;
  ConsistentInitialState(model, bm, body_dae.mechanics(), 0.0, q0, qd0, &init);
  std::vector<double> out(bm.dae_size(), 0.0);
  double t = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(dae ? body_dae.Residual(t, init.y.data(), init.yp.data(), out.data())
                                 : ode.Rhs(t, init.y.data(), out.data()));
    benchmark::ClobberMemory();
    t += 1e-3;
  }
}

// What `mbstream simulate --out` and `mbstream results --out` do after the run: the results
// directory of the scene's result (every CSV and stats.json), written and removed again.
void BM_ResultsDirectory(benchmark::State& state, RunConfig config) {
  config.want_torques = true;
  const RunResult result = Simulate(Irb1600(), config);
  const RunProvenance provenance{Irb1600().name, "irb1600.urdf", RunSpecToJson(ToRunSpec(config)),
                                 "", ""};
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("mbstream-scene-bench-" + std::to_string(getpid()));
  for (auto _ : state) {
    WriteResultsDirectory(result, provenance, directory.string());
    std::filesystem::remove_all(directory);
  }
  state.counters["frames"] = result.num_frames();
}

void RegisterAll() {
  for (const SceneCase& c : kCases) {
    RunConfig config = LoadScene(c.scene);
    ParseFormulation(c.formulation, &config.formulation);
    if (std::string(c.method) != "none") ParseMethod(c.method, &config.method);
    if (config.formulation == Formulation::kKinematic) config.want_torques = true;
    const std::string name =
        std::string("BM_Scene/") + c.scene + "/" + c.formulation + "/" + c.method;
    benchmark::RegisterBenchmark(name.c_str(), BM_Scene, config)->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("BM_ResultsDirectory/seed-servo", BM_ResultsDirectory,
                               LoadScene("seed-servo"))
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("BM_RhsEval/seed-servo", BM_RhsEval, LoadScene("seed-servo"))
      ->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("BM_ResidualEval/seed-run/body-index2", BM_BodyEval,
                               LoadScene("seed-run"), true)
      ->Unit(benchmark::kNanosecond);
  benchmark::RegisterBenchmark("BM_RhsEval/seed-servo/body-baumgarte", BM_BodyEval,
                               LoadScene("seed-servo"), false)
      ->Unit(benchmark::kNanosecond);
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  mbstream::RegisterAll();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
