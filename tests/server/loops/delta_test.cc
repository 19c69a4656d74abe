// The Delta robot (models/linkages/delta.sdf): three arms closed on a platform by
// parallelograms whose rods meet the platform at ball joints (five of them cut). Checked
// against the Delta's closed-form inverse kinematics (a kinematic run), the platform kept
// parallel to the base, and a passive run's energy.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "server/kinematics/forward_kinematics.h"
#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"

namespace mbstream {
namespace {

const std::string kDelta = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/delta.sdf";

// models/linkages/generate.py's DELTA, m: base and platform radii, arm, rod, the
// parallelogram's half width, the platform's height as drawn.
constexpr double kBaseR = 0.2, kPlatformR = 0.05, kArm = 0.25, kRod = 0.5, kHalfWidth = 0.03,
                 kZ0 = -0.45;

// The closed form: leg i's motor angle (the arm below the horizontal, rad) that puts the
// platform's centre at p; the elbow-out branch. Each leg: |p + (r - R) u - B_arm| = rod.
double DeltaIk(const Vector3d& p, int leg) {
  const double g = 2.0 * M_PI * leg / 3.0;
  const Vector3d u(std::cos(g), std::sin(g), 0.0), t(-std::sin(g), std::cos(g), 0.0);
  const Vector3d d = p + (kPlatformR - kBaseR) * u;
  const double a = d.dot(u), b = d.dot(t), c = d.z();
  const double k = (a * a + b * b + c * c + kArm * kArm - kRod * kRod) / (2.0 * kArm);
  const double base = std::atan2(-c, a), spread = std::acos(k / std::hypot(a, c));
  return std::cos(base - spread) > std::cos(base + spread) ? base - spread : base + spread;
}

int JointIndex(const Model& model, const std::string& name) {
  for (int i = 0; i < model.num_dofs(); ++i) {
    if (model.bodies[i].joint.name == name) return i;
  }
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

struct PlatformPose {
  Vector3d centre;
  double tilt = 0.0;  // rad, the platform's rotation from its drawn orientation
};

// The platform's centre and tilt at tree coordinates q. Its body frame is the wrist's joint
// frame, drawn at the centre + (r, w, 0) and aligned with the model frame.
PlatformPose Platform(const Model& model, Data& data, const double* q) {
  const Eigen::VectorXd tree = Eigen::Map<const Eigen::VectorXd>(q, model.num_dofs());
  ForwardKinematics(model, data, tree);
  const Pose& X = data.X_world[model.FindBody("platform")];
  PlatformPose pose;
  pose.centre = X.p - X.R * Vector3d(kPlatformR, kHalfWidth, 0.0);
  pose.tilt = Eigen::AngleAxisd(X.R).angle();
  return pose;
}

RunConfig DeltaConfig(const Model& model) {
  RunConfig config;
  config.duration = 1.0;
  config.output_interval = 0.01;
  config.drives.assign(model.num_dofs(), DriveConfig{});
  config.rtol = 1e-9;
  config.atol = 1e-11;
  return config;
}

TEST(DeltaTest, TheKinematicRunMatchesTheClosedFormInverseKinematicsAndKeepsThePlatformLevel) {
  const SdfImport sdf = ImportSdfFile(kDelta);
  ASSERT_EQ(sdf.loops.size(), 5u);
  RunConfig config = DeltaConfig(sdf.model);
  const int motors[3] = {JointIndex(sdf.model, "motor1"), JointIndex(sdf.model, "motor2"),
                         JointIndex(sdf.model, "motor3")};
  for (int leg = 0; leg < 3; ++leg) {  // each motor 0.2 rad about the drawn pose, a third apart
    DriveConfig& drive = config.drives[motors[leg]];
    drive.kind = DriveConfig::Kind::kPrescribed;
    drive.trajectory.amplitude = {0.2};
    drive.trajectory.omega = {M_PI};
    drive.trajectory.phase = {2.0 * M_PI * leg / 3.0};
  }
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  EXPECT_EQ(result.stats.loops.equations, 15);
  EXPECT_EQ(result.stats.loops.mobility, 3);
  // The tree's joints, then each ball joint's three columns.
  EXPECT_EQ(result.num_dofs, sdf.model.num_dofs() + 15);
  EXPECT_EQ(result.joint_names.back(), "ball3b.z");
  Data data(sdf.model);
  const Vector3d drawn(0.0, 0.0, kZ0);
  double worst_ik = 0.0, worst_tilt = 0.0, travel = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const double* q = &result.q[static_cast<size_t>(k) * result.num_dofs];
    const PlatformPose pose = Platform(sdf.model, data, q);
    worst_tilt = std::max(worst_tilt, pose.tilt);
    travel = std::max(travel, (pose.centre - drawn).norm());
    for (int leg = 0; leg < 3; ++leg) {
      const double motor = DeltaIk(drawn, leg) + q[motors[leg]];
      worst_ik = std::max(worst_ik, std::abs(DeltaIk(pose.centre, leg) - motor));
    }
  }
  EXPECT_GT(travel, 0.02);  // the platform moves
  EXPECT_LT(worst_ik, 1e-9);
  EXPECT_LT(worst_tilt, 1e-9);
  EXPECT_LT(result.stats.drift_position_max, 1e-11);
}

TEST(DeltaTest, ThePassiveDeltaFallsWithItsEnergyKeptAndItsPlatformLevel) {
  const SdfImport sdf = ImportSdfFile(kDelta);
  RunConfig config = DeltaConfig(sdf.model);
  // Released at rest, every joint passive, it falls from the drawn pose. At t = 0.2923 s
  // its rods are all parallel, a singular pose of the mechanism where the run stops
  // (delta_singularity_test.cc, docs/closed_loops.md), so 0.15 s of it.
  config.duration = 0.15;
  config.output_interval = 0.005;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "joint");
  EXPECT_LT(result.stats.energy_error_max, 1e-6);
  EXPECT_LT(result.stats.drift_position_max, 1e-9);
  Data data(sdf.model);
  double worst_tilt = 0.0, drop = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    const PlatformPose pose =
        Platform(sdf.model, data, &result.q[static_cast<size_t>(k) * result.num_dofs]);
    worst_tilt = std::max(worst_tilt, pose.tilt);
    drop = std::max(drop, kZ0 - pose.centre.z());
  }
  EXPECT_GT(drop, 0.01);
  EXPECT_LT(worst_tilt, 1e-8);
}

}  // namespace
}  // namespace mbstream
