// DriveSet::ActuatorEfforts (one sincos per distinct sine argument, shared by the joints)
// against the per-joint ActuatorEffort, bit for bit, and the joint-space ODE that uses it
// against the per-joint path.
#include "server/drives/drive_set.h"

#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "server/dynamics/aba.h"
#include "server/sim/joint_space_ode.h"
#include "shared/common/check.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

// Compares doubles bit for bit (0.0 and -0.0 apart).
std::uint64_t Bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// offset + sum_k a_k sin(w_k t + phase_k), terms as {a, w, phase}.
Trajectory Sines(double offset, const std::vector<std::array<double, 3>>& terms) {
  Trajectory trajectory;
  trajectory.offset = offset;
  for (const auto& [a, w, phase] : terms) {
    trajectory.amplitude.push_back(a);
    trajectory.omega.push_back(w);
    trajectory.phase.push_back(phase);
  }
  return trajectory;
}

DriveConfig Servo(const Trajectory& trajectory, double kp, double kd) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPdServo;
  drive.trajectory = trajectory;
  drive.kp = kp;
  drive.kd = kd;
  return drive;
}

DriveConfig Torque(double constant, double amplitude, double omega, double phase) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kTorque;
  drive.constant = constant;
  drive.amplitude = amplitude;
  drive.omega = omega;
  drive.phase = phase;
  return drive;
}

// The IRB 1600's six joints with servos and torque laws sharing some sine arguments and not
// others, and a spline servo. Distinct arguments: A = (0.5, 0.2), B = (1.7, 0.0),
// C = (2.5, -0.0) and D = (2.5, 0.0) (equal in value, not in bits: kept apart).
RunConfig MixedDrives() {
  Trajectory spline;
  spline.kind = Trajectory::Kind::kSpline;
  spline.times = {0.0, 0.7, 1.5, 3.0};
  spline.values = {0.1, 0.9, -0.4, 0.3};
  RunConfig config;
  config.drives = {
      Servo(Sines(0.1, {{0.8, 0.5, 0.2}, {0.3, 1.7, 0.0}}), 400.0, 40.0),  // A, B
      Servo(Sines(-0.2, {{1.1, 0.5, 0.2}}), 300.0, 20.0),                  // A
      Torque(2.0, 5.0, 0.5, 0.2),                                          // A
      Servo(spline, 150.0, 12.0),
      Torque(-1.0, 3.0, 2.5, -0.0),                                      // C
      Servo(Sines(0.0, {{0.4, 2.5, 0.0}, {0.2, 1.7, 0.0}}), 50.0, 5.0),  // D, B
  };
  return config;
}

// The drive laws written out from the configuration and the reference trajectories
// (TrajectoryEvaluator), independently of DriveSet's compact form.
double LawFromConfig(const DriveSet& drives, const DriveConfig& drive, int joint, double t,
                     double q, double qd) {
  switch (drive.kind) {
    case DriveConfig::Kind::kTorque:
      return drive.constant + drive.amplitude * std::sin(drive.omega * t + drive.phase);
    case DriveConfig::Kind::kPdServo: {
      const TrajectoryPoint ref = drives.Reference(joint, t);
      return drive.kp * (ref.q - q) + drive.kd * (ref.qd - qd);
    }
    default:
      return 0.0;
  }
}

// ActuatorEfforts and ActuatorEffort against the laws written out, joint by joint at random
// (t, q, qd), bit for bit, without allocating; each time twice (the workspace reused, as by
// Newton iterations).
void ExpectEffortsMatchPerJointLaws(const Model& model, const RunConfig& config) {
  const DriveSet drives(model, config.drives);
  DriveSet::Workspace workspace = drives.MakeWorkspace();
  const int n = drives.size();
  Eigen::VectorXd q(n), qd(n), effort(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0), time(0.0, 4.0);
  double t = 0.0;
  for (int sample = 0; sample < 400; ++sample) {
    if (sample % 2 == 0 && sample > 0) t = time(rng);
    for (int i = 0; i < n; ++i) {
      q(i) = uniform(rng);
      qd(i) = uniform(rng);
    }
    const long before = testing::AllocationCount();
    drives.ActuatorEfforts(t, q.data(), qd.data(), workspace, effort.data());
    EXPECT_EQ(testing::AllocationCount() - before, 0);
    for (int i = 0; i < n; ++i) {
      const double expected = LawFromConfig(drives, config.drives[i], i, t, q(i), qd(i));
      EXPECT_EQ(Bits(effort(i)), Bits(expected)) << "joint " << i << " at t = " << t;
      EXPECT_EQ(Bits(drives.ActuatorEffort(i, t, q(i), qd(i))), Bits(expected))
          << "joint " << i << " at t = " << t;
    }
  }
}

