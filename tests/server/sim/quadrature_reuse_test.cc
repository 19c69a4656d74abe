// The work quadrature reuses the right-hand side's dynamics: with tracked work and
// prescribed joints, one evaluation of the dynamics per right-hand side (not two), and the
// same results bit for bit as calling Rhs and Quadrature separately.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "server/integrate/appended_quadratures.h"
#include "server/integrate/integrator.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

// The damped IRB 1600 with joints 1, 3, 5 (0-based) prescribed by the seed's sine laws and
// the others passive: tracked work, and the prescribed joints' efforts need the dynamics.
struct MixedScene {
  MixedScene() : model(Irb1600()) {
    for (Body& body : model.bodies) body.joint.damping = 5.0;
    config = Scene("seed-run");
    config.duration = 1.0;
    for (size_t i = 0; i < config.drives.size(); i += 2) {
      config.drives[i] = DriveConfig{};  // passive
    }
  }
  Model model;
  RunConfig config;
};

// Forwards everything to a JointSpaceOde but RhsAndQuadrature, so the appended quadratures
// call Rhs and Quadrature separately: what they did before.
class SeparateCalls : public OdeSystem {
 public:
  explicit SeparateCalls(JointSpaceOde& ode) : ode_(ode) {}
  int size() const override { return ode_.size(); }
  int Rhs(double t, const double* y, double* ydot) override { return ode_.Rhs(t, y, ydot); }
  int num_positions() const override { return ode_.num_positions(); }
  int num_quadratures() const override { return ode_.num_quadratures(); }
  int Quadrature(double t, const double* y, double* qdot) override {
    return ode_.Quadrature(t, y, qdot);
  }

 private:
  JointSpaceOde& ode_;
};

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(QuadratureReuseTest, OneDynamicsEvaluationPerRightHandSide) {
  const MixedScene scene;
  const DriveSet drives(scene.model, scene.config.drives);
  ASSERT_EQ(drives.num_prescribed(), 3);
  JointSpaceOde fused(scene.model, drives, /*track_work=*/true);
  JointSpaceOde separate(scene.model, drives, /*track_work=*/true);
  AppendedQuadratureOde appended(fused);
  const int n = fused.size();
  const Eigen::VectorXd y0 = InitialJointState(scene.config, drives, scene.model.num_dofs());
  std::vector<double> z(y0.data(), y0.data() + n);
  z.push_back(0.0);
  for (int k = 0; k < 5; ++k) {
    const double t = 0.13 * k;
    for (int i = 0; i < n; ++i) z[i] += 0.01 * (i + 1) * k;  // states off the trajectory
    std::vector<double> zdot(n + 1), expected(n + 1);
    const long before = fused.dynamics_evaluations();
    const long allocations = testing::AllocationCount();
    ASSERT_EQ(appended.Rhs(t, z.data(), zdot.data()), 0);
    EXPECT_EQ(testing::AllocationCount() - allocations, 0);
    EXPECT_EQ(fused.dynamics_evaluations() - before, 1);
    const long separate_before = separate.dynamics_evaluations();
    ASSERT_EQ(separate.Rhs(t, z.data(), expected.data()), 0);
    ASSERT_EQ(separate.Quadrature(t, z.data(), expected.data() + n), 0);
    EXPECT_EQ(separate.dynamics_evaluations() - separate_before, 2);
    EXPECT_TRUE(SameBits(zdot, expected)) << "t = " << t;
    EXPECT_NE(zdot[n], 0.0);  // the drives and the damping do work
  }
}

TEST(QuadratureReuseTest, RunsAreBitIdenticalWithHalfTheDynamics) {
  const MixedScene scene;
  const DriveSet drives(scene.model, scene.config.drives);
  const Eigen::VectorXd y0 = InitialJointState(scene.config, drives, scene.model.num_dofs());
  for (Method method : {Method::kBdf, Method::kErk, Method::kDirk}) {
    RunConfig config = scene.config;
    config.method = method;
    const IntegratorOptions options = IntegratorOptionsFrom(config, config.duration);
    JointSpaceOde fused(scene.model, drives, /*track_work=*/true);
    JointSpaceOde inner(scene.model, drives, /*track_work=*/true);
    SeparateCalls separate(inner);
    std::vector<double> y_fused(y0.data(), y0.data() + y0.size()), y_separate = y_fused;
    auto a = MakeIntegrator(fused, 0.0, y_fused.data(), options);
    auto b = MakeIntegrator(separate, 0.0, y_separate.data(), options);
    for (int k = 1; k <= 20; ++k) {
      const double t = 0.05 * k;
      ASSERT_EQ(a->AdvanceTo(t, y_fused.data()).status, IntegratorStatus::kOk);
      ASSERT_EQ(b->AdvanceTo(t, y_separate.data()).status, IntegratorStatus::kOk);
      ASSERT_TRUE(SameBits(y_fused, y_separate)) << MethodName(method) << " t = " << t;
    }
    std::vector<double> w_fused(1), w_separate(1);
    ASSERT_TRUE(a->Quadratures(w_fused.data()));
    ASSERT_TRUE(b->Quadratures(w_separate.data()));
    EXPECT_TRUE(SameBits(w_fused, w_separate)) << MethodName(method);
    EXPECT_EQ(a->stats().rhs_evals, b->stats().rhs_evals) << MethodName(method);
    EXPECT_EQ(2 * fused.dynamics_evaluations(), inner.dynamics_evaluations()) << MethodName(method);
  }
}

}  // namespace
}  // namespace mbstream
