// Contact detection of many bodies at rest (issue 44, docs/performance.md "Contact
// detection"): 100 boxes (0.2 m, 2 kg) on a 10 x 10 grid of 0.5 m pitch (0.3 m gaps: none
// touches another), each pressed 3.9e-4 m into the floor (its rest depth under the run's
// default stiffness, 5e4 N/m the pair: m g / k), so that every box stands on its four bottom
// corners, 400 contacts:
//
//   build/bench/contact_detection_bench --benchmark_repetitions=10
//       --benchmark_report_aggregates_only  (one line)
//
// mbstream (server/contact/, the code runs use), one evaluation each:
//   BM_MbstreamContactForces  ContactForces::AddForces: the geometries' poses, FCL's dynamic
//                             AABB tree (update, self-collide: no box pair is near), the
//                             plane against every box, the narrow phase, and then the contact
//                             law and J^T f of the 400 points (not separable from the outside).
//   BM_MbstreamNarrowPhase    NarrowPhase::Collide of the 100 box-floor pairs alone (what the
//                             broad phase hands it here).
//   BM_MbstreamSignedDistances ContactForces::SignedDistances: the integrator's root functions
//                             (the first 256 of the 5,050 allowed pairs).
// MuJoCo 2.2.2 (where CMake finds it): the same scene in MJCF,
//   BM_MujocoCollision        mj_collision: its broad phase (sweep and prune, bounding
//                             spheres) and narrow phase (plane-box), the contacts in d->contact.
// Each iteration evaluates the same state (after the kinematics, not timed). For scale, whole
// steps: BM_MbstreamRun (a 0.1 s run: steps, right-hand sides a step, each one AddForces)
// and BM_MujocoStep (mj_step).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "server/contact/contact_forces.h"
#include "server/contact/narrow_phase.h"
#include "server/engine/engine.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/data.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"

#ifdef MBSTREAM_HAVE_MUJOCO
#include <mujoco/mujoco.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#endif

namespace mbstream {
namespace {

constexpr int kSide = 10;          // boxes a side
constexpr double kPitch = 0.5;     // m between box centres
constexpr double kHalf = 0.1;      // m, half the box's edge
constexpr double kDepth = 3.9e-4;  // m into the floor

// The box at grid cell (i, j): its centre.
Eigen::Vector3d Centre(int i, int j) {
  return {kPitch * (i - (kSide - 1) / 2.0), kPitch * (j - (kSide - 1) / 2.0), kHalf - kDepth};
}

std::string BoxesSdf() {
  std::string text =
      "<?xml version=\"1.0\"?><sdf version=\"1.8\"><world name=\"boxes\">"
      "<model name=\"ground\"><static>true</static><link name=\"floor\"><collision "
      "name=\"plane\"><geometry><plane><normal>0 0 1</normal><size>20 20</size></plane>"
      "</geometry></collision></link></model>";
  char model[1024];
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      const Eigen::Vector3d c = Centre(i, j);
      std::snprintf(model, sizeof(model),
                    "<model name=\"box_%d_%d\"><pose>%.17g %.17g %.17g 0 0 0</pose><link "
                    "name=\"body\"><inertial><mass>2</mass><inertia><ixx>0.013333333333333334</"
                    "ixx><iyy>0.013333333333333334</iyy><izz>0.013333333333333334</izz></"
                    "inertia></inertial><collision name=\"cube\"><geometry><box><size>0.2 0.2 "
                    "0.2</size></box></geometry></collision></link></model>",
                    i, j, c.x(), c.y(), c.z());
      text += model;
    }
  }
  return text + "</world></sdf>";
}

// The scene at its default pose, the kinematics done: what a run's right-hand side sees.
struct OurBoxes {
  OurBoxes()
      : model(ImportSdf(BoxesSdf(), "boxes.sdf").model),
        forces(model, ContactSettings{}),
        narrow(model.collisions),
        data(model),
        q(model.nq()),
        qd(Eigen::VectorXd::Zero(model.nv())),
        tau(Eigen::VectorXd::Zero(model.nv())) {
    NeutralPositions(model, q.data());
    BodyKinematics(model, data, q);
    const int n = static_cast<int>(model.collisions.size());
    for (int g = 0; g < n; ++g) {
      const CollisionGeometry& geometry = model.collisions[g];
      X_W.push_back(geometry.body == kBase ? geometry.X_BG
                                           : data.X_world[geometry.body] * geometry.X_BG);
    }
    for (int g = 0; g < n; ++g) {
      if (model.collisions[g].shape.type == ShapeType::kPlane) plane = g;
    }
    for (int g = 0; g < n; ++g) {
      if (g != plane) boxes.push_back(g);
    }
    distances.resize(static_cast<size_t>(forces.num_root_pairs()));
    points.reserve(8 * boxes.size());
  }
  Model model;
  ContactForces forces;
  NarrowPhase narrow;
  Data data;
  Eigen::VectorXd q, qd, tau;
  std::vector<Pose> X_W;
  int plane = -1;
  std::vector<int> boxes;
  std::vector<double> distances;
  std::vector<ContactPoint> points;
};

OurBoxes& Ours() {
  static OurBoxes boxes;
  return boxes;
}

