// Prescribed poses (run_spec.proto Drive.Pose, server/drives/pose_motion.h): a free body's and
// a ball joint's motion imposed in a kinematic run. Checked against closed forms written here
// from scratch: the rotation as a product of axis rotations, its angular velocity by central
// differences of R(t), and the wrench that moves the body by Newton-Euler.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "server/drives/pose_motion.h"
#include "server/engine/engine.h"
#include "server/model/coordinate_names.h"
#include "server/model/model_builder.h"
#include "server/sim/run_validation.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

constexpr double kPi = 3.14159265358979323846;

// R = Rz(yaw) Ry(pitch) Rx(roll), by Eigen's axis rotations.
Matrix3d Rpy(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Vector3d::UnitX()))
      .toRotationMatrix();
}

Vector3d Unskew(const Matrix3d& W) {
  return Vector3d(W(2, 1) - W(1, 2), W(0, 2) - W(2, 0), W(1, 0) - W(0, 1)) / 2.0;
}

// The test's pose: components as functions of t with their rates.
struct Component {
  double offset, amplitude, omega, phase;
  double At(double t) const { return offset + amplitude * std::sin(omega * t + phase); }
};
const Component kPose[6] = {{1.0, 0.3, 2.0, 0.1}, {0.0, 0.2, 3.0, 0.0},  {2.0, 0.5, 1.0, 0.4},
                            {0.2, 0.7, 1.3, 0.0}, {-0.1, 0.9, 0.7, 0.5}, {0.5, 2.0, 0.9, 0.2}};

Matrix3d RotationAt(double t) { return Rpy(kPose[3].At(t), kPose[4].At(t), kPose[5].At(t)); }

// w_B by central differences of R(t): [w_B]x = R^T R'.
Vector3d BodyRateAt(double t) {
  const double h = 1e-5;
  const Matrix3d R_dot = (RotationAt(t + h) - RotationAt(t - h)) / (2 * h);
  return Unskew(RotationAt(t).transpose() * R_dot);
}

TEST(PoseMotionTest, QuaternionAnglesAndRatesMatchTheAxisRotations) {
  for (double t : {0.0, 0.37, 1.2, 2.9, 4.4}) {
    TrajectoryPoint c[6];
    for (int k = 0; k < 6; ++k) {
      const Component& p = kPose[k];
      c[k] = {p.At(t), p.amplitude * p.omega * std::cos(p.omega * t + p.phase),
              -p.amplitude * p.omega * p.omega * std::sin(p.omega * t + p.phase)};
    }
    double q[7], qd[6], qdd[6];
    pose_motion::FreeCoordinates(c, q, qd, qdd);
    const Matrix3d R = Eigen::Quaterniond(q[3], q[4], q[5], q[6]).toRotationMatrix();
    EXPECT_LT((R - RotationAt(t)).norm(), 1e-15) << t;
    EXPECT_NEAR(Eigen::Vector4d(q[3], q[4], q[5], q[6]).norm(), 1.0, 1e-15);
    EXPECT_EQ(q[0], c[0].q);
    EXPECT_EQ(qd[2], c[2].qd);
    EXPECT_EQ(qdd[1], c[1].qdd);
    const Vector3d w_B(qd[3], qd[4], qd[5]);
    EXPECT_LT((w_B - BodyRateAt(t)).norm(), 1e-8) << t;
    const double h = 1e-4;
    const Vector3d w_dot_B = (BodyRateAt(t + h) - BodyRateAt(t - h)) / (2 * h);
    EXPECT_LT((Vector3d(qdd[3], qdd[4], qdd[5]) - w_dot_B).norm(), 1e-5) << t;
    // The angles back from the rotation give the same rotation.
    const Vector3d rpy = pose_motion::Angles(R);
    EXPECT_LT((Rpy(rpy(0), rpy(1), rpy(2)) - R).norm(), 1e-14);
  }
  // At pitch 90 degrees only roll - yaw is defined: the rotation still comes back.
  const Matrix3d lock = Rpy(0.3, kPi / 2, 1.1);
  const Vector3d rpy = pose_motion::Angles(lock);
  EXPECT_LT((Rpy(rpy(0), rpy(1), rpy(2)) - lock).norm(), 1e-7);
}

RigidInertia BoxInertia() {
  RigidInertia inertia;
  inertia.mass = 2.0;
  inertia.inertia_com = Vector3d(0.1, 0.2, 0.25).asDiagonal();
  return inertia;
}

