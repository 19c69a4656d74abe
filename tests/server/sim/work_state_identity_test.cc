// The work quadrature leaves the motion alone: with the work W(t) appended to the ODE (a
// state outside the error control), q and qd are those of the ODE alone, bit for bit, with
// the same steps and evaluations, for every method, with the joint formulation's own Jacobian
// and with finite differences, and for body-baumgarte. So every driven scene can integrate
// its work without changing a single result the bit-identity tests compare.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "server/body/body_baumgarte_ode.h"
#include "server/body/body_model.h"
#include "server/body/consistent_init.h"
#include "server/integrate/integrator.h"
#include "server/sim/initial_state.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Advances both integrators over `config`'s first second, frame by frame: the states must
// agree bit for bit at every output, and the solver statistics at the end; the tracked one's
// work must be non-zero.
void ExpectSameMotion(OdeSystem& alone, OdeSystem& tracked, const std::vector<double>& y0,
                      const RunConfig& config, const std::string& what) {
  ASSERT_EQ(alone.num_quadratures(), 0) << what;
  ASSERT_EQ(tracked.num_quadratures(), 1) << what;
  const IntegratorOptions options = IntegratorOptionsFrom(config, config.duration);
  std::vector<double> y_alone = y0, y_tracked = y0;
  auto a = MakeIntegrator(alone, 0.0, y_alone.data(), options);
  auto b = MakeIntegrator(tracked, 0.0, y_tracked.data(), options);
  const int frames = static_cast<int>(config.duration / config.output_interval + 0.5);
  for (int k = 1; k <= frames; ++k) {
    const double t = config.duration * k / frames;
    ASSERT_EQ(a->AdvanceTo(t, y_alone.data()).status, IntegratorStatus::kOk) << what;
    ASSERT_EQ(b->AdvanceTo(t, y_tracked.data()).status, IntegratorStatus::kOk) << what;
    ASSERT_TRUE(SameBits(y_alone, y_tracked)) << what << " t = " << t;
  }
  const SolverStats sa = a->stats(), sb = b->stats();
  EXPECT_GT(sa.steps, 0) << what;
  EXPECT_EQ(sa.steps, sb.steps) << what;
  EXPECT_EQ(sa.rhs_evals, sb.rhs_evals) << what;
  EXPECT_EQ(sa.jac_evals, sb.jac_evals) << what;
  EXPECT_EQ(sa.nonlinear_iterations, sb.nonlinear_iterations) << what;
  EXPECT_EQ(sa.error_test_failures, sb.error_test_failures) << what;
  EXPECT_EQ(sa.last_step, sb.last_step) << what;
  double work = 0.0;
  ASSERT_TRUE(b->Quadratures(&work)) << what;
  EXPECT_NE(work, 0.0) << what;
}

struct JointCase {
  const char* scene;
  double damping;  // N*m*s/rad on every joint
  Formulation formulation;
};

TEST(WorkStateIdentityTest, JointFormulationEveryMethod) {
  // seed-servo: servos, the ODE's own Jacobian; seed-run: velocity sources, so finite
  // differences (and the power of the prescribed joints from the dynamics); passive-swing
  // with damping: its own Jacobian, dissipation only.
  for (const JointCase& c : {JointCase{"seed-servo", 0.0, Formulation::kJoint},
                             JointCase{"seed-run", 0.0, Formulation::kJoint},
                             JointCase{"passive-swing", 2.0, Formulation::kJoint}}) {
    Model model = Irb1600();
    for (Body& body : model.bodies) body.joint.damping = c.damping;
    for (Method method : {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4,
                          Method::kEuler}) {
      RunConfig config = Scene(c.scene);
      config.formulation = c.formulation;
      config.method = method;
      config.duration = 1.0;
      config.output_interval = 0.05;
      config.fixed_step = 1e-4;  // RK4 and Euler diverge on seed-servo's wrist above 3e-4 s
      const DriveSet drives(model, config.drives);
      JointSpaceOde alone(model, drives, /*track_work=*/false);
      JointSpaceOde tracked(model, drives, /*track_work=*/true);
      const Eigen::VectorXd y0 = InitialJointState(config, drives, model.num_dofs());
      ExpectSameMotion(alone, tracked, std::vector<double>(y0.data(), y0.data() + y0.size()),
                       config, std::string(c.scene) + " " + MethodName(method));
    }
  }
}

TEST(WorkStateIdentityTest, BodyBaumgarte) {
  const Model& model = Irb1600();
  RunConfig config = Scene("seed-servo");
  config.formulation = Formulation::kBodyBaumgarte;
  config.duration = 0.5;
  config.output_interval = 0.05;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  const DriveSet drives(model, config.drives);
  const int n = model.num_dofs();
  const Eigen::VectorXd state = InitialJointState(config, drives, n);
  const Eigen::VectorXd q0 = state.head(n), qd0 = state.tail(n);
  const BodyModel bm = MakeBodyModel(model, drives, q0);
  BodyBaumgarteOde alone(bm, drives, config.baumgarte, /*track_work=*/false);
  BodyBaumgarteOde tracked(bm, drives, config.baumgarte, /*track_work=*/true);
  BodyInitialState init;
  ASSERT_TRUE(ConsistentInitialState(model, bm, alone.mechanics(), 0.0, q0, qd0, &init));
  const std::vector<double> y0(init.y.data(), init.y.data() + bm.ode_size());
  for (Method method : {Method::kBdf, Method::kErk}) {
    config.method = method;
    ExpectSameMotion(alone, tracked, y0, config,
                     std::string("body-baumgarte ") + MethodName(method));
  }
}

}  // namespace
}  // namespace mbstream
