// Timings of the physics core on the IRB 1600 (models/irb1600/irb1600.urdf) and on the big
// models (models/big/: a 38-joint branching tree and a 100-link chain), or on URDF files
// given on the command line instead:
//
//   build/bench/dynamics_bench --benchmark_repetitions=10 --benchmark_report_aggregates_only
//   build/bench/dynamics_bench --urdf=FILE [--urdf=FILE ...]   # BM_*/<robot> for each
//
// One fixture: the model is imported once; every iteration runs the algorithm at a new
// random state from a pre-generated pool, so branch prediction sees realistic inputs.
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/hybrid_dynamics.h"
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

template <typename Algorithm>
void Run(benchmark::State& state, const Model& model, Algorithm algorithm) {
  Data data(model);
  const States states(model.num_dofs());
  int k = 0;
  for (auto _ : state) {
    algorithm(model, data, states.q[k], states.qd[k], states.x[k]);
    benchmark::ClobberMemory();
    k = (k + 1) % States::kCount;
  }
}

void BM_ForwardKinematics(benchmark::State& state, const Model* model) {
  Run(state, *model, [](const Model& m, Data& d, const auto& q, const auto&, const auto&) {
    ForwardKinematics(m, d, q);
    benchmark::DoNotOptimize(d.frame_world[m.tcp_frame].p.data());
  });
}
void BM_InverseDynamics(benchmark::State& state, const Model* model) {
  Run(state, *model, [](const Model& m, Data& d, const auto& q, const auto& qd, const auto& qdd) {
    benchmark::DoNotOptimize(Rnea(m, d, q, qd, qdd).data());
  });
}
void BM_MassMatrix(benchmark::State& state, const Model* model) {
  Run(state, *model, [](const Model& m, Data& d, const auto& q, const auto&, const auto&) {
    benchmark::DoNotOptimize(Crba(m, d, q).data());
  });
}
void BM_ForwardDynamics(benchmark::State& state, const Model* model) {
  Run(state, *model, [](const Model& m, Data& d, const auto& q, const auto& qd, const auto& tau) {
    benchmark::DoNotOptimize(Aba(m, d, q, qd, tau).data());
  });
}

// Mixed models (some joints prescribed, the joint-space ODE's right-hand side): min(6, n/2)
// joints prescribed, spread evenly; their accelerations given, their forces computed.
std::vector<unsigned char> PrescribedMask(int n) {
  std::vector<unsigned char> mask(n, 0);
  const int count = std::min(6, n / 2);
  for (int k = 0; k < count; ++k) mask[k * n / count] = 1;
  return mask;
}

void BM_HybridDynamics(benchmark::State& state, const Model* model) {
  const std::vector<unsigned char> mask = PrescribedMask(model->num_dofs());
  Run(state, *model, [&](const Model& m, Data& d, const auto& q, const auto& qd, const auto& x) {
    benchmark::DoNotOptimize(HybridAba(m, d, q, qd, x, x, mask).data());
  });
}

// What the joint-space ODE did before hybrid dynamics: RNEA for the bias, CRBA, a Cholesky
// factorisation of the free-free block, and RNEA again for the prescribed joints' forces.
void BM_PartitionedDynamics(benchmark::State& state, const Model* model) {
  const int n = model->num_dofs();
  const std::vector<unsigned char> mask = PrescribedMask(n);
  std::vector<int> free;
  for (int i = 0; i < n; ++i) {
    if (!mask[i]) free.push_back(i);
  }
  const auto nf = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd M_free(nf, nf);
  Eigen::VectorXd rhs(nf), qdd(n);
  Eigen::LLT<Eigen::MatrixXd> llt(nf);
  Run(state, *model, [&](const Model& m, Data& d, const auto& q, const auto& qd, const auto& x) {
    qdd = x;
    for (int i : free) qdd(i) = 0.0;
    const Eigen::VectorXd& bias = Rnea(m, d, q, qd, qdd);
    for (Eigen::Index a = 0; a < nf; ++a) rhs(a) = x(free[a]) - bias(free[a]);
    const Eigen::MatrixXd& M = Crba(m, d, q);
    for (Eigen::Index a = 0; a < nf; ++a) {
      for (Eigen::Index b = 0; b < nf; ++b) M_free(a, b) = M(free[a], free[b]);
    }
    llt.compute(M_free);
    llt.solveInPlace(rhs);
    for (Eigen::Index a = 0; a < nf; ++a) qdd(free[a]) = rhs(a);
    benchmark::DoNotOptimize(Rnea(m, d, q, qd, qdd).data());
  });
}

// Registers every benchmark for the model of one URDF file, named after its robot.
void RegisterModel(const std::string& path) {
  static std::vector<std::unique_ptr<Model>> models;  // alive until the benchmarks ran
  models.push_back(std::make_unique<Model>(ImportUrdfFile(path).model));
  const Model* model = models.back().get();
  const std::string robot = "/" + model->name;
  benchmark::RegisterBenchmark(("BM_ForwardKinematics" + robot).c_str(), BM_ForwardKinematics,
                               model);
  benchmark::RegisterBenchmark(("BM_InverseDynamics" + robot).c_str(), BM_InverseDynamics, model);
  benchmark::RegisterBenchmark(("BM_MassMatrix" + robot).c_str(), BM_MassMatrix, model);
  benchmark::RegisterBenchmark(("BM_ForwardDynamics" + robot).c_str(), BM_ForwardDynamics, model);
  benchmark::RegisterBenchmark(("BM_HybridDynamics" + robot).c_str(), BM_HybridDynamics, model);
  benchmark::RegisterBenchmark(("BM_PartitionedDynamics" + robot).c_str(), BM_PartitionedDynamics,
                               model);
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  // --urdf=FILE (repeatable) is ours; everything else goes to Google Benchmark.
  std::vector<std::string> urdfs;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--urdf=", 7) == 0) {
      urdfs.emplace_back(argv[i] + 7);
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  if (urdfs.empty()) {
    for (const char* file :
         {"/models/irb1600/irb1600.urdf", "/models/big/tree38.urdf", "/models/big/chain100.urdf"}) {
      urdfs.push_back(std::string(MBSTREAM_SOURCE_DIR) + file);
    }
  }
  try {
    for (const std::string& path : urdfs) mbstream::RegisterModel(path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dynamics_bench: %s\n", e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