// An arm with one revolute joint and a free box, as a world file gives them.
Model ArmAndBox() {
  ModelBuilder builder("world", "world");
  Joint joint;
  joint.name = "j1";
  joint.X_PJ.p = Vector3d(0, 0, 0.5);
  builder.AddMovingLink("a1", "world", joint, BoxInertia());
  Pose X_WB;
  X_WB.p = Vector3d(-1.0, 0.5, 0.25);
  X_WB.R = Rpy(0.0, 0.0, 0.6);
  builder.AddFreeLink("box", "box", X_WB, BoxInertia());
  return builder.Build();
}

std::string Sine(const Component& c) {
  char text[200];
  std::snprintf(text, sizeof text,
                "{\"sumOfSines\": {\"offset\": %.17g, \"terms\": [{\"amplitude\": %.17g, "
                "\"omega\": %.17g, \"phase\": %.17g}]}}",
                c.offset, c.amplitude, c.omega, c.phase);
  return text;
}

RunConfig ConfigOf(const Model& model, const std::string& drives, const std::string& extra = "") {
  const std::string json = "{\"durationS\": 2, \"outputIntervalS\": 0.25, " + extra +
                           "\"drives\": [{\"joint\": \"j1\", \"prescribed\": {\"trajectory\": " +
                           Sine({0.1, 0.5, 2.0, 0.0}) + "}}, " + drives + "]}";
  return ToRunConfig(ParseRunSpecJson(json, "pose.json"),
                     SpecCoordinates{PositionNames(model), VelocityNames(model)}, "pose.json");
}

std::string FullPose() {
  return "{\"joint\": \"box\", \"pose\": {\"x\": " + Sine(kPose[0]) + ", \"y\": " + Sine(kPose[1]) +
         ", \"z\": " + Sine(kPose[2]) + ", \"roll\": " + Sine(kPose[3]) +
         ", \"pitch\": " + Sine(kPose[4]) + ", \"yaw\": " + Sine(kPose[5]) + "}}";
}

TEST(PrescribedPoseTest, AKinematicRunMovesAFreeBoxAlongItsPoseWithTheWrenchNewtonEulerGives) {
  const Model model = ArmAndBox();
  const RunConfig config = ConfigOf(model, FullPose());
  const FormulationChoice choice = ValidateRun(model, config);
  EXPECT_EQ(choice.formulation, Formulation::kKinematic);  // auto: every joint prescribed
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_EQ(result.num_frames(), 9);
  ASSERT_EQ(result.positions(), 8);
  const Vector3d g(0, 0, -9.81);
  const RigidInertia inertia = BoxInertia();
  for (int f = 0; f < result.num_frames(); ++f) {
    const double t = result.t[static_cast<size_t>(f)];
    const double* q = &result.q[static_cast<size_t>(f) * 8];
    const double* qd = &result.qd[static_cast<size_t>(f) * 7];
    const double* tau = &result.tau[static_cast<size_t>(f) * 7];
    // Position and velocity of the origin, in the world.
    for (int k = 0; k < 3; ++k) {
      const Component& c = kPose[k];
      EXPECT_NEAR(q[1 + k], c.At(t), 1e-15);
      EXPECT_NEAR(qd[1 + k], c.amplitude * c.omega * std::cos(c.omega * t + c.phase), 1e-14);
    }
    const Matrix3d R = Eigen::Quaterniond(q[4], q[5], q[6], q[7]).toRotationMatrix();
    EXPECT_LT((R - RotationAt(t)).norm(), 1e-15) << t;
    EXPECT_LT((Vector3d(qd[4], qd[5], qd[6]) - BodyRateAt(t)).norm(), 1e-8) << t;
    // Newton-Euler about the centre of mass (the origin): f_W = m (a - g), n_B = I w' + w x Iw.
    Vector3d a;
    for (int k = 0; k < 3; ++k) {
      const Component& c = kPose[k];
      a(k) = -c.amplitude * c.omega * c.omega * std::sin(c.omega * t + c.phase);
    }
    const Vector3d f_W = inertia.mass * (a - g);
    const double h = 1e-4;
    const Vector3d w = BodyRateAt(t);
    const Vector3d w_dot = (BodyRateAt(t + h) - BodyRateAt(t - h)) / (2 * h);
    const Vector3d n_B = inertia.inertia_com * w_dot + w.cross(inertia.inertia_com * w);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(tau[1 + k], f_W(k), 1e-12) << "t " << t << " f"
                                             << "xyz"[k];
      EXPECT_NEAR(tau[4 + k], n_B(k), 1e-5) << "t " << t << " n"
                                            << "xyz"[k];
    }
  }
  EXPECT_LT(result.stats.quaternion_norm_error_max, 1e-15);
  EXPECT_EQ(result.stats.formulation, "kinematic");
  // The summary tracks the arm's joint against its reference, not the box's pose components
  // (no coordinate of their own: run_summary.h says < 0).
  const std::vector<JointSummary>& joints = result.stats.summary.joints;
  ASSERT_EQ(joints.size(), 7u);
  EXPECT_EQ(joints[0].tracking_error_max, 0.0);
  for (size_t j = 1; j < 7; ++j) EXPECT_LT(joints[j].tracking_error_max, 0.0) << j;
}

