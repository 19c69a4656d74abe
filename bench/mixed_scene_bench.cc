// Whole runs of models with prescribed and free joints, the joint-space ODE's mixed case:
//
//   build/bench/mixed_scene_bench --benchmark_repetitions=3 --benchmark_report_aggregates_only
//
// BM_MixedScene/<robot>/<method>: one Simulate per iteration of the IRB 1600, the 38-joint
// tree and the 100-link chain (models/big/) with min(6, n/2) joints, spread evenly, moved by
// sine laws and the others passive (their URDF damping, so the drives' work is a tracked
// quadrature); joint formulation, rtol 1e-6. Each right-hand side is one hybrid-dynamics
// pass (server/dynamics/aba.h); BDF's Jacobian is differenced, 2n right-hand sides each.
// Counters: the run's own CPU time, right-hand sides, steps.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/parse/urdf_import.h"

namespace mbstream {
namespace {

RunConfig MixedConfig(const Model& model, Method method, double duration) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.05;
  config.formulation = Formulation::kJoint;
  config.method = method;
  const int n = model.num_dofs();
  config.drives.resize(n);  // passive
  const int count = std::min(6, n / 2);
  for (int k = 0; k < count; ++k) {
    DriveConfig& drive = config.drives[k * n / count];
    drive.kind = DriveConfig::Kind::kPrescribed;
    drive.trajectory.amplitude = {0.5};
    drive.trajectory.omega = {2.0 + k};
    drive.trajectory.phase = {0.0};
  }
  return config;
}

void BM_MixedScene(benchmark::State& state, const Model* model, RunConfig config) {
  RunStats stats;
  for (auto _ : state) {
    RunResult result = Simulate(*model, config);
    benchmark::DoNotOptimize(result.tcp.data());
    stats = result.stats;
  }
  if (stats.status != RunStatus::kFinished) {
    state.SkipWithError((std::string(RunStatusName(stats.status)) + ": " + stats.message).c_str());
    return;
  }
  state.counters["cpu_ms"] = stats.cpu_s * 1e3;
  state.counters["rhs_evals"] = static_cast<double>(stats.solver.rhs_evals);
  state.counters["steps"] = static_cast<double>(stats.solver.steps);
}

void RegisterAll() {
  static const struct {
    const char* file;
    double duration;  // s
  } kModels[] = {{"/models/irb1600/irb1600.urdf", 2.0},
                 {"/models/big/tree38.urdf", 1.0},
                 {"/models/big/chain100.urdf", 0.25}};
  static std::vector<std::unique_ptr<Model>> models;  // alive until the benchmarks ran
  for (const auto& entry : kModels) {
    models.push_back(std::make_unique<Model>(
        ImportUrdfFile(std::string(MBSTREAM_SOURCE_DIR) + entry.file).model));
    const Model* model = models.back().get();
    for (Method method : {Method::kBdf, Method::kErk}) {
      const std::string name =
          "BM_MixedScene/" + model->name + "/" + std::string(MethodName(method));
      benchmark::RegisterBenchmark(name.c_str(), BM_MixedScene, model,
                                   MixedConfig(*model, method, entry.duration))
          ->Unit(benchmark::kMillisecond);
    }
  }
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