TEST(DriveSetTest, SharedSineEffortsMatchThePerJointLaws) {
  const Model& model = testing::Irb1600();
  const RunConfig mixed = MixedDrives();
  EXPECT_EQ(DriveSet(model, mixed.drives).num_sine_arguments(), 4);
  ExpectEffortsMatchPerJointLaws(model, mixed);

  // A prescribed and a passive joint: effort 0, and their references take no sincos.
  RunConfig with_prescribed = mixed;
  with_prescribed.drives[1].kind = DriveConfig::Kind::kPrescribed;
  with_prescribed.drives[3] = DriveConfig{};
  EXPECT_EQ(DriveSet(model, with_prescribed.drives).num_sine_arguments(), 4);
  ExpectEffortsMatchPerJointLaws(model, with_prescribed);

  // The seed-servo scene: six servos on one argument (omega = pi/10, phase 0).
  const RunConfig servo = testing::Scene("seed-servo");
  EXPECT_EQ(DriveSet(model, servo.drives).num_sine_arguments(), 1);
  ExpectEffortsMatchPerJointLaws(model, servo);

  // A workspace serves only the DriveSet that made it.
  const DriveSet other(model, servo.drives);
  DriveSet::Workspace workspace = other.MakeWorkspace();
  std::vector<double> zeros(6, 0.0), effort(6);
  EXPECT_THROW(DriveSet(model, servo.drives)
                   .ActuatorEfforts(0.5, zeros.data(), zeros.data(), workspace, effort.data()),
               InternalError);
}

// The joint-space ODE's right-hand side against the per-joint path it replaced: efforts
// from ActuatorEffort, damping, then ABA; bit for bit.
TEST(DriveSetTest, JointSpaceOdeRhsMatchesThePerJointEfforts) {
  const Model& model = testing::Irb1600();
  for (const RunConfig& config : {MixedDrives(), testing::Scene("seed-servo")}) {
    const DriveSet drives(model, config.drives);
    JointSpaceOde ode(model, drives);
    const int n = model.num_dofs();
    Data data(model);
    Eigen::VectorXd q(n), qd(n), tau(n);
    std::vector<double> y(2 * n), ydot(2 * n);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uniform(-1.5, 1.5), time(0.0, 4.0);
    double t = 0.0;
    for (int sample = 0; sample < 100; ++sample) {
      if (sample % 2 == 0) t = time(rng);  // each time twice, as in Newton iterations
      for (double& value : y) value = uniform(rng);
      ASSERT_EQ(ode.Rhs(t, y.data(), ydot.data()), 0);
      for (int i = 0; i < n; ++i) {
        q(i) = y[i];
        qd(i) = y[n + i];
        tau(i) = drives.ActuatorEffort(i, t, q(i), qd(i)) - drives.damping(i) * qd(i);
      }
      const Eigen::VectorXd& qdd = Aba(model, data, q, qd, tau);
      for (int i = 0; i < n; ++i) {
        EXPECT_EQ(Bits(ydot[i]), Bits(qd(i)));
        EXPECT_EQ(Bits(ydot[n + i]), Bits(qdd(i))) << "joint " << i << " at t = " << t;
        EXPECT_EQ(Bits(ode.drive_effort()(i)), Bits(drives.ActuatorEffort(i, t, q(i), qd(i))));
      }
    }
  }
}

// A held component of a prescribed pose has the empty trajectory: every reader of a drive's
// reference gets 0 from it (Trajectory{} is the sine law with no terms).
TEST(DriveSetTest, AnEmptyTrajectoryIsZeroAtEveryTime) {
  const TrajectoryEvaluator empty{Trajectory{}};
  for (const double t : {-1.0, 0.0, 0.5, 1e9}) {
    const TrajectoryPoint p = empty.At(t);
    EXPECT_EQ(p.q, 0.0);
    EXPECT_EQ(p.qd, 0.0);
    EXPECT_EQ(p.qdd, 0.0);
  }
}

}  // namespace
}  // namespace mbstream
