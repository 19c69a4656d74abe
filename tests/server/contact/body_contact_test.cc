// Contact in body coordinates (issue 44, docs/contact.md "Formulations"): formulation
// body-baumgarte, every link a free rigid body held by its joints' constraints, takes the
// contact forces as wrenches on the bodies (server/body/body_contact.h). The oracles: the joint
// formulation's run of the same scene (the same equations of motion in other coordinates) and
// the closed forms of resting contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "server/engine/engine.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using contact_testing::Config;
using contact_testing::NormalForce;
using contact_testing::Scene;

constexpr double kG = 9.81;

// The coordinate of joint `name` (no quaternions in these scenes: one position per velocity).
int Coordinate(const Model& model, const std::string& name) {
  for (const Body& body : model.bodies) {
    if (body.joint.name == name) return body.v_index;
  }
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

double Q(const RunResult& r, size_t frame, int k) {
  return r.q[frame * static_cast<size_t>(r.num_dofs) + static_cast<size_t>(k)];
}
double Qd(const RunResult& r, size_t frame, int k) {
  return r.qd[frame * static_cast<size_t>(r.num_dofs) + static_cast<size_t>(k)];
}

// `config` run on `model` in `formulation` with every joint passive, validated at the door as
// the engine does; EXPECTs that it finished.
RunResult RunIn(const Model& model, RunConfig config, Formulation formulation) {
  config.formulation = formulation;
  config.drives.assign(static_cast<size_t>(model.nv()), DriveConfig{});
  ValidateRun(model, config);
  RunResult result = Simulate(model, config);
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  return result;
}

// The deepest contact of the last frame (m).
double LastDepth(const RunResult& r) {
  double depth = 0.0;
  for (const ContactRecord& c : r.contacts.records) {
    if (c.t == r.t.back()) depth = std::max(depth, c.depth);
  }
  return depth;
}

// The largest differences of coordinate k and of the frames' normal forces between two runs.
struct Differences {
  double q = 0.0, qd = 0.0, force = 0.0, force_peak = 0.0;
};
Differences Compare(const RunResult& a, const RunResult& b, int k) {
  Differences d;
  EXPECT_EQ(a.t.size(), b.t.size());
  for (size_t f = 0; f < std::min(a.t.size(), b.t.size()); ++f) {
    d.q = std::max(d.q, std::abs(Q(a, f, k) - Q(b, f, k)));
    d.qd = std::max(d.qd, std::abs(Qd(a, f, k) - Qd(b, f, k)));
    d.force = std::max(d.force, std::abs(NormalForce(a, f) - NormalForce(b, f)));
    d.force_peak = std::max(d.force_peak, NormalForce(b, f));
  }
  return d;
}

// A frictionless pendulum swings onto the floor, bounces and comes to rest on its tip: the
// body-coordinate run retraces the joint formulation's, stops where each contact begins and
// ends, balances its energy with the contacts' work included, and rests m g / (2 k) deep.
TEST(BodyContactTest, APendulumSwingsOntoTheFloorAndRestsAsInTheJointFormulation) {
  const Model model = Scene("pendulum_on_floor.sdf");
  RunConfig config = Config(5.0, 0.01);
  config.contact.dissipation = 2.0;
  config.contact.mu_static = config.contact.mu_dynamic = 0.0;
  const RunResult body = RunIn(model, config, Formulation::kBodyBaumgarte);
  const RunResult joint = RunIn(model, config, Formulation::kJoint);
  const int hinge = Coordinate(model, "pendulum::hinge"), yaw = Coordinate(model, "pendulum::yaw");
  const Differences d = Compare(body, joint, hinge);
  double yaw_max = 0.0;
  for (size_t f = 0; f < body.t.size(); ++f) yaw_max = std::max(yaw_max, std::abs(Q(body, f, yaw)));
  const double k = 0.5 * config.contact.stiffness;  // two equal surfaces in series
  const double expected = 1.0 * kG / (2.0 * k);
  printf("RESULT body vs joint: |dq| %.3g rad |dqd| %.3g rad/s |dF| %.3g N (peak %.4g N)\n", d.q,
         d.qd, d.force, d.force_peak);
  printf("RESULT rest depth body %.10g joint %.10g expected %.10g m; yaw %.3g rad\n",
         LastDepth(body), LastDepth(joint), expected, yaw_max);
  printf(
      "RESULT steps body %ld joint %ld; roots body %ld joint %ld; energy balance body %.3g "
      "(trust %s) joint %.3g; dissipated body %.10g joint %.10g J\n",
      body.stats.solver.steps, joint.stats.solver.steps, body.stats.solver.roots_found,
      joint.stats.solver.roots_found, body.stats.energy_error_max, TrustName(body.stats.trust),
      joint.stats.energy_error_max, body.stats.contact.dissipated_work_j,
      joint.stats.contact.dissipated_work_j);
  EXPECT_GT(d.force_peak, 10.0);  // it struck the floor
  EXPECT_LT(d.q, 1e-7);
  EXPECT_LT(d.force, 1e-5 * d.force_peak);
  EXPECT_LT(yaw_max, 1e-12);
  EXPECT_NEAR(LastDepth(body), expected, 1e-6 * expected);
  EXPECT_NEAR(LastDepth(joint), expected, 1e-6 * expected);
  EXPECT_GE(body.stats.solver.roots_found, 1);
  ASSERT_TRUE(body.stats.contact.active);
  EXPECT_EQ(body.stats.contact.contacts_peak, 1);
  // The drop from q = 0 to the rest angle, less what is left as motion: all dissipated.
  const double rest = std::asin((0.3 + expected) / 0.4);
  const double lost = 1.0 * kG * 0.2 * std::sin(rest) - 0.5 * k * expected * expected;
  EXPECT_NEAR(body.stats.contact.dissipated_work_j, lost, 1e-6 * lost);
  EXPECT_NEAR(body.stats.contact.dissipated_work_j, joint.stats.contact.dissipated_work_j,
              1e-6 * lost);
  EXPECT_LT(body.stats.energy_error_max, 1e-6);
  EXPECT_NE(body.stats.formulation_reason.find("contact on: 1 geometry pair"), std::string::npos)
      << body.stats.formulation_reason;
}

// The box on its sliders (tests/data/contact/box_on_slider.sdf) dropped 5 cm and pushed along x
// at 0.3 m/s: it lands, slides against Coulomb friction, stops and rests m g / k deep, in body
// coordinates as in joint coordinates.
TEST(BodyContactTest, ABoxOnSlidersLandsSlidesAndStopsAsInTheJointFormulation) {
  const Model model = Scene("box_on_slider.sdf");
  RunConfig config = Config(2.0, 0.01);
  config.contact.dissipation = 20.0;
  config.qd0 = Eigen::VectorXd::Zero(model.nv());
  const int x = Coordinate(model, "box::carriage"), z = Coordinate(model, "box::drop");
  config.qd0(x) = 0.3;
  const RunResult body = RunIn(model, config, Formulation::kBodyBaumgarte);
  const RunResult joint = RunIn(model, config, Formulation::kJoint);
  const Differences dz = Compare(body, joint, z);
  const Differences dx = Compare(body, joint, x);
  const double k = 0.5 * config.contact.stiffness;
  const double expected = 2.0 * kG / k;
  printf(
      "RESULT body vs joint: |dz| %.3g m |dx| %.3g m |dvx| %.3g m/s |dF| %.3g N (peak %.4g "
      "N); slid %.6g m; rest depth %.10g expected %.10g m\n",
      dz.q, dx.q, dx.qd, dz.force, dz.force_peak, Q(body, body.t.size() - 1, x), LastDepth(body),
      expected);
  EXPECT_LT(dz.q, 1e-8);
  EXPECT_LT(dx.q, 1e-7);
  EXPECT_LT(dz.force, 1e-5 * dz.force_peak);
  EXPECT_GT(Q(body, body.t.size() - 1, x), 0.005);  // it slid
  EXPECT_LT(std::abs(Qd(body, body.t.size() - 1, x)), config.contact.stiction_tolerance);
  EXPECT_NEAR(LastDepth(body), expected, 1e-6 * expected);
  EXPECT_EQ(body.stats.contact.contacts_peak, joint.stats.contact.contacts_peak);
  EXPECT_NEAR(body.stats.contact.dissipated_work_j, joint.stats.contact.dissipated_work_j,
              1e-6 * joint.stats.contact.dissipated_work_j);
}

// The body DAEs for IDA have no contact forces: refused at the door, naming what has them.
TEST(BodyContactTest, TheBodyDaesAreRefusedWhenContactMayAct) {
  const Model model = Scene("pendulum_on_floor.sdf");
  RunConfig config = Config(0.1, 0.01);
  config.drives.assign(static_cast<size_t>(model.nv()), DriveConfig{});
  for (const Formulation f : {Formulation::kBodyIndex2, Formulation::kBodyIndex3}) {
    config.formulation = f;
    config.method = Method::kIda;
    try {
      ValidateRun(model, config);
      ADD_FAILURE() << FormulationName(f) << " with contact accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("use formulation body-baumgarte"), std::string::npos)
          << e.what();
    }
  }
  config.contact.enabled = false;
  EXPECT_NO_THROW(ValidateRun(model, config));
  config.contact.enabled = true;
  config.formulation = Formulation::kBodyBaumgarte;
  config.method = Method::kBdf;
  EXPECT_NO_THROW(ValidateRun(model, config));
}

}  // namespace
}  // namespace mbstream
