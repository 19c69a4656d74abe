// Timings of the algorithms with free bodies (docs/free_bodies.md): one free body, the
// 38-joint tree of models/big/tree38.urdf on a free root (44 degrees of freedom, 45
// positions), against the same tree bolted down, and a published humanoid on a free root
// (Atlas v3 of Debian's dart-doc, read with --floating-base: 6 + 27 velocities; left out with
// a note when the file is missing):
//
//   build/bench/free_body_bench --benchmark_repetitions=10 --benchmark_report_aggregates_only
//
// Where CMake finds MuJoCo (libmujoco-dev 2.2.2), BM_MujocoForward/NAME times mj_forward on
// the same model written as MJCF (tests/server/free/mjcf.h), at the same states (MuJoCo numbers
// its coordinates depth first: each is copied to its place by joint name).
//
// Every iteration runs at a new random state from a pre-generated pool (unit quaternions).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <exception>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/free_joint.h"
#include "server/model/model_builder.h"
#include "server/parse/model_file.h"
#include "server/parse/urdf_import.h"

#include <filesystem>

#ifdef MBSTREAM_HAVE_MUJOCO
#include <mujoco/mujoco.h>

#include <fstream>

#include "tests/server/free/mjcf.h"
#endif

namespace mbstream {
namespace {

constexpr char kAtlas[] = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf";

struct States {
  explicit States(const Model& model) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> dist(-2.0, 2.0);
    const auto fill = [&](std::vector<Eigen::VectorXd>* pool, int n) {
      pool->resize(kCount, Eigen::VectorXd(n));
      for (auto& v : *pool) {
        for (int i = 0; i < n; ++i) v(i) = dist(rng);
      }
    };
    fill(&q, model.nq());
    fill(&qd, model.nv());
    fill(&x, model.nv());
    for (auto& v : q) {
      for (const int b : model.free_bodies)
        free_joint::NormaliseQuaternion(&v(model.bodies[b].q_index));
    }
  }
  static constexpr int kCount = 256;
  std::vector<Eigen::VectorXd> q, qd, x;  // x: a torque or an acceleration
};

template <typename Algorithm>
void Run(benchmark::State& state, const Model& model, Algorithm algorithm) {
  Data data(model);
  const States states(model);
  int k = 0;
  for (auto _ : state) {
    algorithm(model, data, states.q[k], states.qd[k], states.x[k]);
    benchmark::ClobberMemory();
    k = (k + 1) % States::kCount;
  }
}

void BM_ForwardDynamics(benchmark::State& state, const Model* model) {
  Run(state, *model, [](const Model& m, Data& d, const auto& q, const auto& qd, const auto& tau) {
    benchmark::DoNotOptimize(Aba(m, d, q, qd, tau).data());
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

RigidInertia Box() {
  RigidInertia inertia;
  inertia.mass = 2.0;
  inertia.com = Vector3d(0.01, -0.02, 0.03);
  inertia.inertia_com = Vector3d(0.1, 0.15, 0.2).asDiagonal();
  return inertia;
}

// One free body.
Model FreeBody() {
  ModelBuilder builder("free_body", "world");
  builder.AddFreeLink("body", "body", Pose::Identity(), Box());
  return builder.Build();
}

// `fixed`'s tree hung from a free root body instead of the world.
Model Floating(const Model& fixed) {
  ModelBuilder builder(fixed.name + "_floating", "world");
  builder.AddFreeLink("floating_base", "floating_base", Pose::Identity(), Box());
  for (const Body& body : fixed.bodies) {
    const std::string parent =
        body.parent == kBase ? "floating_base" : fixed.bodies[body.parent].name;
    builder.AddMovingLink(body.name, parent, body.joint, body.inertia);
  }
  return builder.Build();
}

#ifdef MBSTREAM_HAVE_MUJOCO
// mj_forward (contacts, constraints and passive forces off) at the same states.
void BM_MujocoForward(benchmark::State& state, const Model* model) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("mbstream_bench_" + model->name + ".xml");
  std::ofstream(path) << testing::Mjcf(*model);
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
  std::filesystem::remove(path);
  if (m == nullptr) {
    state.SkipWithError(error);
    return;
  }
  mjData* d = mj_makeData(m);
  std::vector<int> qpos(static_cast<size_t>(model->nq())), dof(static_cast<size_t>(model->nv()));
  for (const Body& body : model->bodies) {
    const int joint = mj_name2id(m, mjOBJ_JOINT, body.joint.name.c_str());
    if (joint < 0) {
      state.SkipWithError(("MuJoCo's model has no joint " + body.joint.name).c_str());
      return;
    }
    for (int k = 0; k < body.nq(); ++k) qpos[body.q_index + k] = m->jnt_qposadr[joint] + k;
    for (int k = 0; k < body.nv(); ++k) dof[body.v_index + k] = m->jnt_dofadr[joint] + k;
  }
  const States states(*model);
  int k = 0;
  for (auto _ : state) {
    for (int i = 0; i < m->nq; ++i) d->qpos[qpos[i]] = states.q[k](i);
    for (int i = 0; i < m->nv; ++i) {
      d->qvel[dof[i]] = states.qd[k](i);
      d->qfrc_applied[dof[i]] = states.x[k](i);
    }
    mj_forward(m, d);
    benchmark::DoNotOptimize(d->qacc);
    benchmark::ClobberMemory();
    k = (k + 1) % States::kCount;
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}
#endif

void Register(const std::string& name, const Model* model) {
#ifdef MBSTREAM_HAVE_MUJOCO
  benchmark::RegisterBenchmark(("BM_MujocoForward/" + name).c_str(), BM_MujocoForward, model);
#endif
  benchmark::RegisterBenchmark(("BM_ForwardDynamics/" + name).c_str(), BM_ForwardDynamics, model);
  benchmark::RegisterBenchmark(("BM_InverseDynamics/" + name).c_str(), BM_InverseDynamics, model);
  benchmark::RegisterBenchmark(("BM_MassMatrix/" + name).c_str(), BM_MassMatrix, model);
}

}  // namespace
}  // namespace mbstream

int main(int argc, char** argv) {
  using namespace mbstream;
  static std::vector<std::unique_ptr<Model>> models;  // alive until the benchmarks ran
  try {
    models.push_back(std::make_unique<Model>(FreeBody()));
    const Model tree =
        ImportUrdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/models/big/tree38.urdf").model;
    models.push_back(std::make_unique<Model>(Floating(tree)));
    models.push_back(std::make_unique<Model>(tree));
    if (std::filesystem::exists(kAtlas)) {
      models.push_back(std::make_unique<Model>(
          ImportModelFile(kAtlas, UrdfImportOptions{.floating_base = true}).model));
    } else {
      std::fprintf(stderr, "free_body_bench: %s is missing (Debian's dart-doc): no atlas rows\n",
                   kAtlas);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "free_body_bench: %s\n", e.what());
    return 2;
  }
  Register("free_body", models[0].get());
  Register("tree38_floating", models[1].get());
  Register("tree38_fixed", models[2].get());
  if (models.size() > 3) Register("atlas_floating", models[3].get());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
