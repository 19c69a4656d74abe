// A heavy symmetric top on a ball joint (the Cardan expansion, ball_joint.h) in steady
// precession: its precession rate against the closed form.
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

// Mass m, centre of mass l along its symmetry axis z from the pivot, moments A (transverse,
// about the pivot) and C (axial), tilted by theta from the vertical and spinning with w3 about
// its axis: it precesses steadily about the vertical at Omega when
//   A cos(theta) Omega^2 - C w3 Omega + m g l = 0
// (Goldstein, Classical Mechanics, 5.7); the slow root is taken.
TEST(HeavyTopTest, SteadyPrecessionRateMatchesTheClosedForm) {
  const double m = 2.0, l = 0.1, g = 9.81, theta = std::numbers::pi / 6, w3 = 100.0;
  const double A_cm = 0.004, C = 0.006;
  const double A = A_cm + m * l * l;
  const double disc = C * C * w3 * w3 - 4.0 * A * std::cos(theta) * m * g * l;
  ASSERT_GT(disc, 0.0);
  const double Omega = (C * w3 - std::sqrt(disc)) / (2.0 * A * std::cos(theta));

  ModelBuilder builder("top", "world");
  RigidInertia top;
  top.mass = m;
  top.com = Vector3d(0, 0, l);
  top.inertia_com = Vector3d(A_cm, A_cm, C).asDiagonal();
  const std::string axes[3] = {"ball.x", "ball.y", "ball.z"};
  builder.AddBallLink("top", "world", "ball", "test", Pose::Identity(), axes, top);
  builder.SetGravity(Vector3d(0, 0, -g));
  const Model model = builder.Build();
  const DriveSet drives(model, std::vector<DriveConfig>(3));
  JointSpaceOde ode(model, drives);

  // R = Rx(theta) (precession angle 0, spin angle 0): Cardan angles (theta, 0, 0). Angular
  // velocity (world) Omega e_z + s axis, s = w3 - Omega cos(theta) the spin rate; the Cardan
  // rates from w = a' e_x + b' Rx(a) e_y + c' Rx(a) Ry(b) e_z.
  const Matrix3d Rx = AxisAngleRotation(Vector3d::UnitX(), theta);
  const Vector3d axis = Rx.col(2);
  const Vector3d w = Omega * Vector3d::UnitZ() + (w3 - Omega * std::cos(theta)) * axis;
  Matrix3d J;
  J.col(0) = Vector3d::UnitX();
  J.col(1) = Rx.col(1);
  J.col(2) = Rx.col(2);
  Eigen::VectorXd y(6);
  y << theta, 0, 0, J.partialPivLu().solve(w);

  IntegratorOptions options;
  options.method = Method::kBdf;
  options.rtol = 1e-12;
  options.atol = 1e-14;
  auto integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  Data data(model);
  const int body = model.FindBody("top");
  // About a quarter turn of precession, unwrapped frame by frame.
  const double T = 0.5 * std::numbers::pi / Omega;
  double phi = 0.0, tilt_error = 0.0;
  const int frames = 200;
  for (int k = 1; k <= frames; ++k) {
    const double t = T * k / frames;
    ASSERT_EQ(integrator->AdvanceTo(t, y.data()).status, IntegratorStatus::kOk);
    ForwardKinematics(model, data, y.head(3));
    const Vector3d z = data.X_world[body].R.col(2);  // (sin phi sin theta, -cos phi sin theta, ..)
    phi = std::atan2(z.x(), -z.y());
    tilt_error = std::max(tilt_error, std::abs(std::acos(z.z()) - theta));
  }
  std::printf(
      "precession: closed form %.12f rad/s, simulated %.12f rad/s (relative %.2e); tilt "
      "kept to %.2e rad\n",
      Omega, phi / T, phi / T / Omega - 1.0, tilt_error);
  EXPECT_NEAR(phi / T / Omega, 1.0, 1e-6);
  EXPECT_LT(tilt_error, 1e-6);
}

}  // namespace
}  // namespace mbstream