TEST(PrescribedPoseTest, ComponentsLeftOutAreHeldAtTheDefaultPoseOrAtInitialQ) {
  const Model model = ArmAndBox();
  // Only z moves: x, y and the default yaw of 0.6 rad are held.
  const std::string z_only = "{\"joint\": \"box\", \"pose\": {\"z\": " + Sine(kPose[2]) + "}}";
  const RunResult held = Simulate(model, ConfigOf(model, z_only));
  ASSERT_EQ(held.stats.status, RunStatus::kFinished) << held.stats.message;
  const Eigen::Quaterniond yaw(Rpy(0, 0, 0.6));
  for (int f = 0; f < held.num_frames(); ++f) {
    const double* q = &held.q[static_cast<size_t>(f) * 8];
    const double* qd = &held.qd[static_cast<size_t>(f) * 7];
    EXPECT_NEAR(q[1], -1.0, 1e-15);
    EXPECT_NEAR(q[2], 0.5, 1e-15);
    EXPECT_NEAR(q[3], kPose[2].At(held.t[static_cast<size_t>(f)]), 1e-15);
    EXPECT_NEAR(std::abs(Eigen::Quaterniond(q[4], q[5], q[6], q[7]).dot(yaw)), 1.0, 1e-15);
    for (int k = 4; k < 7; ++k) EXPECT_EQ(qd[k], 0.0);
  }
  // With initial_q, the held components are initial_q's.
  const Eigen::Quaterniond turn(Rpy(0.4, -0.2, 1.0));
  char initial[300];
  std::snprintf(initial, sizeof initial, "\"initialQ\": [0, 3, 4, 5, %.17g, %.17g, %.17g, %.17g], ",
                turn.w(), turn.x(), turn.y(), turn.z());
  const std::string yaw_only = "{\"joint\": \"box\", \"pose\": {\"yaw\": " + Sine(kPose[5]) + "}}";
  const RunResult from_q = Simulate(model, ConfigOf(model, yaw_only, initial));
  ASSERT_EQ(from_q.stats.status, RunStatus::kFinished) << from_q.stats.message;
  const double t = from_q.t.back();
  const double* q = &from_q.q[from_q.q.size() - 8];
  EXPECT_EQ(Vector3d(q[1], q[2], q[3]), Vector3d(3, 4, 5));
  const Matrix3d R = Eigen::Quaterniond(q[4], q[5], q[6], q[7]).toRotationMatrix();
  EXPECT_LT((R - Rpy(0.4, -0.2, kPose[5].At(t))).norm(), 1e-14);
}

