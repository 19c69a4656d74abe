// Timings of the physics core on the IRB 1600 (models/irb1600/irb1600.urdf).
//
//   build/bench/dynamics_bench --benchmark_repetitions=10 --benchmark_report_aggregates_only
//
// One fixture: the model is imported once; every iteration runs the algorithm at a new
// random state from a pre-generated pool, so branch prediction sees realistic inputs.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/parse/urdf_import.h"

namespace mbstream {
namespace {

struct States {
  explicit States(int n) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> dist(-2.0, 2.0);
    for (auto* pool : {&q, &qd, &x}) {
      pool->resize(kCount, Eigen::VectorXd(n));
      for (auto& v : *pool) {
        for (int i = 0; i < n; ++i) v(i) = dist(rng);
      }
    }
  }
  static constexpr int kCount = 256;
  std::vector<Eigen::VectorXd> q, qd, x;  // x: a torque or an acceleration
};

const Model& Irb1600() {
  static const Model model =
      ImportUrdfFile(MBSTREAM_SOURCE_DIR "/models/irb1600/irb1600.urdf").model;
  return model;
}

template <typename Algorithm>
void Run(benchmark::State& state, Algorithm algorithm) {
  const Model& model = Irb1600();
  Data data(model);
  const States states(model.num_dofs());
  int k = 0;
  for (auto _ : state) {
    algorithm(model, data, states.q[k], states.qd[k], states.x[k]);
    benchmark::ClobberMemory();
    k = (k + 1) % States::kCount;
  }
}

void BM_ForwardKinematics(benchmark::State& state) {
  Run(state, [](const Model& m, Data& d, const auto& q, const auto&, const auto&) {
    ForwardKinematics(m, d, q);
    benchmark::DoNotOptimize(d.frame_world[m.tcp_frame].p.data());
  });
}
void BM_InverseDynamics(benchmark::State& state) {
  Run(state, [](const Model& m, Data& d, const auto& q, const auto& qd, const auto& qdd) {
    benchmark::DoNotOptimize(Rnea(m, d, q, qd, qdd).data());
  });
}
void BM_MassMatrix(benchmark::State& state) {
  Run(state, [](const Model& m, Data& d, const auto& q, const auto&, const auto&) {
    benchmark::DoNotOptimize(Crba(m, d, q).data());
  });
}
void BM_ForwardDynamics(benchmark::State& state) {
  Run(state, [](const Model& m, Data& d, const auto& q, const auto& qd, const auto& tau) {
    benchmark::DoNotOptimize(Aba(m, d, q, qd, tau).data());
  });
}

BENCHMARK(BM_ForwardKinematics)->Name("BM_ForwardKinematics/irb1600");
BENCHMARK(BM_InverseDynamics)->Name("BM_InverseDynamics/irb1600");
BENCHMARK(BM_MassMatrix)->Name("BM_MassMatrix/irb1600");
BENCHMARK(BM_ForwardDynamics)->Name("BM_ForwardDynamics/irb1600");

}  // namespace
}  // namespace mbstream

BENCHMARK_MAIN();
