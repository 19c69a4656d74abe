// The joint-space ODE: the partitioned dynamics of mixed prescribed/free joints, and no
// heap allocation in a time step.
#include "server/sim/joint_space_ode.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "server/drives/trajectory.h"
#include "server/dynamics/rnea.h"
#include "server/integrate/integrator.h"
#include "server/kinematics/joint_transform.h"
#include "server/parse/urdf_import.h"
#include "server/sim/integrator_options_from.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

DriveConfig SineDrive(double amplitude, double omega) {
  DriveConfig drive;
  drive.kind = DriveConfig::Kind::kPrescribed;
  drive.trajectory.amplitude = {amplitude};
  drive.trajectory.omega = {omega};
  drive.trajectory.phase = {0.3};
  return drive;
}

TEST(JointSpaceOdeTest, MixedPrescribedAndFreeJointsSatisfyTheEquationsOfMotion) {
  const Model model = ImportUrdfFile("models/pendulum/double_pendulum.urdf").model;
  ASSERT_EQ(model.num_dofs(), 2);
  RunConfig config;
  config.drives = {SineDrive(0.8, 2.0), DriveConfig{}};  // joint 1 prescribed, joint 2 free
  const DriveSet drives(model, config.drives);
  JointSpaceOde ode(model, drives);
  const double y[4] = {0.1, -0.4, 0.2, 1.5};
  const double t = 0.7;
  ASSERT_TRUE(ode.Evaluate(t, y));
  ode.ComputePrescribedEfforts();
  // The prescribed joint follows its reference; the free joint keeps the state.
  const TrajectoryPoint ref = drives.Reference(0, t);
  EXPECT_DOUBLE_EQ(ode.q()(0), ref.q);
  EXPECT_DOUBLE_EQ(ode.qd()(0), ref.qd);
  EXPECT_DOUBLE_EQ(ode.qdd()(0), ref.qdd);
  EXPECT_DOUBLE_EQ(ode.q()(1), -0.4);
  // Inverse dynamics of the result: zero effort on the free joint, the drive's on joint 1.
  Data data(model);
  const Eigen::VectorXd tau = Rnea(model, data, ode.q(), ode.qd(), ode.qdd());
  EXPECT_NEAR(tau(1), 0.0, 1e-12);
  EXPECT_NEAR(tau(0), ode.drive_effort()(0), 1e-12);
  EXPECT_GT(std::abs(tau(0)), 1e-3);
}

TEST(JointSpaceOdeTest, SplineTrajectoryInterpolatesItsKnots) {
  Trajectory spline;
  spline.kind = Trajectory::Kind::kSpline;
  spline.times = {0.0, 0.5, 1.5, 2.0};
  spline.values = {0.0, 1.0, -1.0, 0.5};
  const TrajectoryEvaluator evaluator(spline);
  for (size_t k = 0; k < spline.times.size(); ++k) {
    EXPECT_NEAR(evaluator.At(spline.times[k]).q, spline.values[k], 1e-14);
  }
  // C2 at an inner knot, natural (zero curvature) at the ends, held outside.
  const double h = 1e-7;
  EXPECT_NEAR(evaluator.At(0.5 - h).qd, evaluator.At(0.5 + h).qd, 1e-5);
  EXPECT_NEAR(evaluator.At(0.5 - h).qdd, evaluator.At(0.5 + h).qdd, 1e-5);
  EXPECT_NEAR(evaluator.At(1e-12).qdd, 0.0, 1e-9);
  EXPECT_EQ(evaluator.At(3.0).q, 0.5);
  EXPECT_EQ(evaluator.At(3.0).qd, 0.0);
  // The derivative is the derivative of the value.
  const double t = 1.1;
  EXPECT_NEAR(evaluator.At(t).qd, (evaluator.At(t + h).q - evaluator.At(t - h).q) / (2 * h), 1e-6);
}

