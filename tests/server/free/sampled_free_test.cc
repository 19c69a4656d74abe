// Sampled drives (pd_servo with period_s, external drives commanded by a ControlLaw) on the
// one-coordinate joints of models with free bodies and ball joints (server/sim/
// sampled_joint_run.h): the servos and the controller read each joint's position at its
// position index, the quaternions are unit at every control instant, an external PD equals
// the built-in sampled one, the sampled servo converges to the continuous one at first order,
// internal efforts keep a floating tree's momentum in zero gravity, and a period allocates
// nothing after the first.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "server/engine/engine.h"
#include "server/sim/run_validation.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/free/free_run.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

constexpr double kPeriod = 1e-3;  // s

Model Floating() {
  std::mt19937 rng(7);
  return testing::FloatingTree(rng);
}

Model Balls() {
  std::mt19937 rng(11);
  return testing::BallTree(rng);
}

// The one-coordinate joints (their velocity indices), the ones a drive may act on.
std::vector<int> Actuated(const Model& model) {
  std::vector<int> joints;
  for (const Body& body : model.bodies) {
    if (body.nv() == 1) joints.push_back(body.v_index);
  }
  return joints;
}

// A servo on each actuated joint k-th of them along 0.2 sin((1 + k / 2) t), sampled every
// `period` (0: continuous); the free and ball joints passive, the box and torso moving.
RunConfig Servos(const Model& model, double period, double duration = 0.3) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.05;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.drives.resize(static_cast<size_t>(model.nv()));
  const std::vector<int> joints = Actuated(model);
  for (size_t k = 0; k < joints.size(); ++k) {
    DriveConfig& drive = config.drives[static_cast<size_t>(joints[k])];
    drive = testing::SineServo(20.0, 1.0, 0.0, 0.2, 1.0 + 0.5 * static_cast<double>(k));
    drive.period = period;
  }
  config.qd0 = Eigen::VectorXd::Zero(model.nv());
  for (const int b : model.free_bodies) {  // each free body tumbling and drifting
    const int v = model.bodies[static_cast<size_t>(b)].v_index;
    config.qd0(v + 0) = 0.3;
    config.qd0(v + 4) = 1.5;
    config.qd0(v + 5) = -0.7;
  }
  return config;
}

// The servos' law, computed outside the engine from the state the controller gets: q by
// position index (ControlState::q has nq values), qd by velocity index. Also checks that every
// quaternion it is shown is unit.
class ServoLaw : public ControlLaw {
 public:
  ServoLaw(const Model& model, const RunConfig& servos) : model_(model), servos_(servos) {}
  bool Command(const ControlState& state, double* commands, RunStats*) override {
    EXPECT_EQ(state.q->size(), model_.nq());
    EXPECT_EQ(state.qd->size(), model_.nv());
    for (const int k : model_.quaternions) {
      norm_error = std::max(norm_error, std::abs(state.q->segment<4>(k).norm() - 1.0));
    }
    size_t c = 0;
    for (const Body& body : model_.bodies) {
      const DriveConfig& drive = servos_.drives[static_cast<size_t>(body.v_index)];
      if (body.nv() != 1 || drive.kind != DriveConfig::Kind::kPdServo) continue;
      const double a = drive.trajectory.amplitude[0], w = drive.trajectory.omega[0];
      const double ref = drive.trajectory.offset + a * std::sin(w * state.t);
      const double rate = (a * w) * std::cos(w * state.t);
      commands[c++] = drive.kp * (ref - (*state.q)(body.q_index)) +
                      drive.kd * (rate - (*state.qd)(body.v_index));
    }
    ++calls;
    return true;
  }
  long calls = 0;
  double norm_error = 0.0;

 private:
  const Model& model_;
  const RunConfig servos_;
};

RunConfig External(const RunConfig& servos) {
  RunConfig config = servos;
  for (DriveConfig& drive : config.drives) {
    if (drive.kind != DriveConfig::Kind::kPdServo) continue;
    const double period = drive.period;
    drive = DriveConfig{};
    drive.kind = DriveConfig::Kind::kExternal;
    drive.command = DriveConfig::Command::kEffort;
    drive.period = period;
  }
  return config;
}

double WorstDifference(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.q.size(), b.q.size());
  EXPECT_EQ(a.qd.size(), b.qd.size());
  double worst = 0.0;
  for (size_t k = 0; k < std::min(a.q.size(), b.q.size()); ++k) {
    worst = std::max(worst, std::abs(a.q[k] - b.q[k]));
  }
  for (size_t k = 0; k < std::min(a.qd.size(), b.qd.size()); ++k) {
    worst = std::max(worst, std::abs(a.qd[k] - b.qd[k]));
  }
  return worst;
}

void ExpectExternalEqualsBuiltin(const Model& model) {
  const RunConfig servos = Servos(model, kPeriod);
  ValidateRun(model, servos);
  const RunResult builtin = Simulate(model, servos);
  ASSERT_EQ(builtin.stats.status, RunStatus::kFinished) << builtin.stats.message;
  const RunConfig external = External(servos);
  ValidateRun(model, external);
  ServoLaw law(model, servos);
  const RunResult controlled = Simulate(model, {}, external, nullptr, nullptr, &law);
  ASSERT_EQ(controlled.stats.status, RunStatus::kFinished) << controlled.stats.message;
  EXPECT_EQ(law.calls, 300);  // t = 0, 1 ms, ..., 299 ms
  EXPECT_LT(law.norm_error, 1e-15);
  EXPECT_EQ(controlled.positions(), model.nq());
  EXPECT_LE(WorstDifference(builtin, controlled), 1e-12);
  EXPECT_EQ(builtin.stats.solver.steps, controlled.stats.solver.steps);
  // The arm moved: the servos acted on the joints they read.
  double moved = 0.0;
  const size_t last = static_cast<size_t>(builtin.num_frames() - 1) * builtin.positions();
  for (const Body& body : model.bodies) {
    if (body.nv() == 1) moved = std::max(moved, std::abs(builtin.q[last + body.q_index]));
  }
  EXPECT_GT(moved, 0.01);
}