void BM_MbstreamContactForces(benchmark::State& state) {
  OurBoxes& s = Ours();
  for (auto _ : state) {
    s.tau.setZero();
    benchmark::DoNotOptimize(s.forces.AddForces(s.data, s.qd, &s.tau));
    benchmark::DoNotOptimize(s.tau.data());
  }
  state.counters["contacts"] = static_cast<double>(s.forces.contacts().size());
  state.counters["pairs"] = s.forces.num_allowed_pairs();
}
BENCHMARK(BM_MbstreamContactForces)->Unit(benchmark::kMicrosecond);

void BM_MbstreamNarrowPhase(benchmark::State& state) {
  OurBoxes& s = Ours();
  for (auto _ : state) {
    s.points.clear();
    for (const int g : s.boxes) {
      const int a = std::min(g, s.plane), b = std::max(g, s.plane);
      s.narrow.Collide(a, s.X_W[a], b, s.X_W[b], &s.points);
    }
    benchmark::DoNotOptimize(s.points.data());
  }
  state.counters["contacts"] = static_cast<double>(s.points.size());
}
BENCHMARK(BM_MbstreamNarrowPhase)->Unit(benchmark::kMicrosecond);

void BM_MbstreamSignedDistances(benchmark::State& state) {
  OurBoxes& s = Ours();
  for (auto _ : state) {
    s.forces.SignedDistances(s.data, s.distances.data());
    benchmark::DoNotOptimize(s.distances.data());
  }
  state.counters["root_pairs"] = s.forces.num_root_pairs();
}
BENCHMARK(BM_MbstreamSignedDistances)->Unit(benchmark::kMicrosecond);

// For scale: a whole run of the scene (0.1 s at the run spec's defaults: BDF, rtol 1e-6, the
// joint formulation), its steps and right-hand sides (each one AddForces), CPU per step.
void BM_MbstreamRun(benchmark::State& state) {
  OurBoxes& s = Ours();
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.want_torques = false;
  config.duration = 0.1;
  config.output_interval = 0.01;
  config.drives.resize(static_cast<size_t>(s.model.nv()));
  ValidateRun(s.model, config);
  RunResult result;
  for (auto _ : state) result = Simulate(s.model, config);
  const SolverStats& solver = result.stats.solver;
  state.counters["steps"] = static_cast<double>(solver.steps);
  state.counters["rhs_per_step"] =
      static_cast<double>(solver.rhs_evals) / static_cast<double>(std::max(1L, solver.steps));
  state.counters["us_per_step"] = benchmark::Counter(
      static_cast<double>(solver.steps),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  if (result.stats.status != RunStatus::kFinished) state.SkipWithError("the run did not finish");
}
BENCHMARK(BM_MbstreamRun)->Unit(benchmark::kMillisecond)->Iterations(1);

#ifdef MBSTREAM_HAVE_MUJOCO
std::string BoxesMjcf() {
  std::string text =
      "<mujoco model=\"boxes\"><size nconmax=\"1000\" njmax=\"6000\"/><worldbody><geom "
      "type=\"plane\" size=\"10 10 0.1\"/>";
  char body[512];
  for (int i = 0; i < kSide; ++i) {
    for (int j = 0; j < kSide; ++j) {
      const Eigen::Vector3d c = Centre(i, j);
      std::snprintf(body, sizeof(body),
                    "<body pos=\"%.17g %.17g %.17g\"><freejoint/><geom type=\"box\" size=\"0.1 "
                    "0.1 0.1\"/><inertial pos=\"0 0 0\" mass=\"2\" "
                    "diaginertia=\"0.013333333333333334 0.013333333333333334 "
                    "0.013333333333333334\"/></body>",
                    c.x(), c.y(), c.z());
      text += body;
    }
  }
  return text + "</worldbody></mujoco>";
}

struct MujocoBoxes {
  MujocoBoxes() {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / "mbstream_contact_detection_boxes.xml";
    std::ofstream(path) << BoxesMjcf();
    char error[1000] = "";
    m = mj_loadXML(path.c_str(), nullptr, error, sizeof(error));
    std::filesystem::remove(path);
    if (m == nullptr) throw std::runtime_error(std::string("MuJoCo refused the boxes: ") + error);
    d = mj_makeData(m);
    mj_forward(m, d);  // the kinematics (and one collision) at the initial state
  }
  ~MujocoBoxes() {
    mj_deleteData(d);
    mj_deleteModel(m);
  }
  mjModel* m = nullptr;
  mjData* d = nullptr;
};

void BM_MujocoCollision(benchmark::State& state) {
  static MujocoBoxes s;
  for (auto _ : state) {
    mj_collision(s.m, s.d);
    benchmark::DoNotOptimize(s.d->ncon);
  }
  state.counters["contacts"] = s.d->ncon;
}
BENCHMARK(BM_MujocoCollision)->Unit(benchmark::kMicrosecond);

// For scale: one mj_step (its default 2 ms, Euler) of the scene from rest.
void BM_MujocoStep(benchmark::State& state) {
  static MujocoBoxes s;
  mj_resetData(s.m, s.d);
  for (auto _ : state) mj_step(s.m, s.d);
  state.counters["contacts"] = s.d->ncon;
}
BENCHMARK(BM_MujocoStep)->Unit(benchmark::kMicrosecond);
#endif

}  // namespace
}  // namespace mbstream

BENCHMARK_MAIN();