// A bob on a ball joint whose orientation is prescribed: the joint's quaternion, the angular
// velocity and the torque that turns it (Euler's equations about the joint, gravity included).
TEST(PrescribedPoseTest, ABallJointFollowsItsPrescribedOrientation) {
  ModelBuilder builder("ball", "world");
  Pose X_PJ;
  X_PJ.p = Vector3d(0, 0, 1.0);
  RigidInertia bob;
  bob.mass = 1.5;
  bob.com = Vector3d(0.1, 0.0, -0.4);
  bob.inertia_com = Vector3d(0.02, 0.03, 0.01).asDiagonal();
  builder.AddBallLink("bob", "world", "shoulder", X_PJ, bob);
  const Model model = builder.Build();
  const std::string json =
      "{\"durationS\": 2, \"outputIntervalS\": 0.25, \"drives\": "
      "[{\"joint\": \"shoulder\", \"pose\": {\"roll\": " +
      Sine(kPose[3]) + ", \"pitch\": " + Sine(kPose[4]) + ", \"yaw\": " + Sine(kPose[5]) + "}}]}";
  const RunConfig config =
      ToRunConfig(ParseRunSpecJson(json, "ball.json"),
                  SpecCoordinates{PositionNames(model), VelocityNames(model)}, "ball.json");
  EXPECT_EQ(ValidateRun(model, config).formulation, Formulation::kKinematic);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  const Vector3d g(0, 0, -9.81);
  const Matrix3d C = Skew(bob.com);
  const Matrix3d I_O = bob.inertia_com - bob.mass * C * C;  // about the joint
  for (int f = 0; f < result.num_frames(); ++f) {
    const double t = result.t[static_cast<size_t>(f)];
    const double* q = &result.q[static_cast<size_t>(f) * 4];
    const double* qd = &result.qd[static_cast<size_t>(f) * 3];
    const double* tau = &result.tau[static_cast<size_t>(f) * 3];
    const Matrix3d R = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    EXPECT_LT((R - RotationAt(t)).norm(), 1e-15);
    const Vector3d w = BodyRateAt(t);
    EXPECT_LT((Vector3d(qd[0], qd[1], qd[2]) - w).norm(), 1e-8);
    const double h = 1e-4;
    const Vector3d w_dot = (BodyRateAt(t + h) - BodyRateAt(t - h)) / (2 * h);
    // The joint's origin is fixed: tau = I_O w' + w x I_O w - c x m R^T g (child frame).
    const Vector3d torque =
        I_O * w_dot + w.cross(I_O * w) - bob.com.cross(bob.mass * (R.transpose() * g));
    EXPECT_LT((Vector3d(tau[0], tau[1], tau[2]) - torque).norm(), 1e-5) << t;
  }
}

TEST(PrescribedPoseTest, TheSpecRecordsAPoseAndReadsItBack) {
  const Model model = ArmAndBox();
  const RunConfig config = ConfigOf(model, FullPose());
  const SpecCoordinates coordinates{PositionNames(model), VelocityNames(model)};
  const RunConfig back = ToRunConfig(ToRunSpec(config), coordinates, "recorded");
  EXPECT_TRUE(back.drives == config.drives);
  // The same motion as prescribed drives on the joint's coordinates, by name.
  const std::string by_coordinate =
      "{\"joint\": \"box.vz\", \"prescribed\": {\"trajectory\": " + Sine(kPose[2]) + "}}";
  const RunConfig z = ConfigOf(model, by_coordinate);
  const std::string z_only = "{\"joint\": \"box\", \"pose\": {\"z\": " + Sine(kPose[2]) + "}}";
  EXPECT_TRUE(z.drives == ConfigOf(model, z_only).drives);
}

std::string Refusal(const Model& model, const std::string& drives, const std::string& extra = "") {
  try {
    ValidateRun(model, ConfigOf(model, drives, extra));
  } catch (const InputError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(PrescribedPoseTest, WhatIsRefusedSaysWhatToDo) {
  const Model model = ArmAndBox();
  EXPECT_NE(Refusal(model, FullPose(), "\"formulation\": \"joint\", ")
                .find("runs in formulation kinematic only"),
            std::string::npos);
  EXPECT_NE(Refusal(model, "{\"joint\": \"j1\", \"pose\": {\"z\": " + Sine(kPose[2]) + "}}")
                .find("no free or ball joint named 'j1'; a pose drive takes one of box"),
            std::string::npos);
  EXPECT_NE(
      Refusal(model, "{\"joint\": \"box\", \"pose\": {}}").find("drives[1].pose: has no component"),
      std::string::npos);
  EXPECT_NE(
      Refusal(model, "{\"joint\": \"box.vx\", \"passive\": {}}", "\"formulation\": \"kinematic\", ")
          .find("give it a pose drive"),
      std::string::npos);
  EXPECT_NE(Refusal(model, FullPose() + ", {\"joint\": \"box.wz\", \"passive\": {}}")
                .find("already has a drive"),
            std::string::npos);
  EXPECT_NE(Refusal(model, "{\"joint\": \"box.wz\", \"torque\": {\"constant\": 1}}")
                .find("a free joint has no actuator"),
            std::string::npos);
}

}  // namespace
}  // namespace mbstream