TEST(SampledFreeTest, AnExternalPdEqualsTheSampledServoOnAFloatingTree) {
  ExpectExternalEqualsBuiltin(Floating());
}

TEST(SampledFreeTest, AnExternalPdEqualsTheSampledServoBesideBallJoints) {
  ExpectExternalEqualsBuiltin(Balls());
}

// The zero-order hold delays the servo by about h / 2: the error against the continuous servo
// halves with h.
TEST(SampledFreeTest, TheSampledServoConvergesToTheContinuousOneAtFirstOrder) {
  const Model model = Floating();
  const RunResult exact = Simulate(model, Servos(model, 0.0));
  ASSERT_EQ(exact.stats.status, RunStatus::kFinished) << exact.stats.message;
  std::vector<double> errors;
  for (const double h : {4e-3, 2e-3, 1e-3}) {
    const RunResult sampled = Simulate(model, Servos(model, h));
    ASSERT_EQ(sampled.stats.status, RunStatus::kFinished) << sampled.stats.message;
    errors.push_back(WorstDifference(exact, sampled));
  }
  for (size_t k = 0; k + 1 < errors.size(); ++k) {
    const double ratio = errors[k] / errors[k + 1];
    EXPECT_GT(ratio, 1.7) << errors[k] << " " << errors[k + 1];
    EXPECT_LT(ratio, 2.3) << errors[k] << " " << errors[k + 1];
  }
}

// In zero gravity the drives' efforts are internal to the floating torso's tree: its spatial
// momentum (and the lone box's) stays what it was, through every held command and restart.
TEST(SampledFreeTest, HeldCommandsKeepAFloatingTreesMomentumInZeroGravity) {
  const Model model = Floating();
  RunConfig servos = Servos(model, kPeriod, 1.0);
  servos.gravity.setZero();
  servos.output_interval = 0.1;
  // 1000 restarts each add their local error: at rtol 1e-10 the drift reaches 9e-8; at 1e-12
  // it stays below 1e-9, the bar for a floating tree.
  servos.rtol = 1e-12;
  servos.atol = 1e-14;
  const RunConfig external = External(servos);
  ServoLaw law(model, servos);
  const RunResult result = Simulate(model, {}, external, nullptr, nullptr, &law);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  Data data(model);
  const auto frame = [&](int f, Eigen::VectorXd* q, Eigen::VectorXd* qd) {
    *q = Eigen::Map<const Eigen::VectorXd>(&result.q[static_cast<size_t>(f) * model.nq()],
                                           model.nq());
    *qd = Eigen::Map<const Eigen::VectorXd>(&result.qd[static_cast<size_t>(f) * model.nv()],
                                            model.nv());
  };
  Eigen::VectorXd q, qd;
  frame(0, &q, &qd);
  const Vector6d h0 = testing::SpatialMomentum(model, data, q, qd, {"arm1", "arm2"});
  ASSERT_GT(h0.norm(), 0.1);
  double worst = 0.0;
  for (int f = 1; f < result.num_frames(); ++f) {
    frame(f, &q, &qd);
    const Vector6d h = testing::SpatialMomentum(model, data, q, qd, {"arm1", "arm2"});
    worst = std::max(worst, (h - h0).norm() / h0.norm());
  }
  EXPECT_LT(worst, 1e-9);
  // The commands did work: the torso's joints moved against one another.
  const size_t last = static_cast<size_t>(result.num_frames() - 1) * model.nq();
  const Body& knee = model.bodies[static_cast<size_t>(model.FindBody("shin_l"))];
  EXPECT_GT(std::abs(result.q[last + knee.q_index]), 0.01);
}

// Counts the allocations at each control instant (and commands the servo law).
class CountingLaw : public ServoLaw {
 public:
  using ServoLaw::ServoLaw;
  bool Command(const ControlState& state, double* commands, RunStats* stats) override {
    if (state.step >= 0 && state.step < 50)
      at[static_cast<size_t>(state.step)] = testing::AllocationCount();
    return ServoLaw::Command(state, commands, stats);
  }
  std::vector<long> at = std::vector<long>(50, -1);
};

TEST(SampledFreeTest, APeriodAllocatesNothingAfterTheFirstWithFreeBodiesAndBallJoints) {
  if (!testing::CountsCAllocations()) {
    GTEST_SKIP() << "malloc is the sanitizer's: SUNDIALS' allocations not counted";
  }
  for (const Model& model : {Floating(), Balls()}) {
    for (const Method method : {Method::kRk4, Method::kBdf, Method::kErk, Method::kDirk}) {
      RunConfig servos = Servos(model, kPeriod, 50 * kPeriod);
      servos.output_interval = servos.duration;
      servos.method = method;
      servos.fixed_step = kPeriod / 4;
      servos.rtol = 1e-8;
      servos.atol = 1e-10;
      const RunConfig external = External(servos);
      ValidateRun(model, external);
      CountingLaw law(model, servos);
      const RunResult result = Simulate(model, {}, external, nullptr, nullptr, &law);
      ASSERT_EQ(result.stats.status, RunStatus::kFinished)
          << MethodName(method) << ": " << result.stats.message;
      ASSERT_GE(law.at[49], 0);
      EXPECT_EQ(law.at[49] - law.at[1], 0) << model.name << " " << MethodName(method);
    }
  }
}

}  // namespace
}  // namespace mbstream