// The ODE's own Jacobian (seed-servo: every joint a PD servo) against central differences
// of its right-hand side, and no allocation in it.
TEST(JointSpaceOdeTest, JacobianMatchesDifferencesOfTheRightHandSide) {
  const Model& model = testing::Irb1600();
  const RunConfig config = testing::Scene("seed-servo");
  const DriveSet drives(model, config.drives);
  JointSpaceOde ode(model, drives);
  ASSERT_TRUE(ode.HasJacobian());
  const int size = ode.size();
  std::vector<double> y(size), fy(size), jac(size * size), yp, fp(size), fm(size);
  for (int i = 0; i < 6; ++i) {
    y[i] = 0.3 * (i + 1) - 0.7;
    y[6 + i] = 0.8 - 0.25 * i;
  }
  const double t = 1.3;
  ASSERT_EQ(ode.Rhs(t, y.data(), fy.data()), 0);
  const long before = testing::AllocationCount();
  ASSERT_EQ(ode.Jacobian(t, y.data(), fy.data(), jac.data()), 0);
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  double max_abs = 0.0;
  for (double v : jac) max_abs = std::max(max_abs, std::abs(v));
  for (int j = 0; j < size; ++j) {
    const double h = 1e-6;
    yp = y;
    yp[j] += h;
    ASSERT_EQ(ode.Rhs(t, yp.data(), fp.data()), 0);
    yp[j] -= 2 * h;
    ASSERT_EQ(ode.Rhs(t, yp.data(), fm.data()), 0);
    for (int i = 0; i < size; ++i) {
      const double fd = (fp[i] - fm[i]) / (2 * h);
      EXPECT_NEAR(jac[j * size + i], fd, 1e-6 * max_abs + 1e-6 * std::abs(fd))
          << "row " << i << " column " << j;
    }
  }
  // Columns of q' = qd: exactly [0 I].
  for (int j = 0; j < size; ++j) {
    for (int i = 0; i < 6; ++i) EXPECT_EQ(jac[j * size + i], j == 6 + i ? 1.0 : 0.0);
  }
  // A prescribed joint: the ODE leaves the Jacobian to the integrator.
  RunConfig mixed = config;
  mixed.drives[0].kind = DriveConfig::Kind::kPrescribed;
  const DriveSet mixed_drives(model, mixed.drives);
  EXPECT_FALSE(JointSpaceOde(model, mixed_drives).HasJacobian());
}

TEST(JointSpaceOdeTest, TimeStepsDoNotAllocate) {
  const Model& model = testing::Irb1600();
  const RunConfig config = testing::Scene("seed-servo");
  const DriveSet drives(model, config.drives);
  JointSpaceOde ode(model, drives);
  std::vector<double> y(12, 0.1), ydot(12, 0.0);
  const long before = testing::AllocationCount();
  for (int k = 0; k < 10; ++k) ASSERT_EQ(ode.Rhs(0.01 * k, y.data(), ydot.data()), 0);
  EXPECT_EQ(testing::AllocationCount() - before, 0);

  // Whole integrator steps: after the first output, advancing allocates nothing, with the
  // work appended as a quadrature too (as every driven run has it), reading it included.
  JointSpaceOde tracked(model, drives, /*track_work=*/true);
  for (JointSpaceOde* system : {&ode, &tracked}) {
    for (Method method : {Method::kBdf, Method::kErk, Method::kDirk, Method::kRk4}) {
      RunConfig c = config;
      c.method = method;
      c.fixed_step = 1e-4;  // the wrist servo (kd / J ~ 2e4 1/s) needs it for RK4
      std::unique_ptr<Integrator> integrator =
          MakeIntegrator(*system, 0.0, y.data(), IntegratorOptionsFrom(c, 2.0));
      std::vector<double> state = y;
      double work = 0.0;
      ASSERT_EQ(integrator->AdvanceTo(0.05, state.data()).status, IntegratorStatus::kOk);
      const long start = testing::AllocationCount();
      for (int k = 2; k <= 20; ++k) {
        ASSERT_EQ(integrator->AdvanceTo(0.05 * k, state.data()).status, IntegratorStatus::kOk);
        EXPECT_EQ(integrator->Quadratures(&work), system == &tracked);
      }
      EXPECT_EQ(testing::AllocationCount() - start, 0)
          << MethodName(method) << (system == &tracked ? " with the work" : "");
      EXPECT_GT(integrator->stats().steps, 20);
    }
  }
}

}  // namespace
}  // namespace mbstream
