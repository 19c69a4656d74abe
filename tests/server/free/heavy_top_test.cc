// A heavy symmetric top on a ball joint (JointType::kBall: a quaternion, the angular velocity
// in the top's frame) in steady precession: its precession rate against the closed form, at a
// tilt of 30 degrees and lying horizontal, where its axis sweeps through the joint frame's x
// axis (the Cardan angles' former gimbal lock, q_y = 90 degrees) once per turn.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "server/drives/drive_set.h"
#include "server/integrate/integrator.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/model_builder.h"
#include "server/sim/joint_space_ode.h"

namespace mbstream {
namespace {

struct Top {
  double m = 2.0, l = 0.1, g = 9.81, w3 = 100.0;
  double A_cm = 0.004, C = 0.006;
  double A() const { return A_cm + m * l * l; }  // transverse moment about the pivot
};

Model TopModel(const Top& top) {
  ModelBuilder builder("top", "world");
  RigidInertia inertia;
  inertia.mass = top.m;
  inertia.com = Vector3d(0, 0, top.l);
  inertia.inertia_com = Vector3d(top.A_cm, top.A_cm, top.C).asDiagonal();
  builder.AddBallLink("top", "world", "ball", Pose::Identity(), inertia);
  builder.SetGravity(Vector3d(0, 0, -top.g));
  return builder.Build();
}

struct Precession {
  double rate = 0.0;           // simulated, rad/s
  double tilt_error = 0.0;     // rad
  double norm_error = 0.0;     // | |quat| - 1 | of the raw states
  double closest_to_x = 10.0;  // the smallest |axis - e_x| over the frames
};

// The top tilted by theta about x (axis z in the y-z plane) precessing about the vertical at
// Omega with spin component w3 along its axis, integrated by BDF (with projection) over a
// quarter of a precession turn (`turns` = 0.25) or more; its axis's azimuth unwrapped.
Precession Precess(const Top& top, double theta, double Omega, double turns) {
  const Model model = TopModel(top);
  const DriveSet drives(model, std::vector<DriveConfig>(3));
  JointSpaceOde ode(model, drives);
  // R = Rx(theta): quat (cos theta/2, sin theta/2, 0, 0). Angular velocity (world)
  // Omega e_z + s axis with s = w3 - Omega cos(theta), in the top's frame R^T w.
  const Matrix3d R = AxisAngleRotation(Vector3d::UnitX(), theta);
  const Vector3d w = Omega * Vector3d::UnitZ() + (top.w3 - Omega * std::cos(theta)) * R.col(2);
  const Vector3d w_B = R.transpose() * w;
  Eigen::VectorXd y(7);
  y << std::cos(theta / 2), std::sin(theta / 2), 0, 0, w_B;

  IntegratorOptions options;
  options.method = Method::kBdf;
  options.rtol = 1e-12;
  options.atol = 1e-14;
  auto integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  Data data(model);
  const int body = model.FindBody("top");
  const double T = turns * 2.0 * std::numbers::pi / Omega;
  const int frames = static_cast<int>(800 * turns);
  Precession result;
  double phi = 0.0, last = 0.0;
  for (int k = 1; k <= frames; ++k) {
    const double t = T * k / frames;
    EXPECT_EQ(integrator->AdvanceTo(t, y.data()).status, IntegratorStatus::kOk) << t;
    result.norm_error = std::max(result.norm_error, std::abs(y.head(4).norm() - 1.0));
    ForwardKinematics(model, data, y.head(4));
    const Vector3d z = data.X_world[body].R.col(2);  // (sin phi sin theta, -cos phi sin theta, ..)
    const double azimuth = std::atan2(z.x(), -z.y());
    double step = azimuth - last;
    step -= 2.0 * std::numbers::pi * std::round(step / (2.0 * std::numbers::pi));
    phi += step;
    last = azimuth;
    result.tilt_error = std::max(result.tilt_error, std::abs(std::acos(z.z()) - theta));
    result.closest_to_x = std::min(result.closest_to_x, (z - Vector3d::UnitX()).norm());
  }
  result.rate = phi / T;
  return result;
}

// Mass m, centre of mass l along its symmetry axis z from the pivot, moments A (transverse,
// about the pivot) and C (axial), tilted by theta from the vertical and spinning with w3 about
// its axis: it precesses steadily about the vertical at Omega when
//   A cos(theta) Omega^2 - C w3 Omega + m g l = 0
// (Goldstein, Classical Mechanics, 5.7); the slow root is taken.
TEST(HeavyTopTest, SteadyPrecessionRateMatchesTheClosedForm) {
  const Top top;
  const double theta = std::numbers::pi / 6;
  const double a = top.A() * std::cos(theta), b = top.C * top.w3, c = top.m * top.g * top.l;
  ASSERT_GT(b * b - 4.0 * a * c, 0.0);
  const double Omega = (b - std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
  const Precession p = Precess(top, theta, Omega, 0.25);
  std::printf(
      "precession at 30 deg: closed form %.12f rad/s, simulated %.12f rad/s (relative %.2e); "
      "tilt kept to %.2e rad; raw |quat| - 1 at most %.2e\n",
      Omega, p.rate, p.rate / Omega - 1.0, p.tilt_error, p.norm_error);
  EXPECT_NEAR(p.rate / Omega, 1.0, 1e-6);
  EXPECT_LT(p.tilt_error, 1e-6);
  EXPECT_LT(p.norm_error, 1e-9);
}

// Lying horizontal (theta = 90 degrees) the closed form is Omega = m g l / (C w3); its axis
// sweeps the horizontal plane, through the joint frame's x axis, where the Cardan expansion
// locked (its middle angle at 90 degrees). A whole turn: the quaternion joint goes through.
TEST(HeavyTopTest, AHorizontalTopPrecessesThroughTheFormerGimbalLock) {
  const Top top;
  const double theta = std::numbers::pi / 2;
  const double Omega = top.m * top.g * top.l / (top.C * top.w3);
  const Precession p = Precess(top, theta, Omega, 1.0);
  std::printf(
      "horizontal top: closed form %.12f rad/s, simulated %.12f rad/s (relative %.2e); tilt "
      "kept to %.2e rad; its axis came within %.2e of the joint frame's x axis\n",
      Omega, p.rate, p.rate / Omega - 1.0, p.tilt_error, p.closest_to_x);
  EXPECT_NEAR(p.rate / Omega, 1.0, 1e-6);
  EXPECT_LT(p.tilt_error, 1e-6);
  EXPECT_LT(p.closest_to_x, 0.01);  // 800 frames a turn: within 2 pi / 800 of it
}

}  // namespace
}  // namespace mbstream
