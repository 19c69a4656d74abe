// Free bodies through the joint-space ODE and the integrators, against closed forms: the
// torque-free asymmetric body near its intermediate axis (the Dzhanibekov flip: conserved
// energy and world angular momentum, the flip period by the complete elliptic integral), the
// projectile, the unit quaternion under every method, and a floating-base tree whose driven
// joints conserve its momentum.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/dynamics/energy.h"
#include "server/integrate/integrator.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/sim/joint_space_ode.h"
#include "tests/server/free/free_run.h"
#include "tests/server/free/free_tree_model.h"

namespace mbstream {
namespace {

using testing::FreeRun;

RigidInertia Principal(double mass, const Vector3d& moments) {
  RigidInertia inertia;
  inertia.mass = mass;
  inertia.inertia_com = moments.asDiagonal();
  return inertia;
}

Model LoneBody(const RigidInertia& inertia, const Vector3d& gravity) {
  ModelBuilder builder("body", "world");
  builder.AddFreeLink("body", "body", Pose::Identity(), inertia);
  builder.SetGravity(gravity);
  return builder.Build();
}

// Total spatial momentum in the world, [angular about the world origin; linear], at the ODE's
// outputs (q(), qd()).
Vector6d WorldMomentum(const Model& model, Data& data, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd) {
  ForwardKinematics(model, data, q);
  KineticEnergyAfterKinematics(model, data, qd);  // data.v
  Vector6d h = Vector6d::Zero();
  for (int i = 0; i < model.num_bodies(); ++i) {
    h += ForceToParent(data.X_world[i], model.bodies[i].inertia.Apply(data.v[i]));
  }
  return h;
}

double QuaternionNormError(const Model& model, const double* q) {
  double worst = 0.0;
  for (const int b : model.free_bodies) {
    const double* quat = q + model.bodies[b].q_index + 3;
    const double norm =
        std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
    worst = std::max(worst, std::abs(norm - 1.0));
  }
  return worst;
}

// The Dzhanibekov flip: I1 < I2 < I3, spun about axis 2 with small components about 1 and 3,
// M^2 > 2 E I2 (Landau and Lifshitz, Mechanics, 37). Then w2 = w2max sn(tau, k) with tau = lambda
// t, lambda = sqrt((I3 - I2)(M^2 - 2 E I1) / (I1 I2 I3)),
// k^2 = (I2 - I1)(2 E I3 - M^2) / ((I3 - I2)(M^2 - 2 E I1)): w2 changes sign (the body flips)
// every 2 K(k) / lambda.
TEST(FreeMotionTest, DzhanibekovFlipConservesEnergyAndMomentumAndKeepsItsPeriod) {
  const Vector3d I(1.0, 2.0, 3.0);
  FreeRun run(LoneBody(Principal(1.0, I), Vector3d::Zero()));
  const Vector3d w0(0.01, 3.0, 0.02);
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(13);
  y0(3) = 1.0;
  y0.tail<3>() = w0;
  const double E = 0.5 * w0.dot(I.cwiseProduct(w0));
  const double M2 = I.cwiseProduct(w0).squaredNorm();
  ASSERT_GT(M2, 2 * E * I(1));
  const double lambda = std::sqrt((I(2) - I(1)) * (M2 - 2 * E * I(0)) / (I.prod()));
  const double k2 = (I(1) - I(0)) * (2 * E * I(2) - M2) / ((I(2) - I(1)) * (M2 - 2 * E * I(0)));
  const double flip = 2.0 * std::comp_ellint_1(std::sqrt(k2)) / lambda;
  ASSERT_LT(flip, 7.0);  // at least two flips in 20 s

  run.Start(y0, Method::kErk, 1e-10);
  Data data(run.model);
  const Vector6d h0 = WorldMomentum(run.model, data, y0.head(7), y0.tail(6));
  const double dt = 1e-3;
  double worst_energy = 0.0, worst_momentum = 0.0, worst_norm = 0.0;
  std::vector<double> crossings;
  double t_prev = 0.0, w2_prev = w0(1), dw2_prev = (I(2) - I(0)) / I(1) * w0(2) * w0(0);
  for (int k = 1; k <= 20000; ++k) {
    const double t = k * dt;
    run.AdvanceTo(t);
    const Eigen::VectorXd& q = run.ode.q();
    const Eigen::VectorXd& qd = run.ode.qd();
    const Vector3d w = qd.tail<3>();
    worst_energy = std::max(worst_energy, std::abs(0.5 * w.dot(I.cwiseProduct(w)) - E) / E);
    const Vector6d h = WorldMomentum(run.model, data, q, qd);
    worst_momentum = std::max(worst_momentum, (h.head<3>() - h0.head<3>()).norm() / h0.norm());
    worst_norm = std::max(worst_norm, QuaternionNormError(run.model, q.data()));
    // Euler: I2 w2' = (I3 - I1) w3 w1; a sign change of w2 located by the cubic Hermite
    // interpolant of (w2, w2') over the output interval.
    const double w2 = w(1), dw2 = (I(2) - I(0)) / I(1) * w(2) * w(0);
    if ((w2 > 0) != (w2_prev > 0)) {
      double a = 0.0, b = 1.0;
      auto hermite = [&](double s) {
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * w2_prev + (s3 - 2 * s2 + s) * dt * dw2_prev +
               (-2 * s3 + 3 * s2) * w2 + (s3 - s2) * dt * dw2;
      };
      for (int it = 0; it < 60; ++it) {
        const double m = 0.5 * (a + b);
        ((hermite(m) > 0) == (w2_prev > 0) ? a : b) = m;
      }
      crossings.push_back(t_prev + 0.5 * (a + b) * dt);
    }
    t_prev = t;
    w2_prev = w2;
    dw2_prev = dw2;
  }
  EXPECT_LT(worst_energy, 1e-9);
  EXPECT_LT(worst_momentum, 1e-9);
  EXPECT_LT(worst_norm, 1e-12);
  ASSERT_GE(crossings.size(), 2u);
  // The first flip is at K / lambda (w2 = w2max sn(tau + K) from its maximum at t = 0).
  for (size_t j = 1; j < crossings.size(); ++j) {
    EXPECT_NEAR((crossings[j] - crossings[j - 1]) / flip, 1.0, 1e-6) << "flip " << j;
  }
  RecordProperty("flip_period_s", std::to_string(flip));
  std::printf(
      "flip period %.9f s (closed form), %zu flips; energy %.2e, momentum %.2e, "
      "|quat| - 1 %.2e\n",
      flip, crossings.size(), worst_energy, worst_momentum, worst_norm);
  for (size_t j = 1; j < crossings.size(); ++j) {
    std::printf("  flip %zu: %.9f s, relative error %.2e\n", j, crossings[j] - crossings[j - 1],
                (crossings[j] - crossings[j - 1]) / flip - 1.0);
  }
}

// A spinning body thrown: its centre of mass is on the parabola p0 + v0 t + g t^2 / 2.
TEST(FreeMotionTest, ProjectileCentreOfMassStaysOnTheParabola) {
  const Vector3d g(0.0, 0.0, -9.81);
  for (const Method method : {Method::kRk4, Method::kBdf}) {
    FreeRun run(LoneBody(Principal(2.0, Vector3d(0.1, 0.2, 0.25)), g));
    Eigen::VectorXd y0 = Eigen::VectorXd::Zero(13);
    y0.head<3>() = Vector3d(0.1, -0.2, 1.0);
    y0(3) = 1.0;
    const Vector3d v0(1.0, 2.0, 8.0);
    y0.segment<3>(7) = v0;
    y0.tail<3>() = Vector3d(3.0, -1.0, 5.0);  // tumbling
    run.Start(y0, method, 1e-12);
    double worst = 0.0;
    for (int k = 1; k <= 200; ++k) {
      const double t = 0.01 * k;
      run.AdvanceTo(t);
      const Vector3d com = run.ode.q().head<3>();  // the body origin is its centre of mass
      const Vector3d parabola = y0.head<3>() + v0 * t + 0.5 * g * t * t;
      worst = std::max(worst, (com - parabola).norm());
    }
    std::printf("%s: centre of mass off the parabola by %.2e m at most\n", MethodName(method),
                worst);
    EXPECT_LT(worst, 1e-12) << MethodName(method);
  }
}

// Every method keeps a tumbling body's quaternion unit at the outputs (the ODE normalises what
// it reads). The fixed-step methods' output states are projected steps: unit too. The adaptive
// methods' outputs interpolate between projected steps (CVODE Adams' do not project): their
// raw states are printed.
TEST(FreeMotionTest, QuaternionStaysUnitWithEveryMethod) {
  for (const Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    FreeRun run(LoneBody(Principal(1.0, Vector3d(1.0, 2.0, 3.0)), Vector3d(0, 0, -9.81)));
    Eigen::VectorXd y0 = Eigen::VectorXd::Zero(13);
    y0(3) = 1.0;
    y0.tail<3>() = Vector3d(2.0, -3.0, 4.0);
    run.Start(y0, method, 1e-8, 1e-3);
    double state = 0.0, output = 0.0;
    for (int k = 1; k <= 100; ++k) {
      run.AdvanceTo(0.05 * k);
      state = std::max(state, QuaternionNormError(run.model, run.y.data()));
      output = std::max(output, QuaternionNormError(run.model, run.ode.q().data()));
    }
    std::printf("%-6s | |quat| - 1 |: state %.2e, outputs %.2e\n", MethodName(method), state,
                output);
    EXPECT_LT(output, 1e-12) << MethodName(method);
    if (method == Method::kRk4 || method == Method::kEuler) {
      EXPECT_LT(state, 1e-12) << MethodName(method);
    }
  }
}

// A floating-base tree in zero gravity, its joints driven by servos (internal forces only):
// its total linear and angular momentum stay what they were.
TEST(FreeMotionTest, DrivenFloatingTreeConservesMomentumInZeroGravity) {
  std::mt19937 rng(8);
  // No rotor inertia: a rotor's reaction on its stator is not modelled, so it would carry
  // momentum the bodies do not.
  Model model = testing::FloatingTree(rng, /*armature=*/0.0);
  model.gravity.setZero();
  // The free bodies' joints driven; the fixed-base arm (arm1, arm2) exchanges no force with
  // them and is counted out of the momentum.
  std::vector<DriveConfig> drives(model.nv());
  for (const Body& body : model.bodies) {
    if (body.free() || body.parent == kBase) continue;
    drives[body.v_index] = testing::SineServo(20.0, 1.0, 0.2, 0.5, 3.0);
  }
  FreeRun run(model, drives);
  Eigen::VectorXd y0(model.nq() + model.nv());
  y0.head(model.nq()) = testing::RandomPositions(model, rng);
  y0.tail(model.nv()) = testing::RandomVelocities(model, rng, 1.0);
  run.Start(y0, Method::kErk, 1e-10);
  Data data(model);
  // The fixed-base arm (arm1, arm2) exchanges no force with the free bodies: counted out.
  const auto momentum = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    return testing::SpatialMomentum(model, data, q, qd, {"arm1", "arm2"});
  };
  Eigen::VectorXd q0 = y0.head(model.nq()), qd0 = y0.tail(model.nv());
  const Vector6d h0 = momentum(q0, qd0);
  double worst_angular = 0.0, worst_linear = 0.0;
  for (int k = 1; k <= 200; ++k) {
    run.AdvanceTo(0.01 * k);
    const Vector6d h = momentum(run.ode.q(), run.ode.qd());
    worst_angular = std::max(worst_angular, (h.head<3>() - h0.head<3>()).norm() / h0.norm());
    worst_linear = std::max(worst_linear, (h.tail<3>() - h0.tail<3>()).norm() / h0.norm());
  }
  std::printf("driven floating tree, 2 s: momentum change angular %.2e, linear %.2e (relative)\n",
              worst_angular, worst_linear);
  EXPECT_LT(worst_angular, 1e-9);
  EXPECT_LT(worst_linear, 1e-9);
}

}  // namespace
}  // namespace mbstream
