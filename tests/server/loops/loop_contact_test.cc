// Contact in closed-loop runs (issue 44, docs/closed_loops.md "Contact"): the closed loops'
// joint-space ODE (closed_loop_ode.h) with the contact forces, against the same mechanism as a
// tree. tests/data/loops/box_on_twin_sliders.sdf is tests/data/contact/box_on_slider.sdf with
// its carriage and box each split in two columns that a cut fixed joint welds together: the
// same masses along x (2.1 kg) and z (2 kg), so the loop run must retrace the tree run's
// motion and contacts (the oracle), and rest m g / k deep (ContactChecksTest's closed form).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "server/contact/contact_law.h"
#include "server/drives/drive_set.h"
#include "server/integrate/integrator.h"
#include "server/parse/sdf_import.h"
#include "server/sim/closed_loop_ode.h"
#include "server/sim/joint_integration.h"
#include "server/sim/loop_plan.h"
#include "server/sim/loop_run.h"
#include "shared/common/check.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using contact_testing::Config;
using contact_testing::NormalForce;
using contact_testing::Qd;
using contact_testing::RunScene;
using contact_testing::Scene;

constexpr double kG = 9.81;

// Position k of output frame `frame` (one position per velocity here: the results' positions
// are their num_dofs coordinates, contact_testing::Q reads free bodies' num_positions).
double Q(const RunResult& r, size_t frame, int k) {
  const size_t stride = static_cast<size_t>(r.num_positions > 0 ? r.num_positions : r.num_dofs);
  return r.q[frame * stride + static_cast<size_t>(k)];
}

SdfImport TwinSliders() {
  return ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) +
                       "/tests/data/loops/box_on_twin_sliders.sdf");
}

// The velocity (and, with no quaternions, position) index of joint `name` of model "box".
int Coordinate(const Model& model, const std::string& name) {
  for (const Body& body : model.bodies) {
    if (body.joint.name == "box::" + name) return body.v_index;
  }
  ADD_FAILURE() << "no joint " << name;
  return 0;
}

// `config` run on the loop model with every coordinate passive, validated at the door as the
// engine does; EXPECTs that it finished.
RunResult RunLoops(const SdfImport& sdf, RunConfig config) {
  config.drives.assign(static_cast<size_t>(sdf.model.nv()), DriveConfig{});
  ValidateLoopRun(sdf.model, sdf.loops, config);
  RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  return result;
}

TEST(LoopContactTest, TheTwinSlidersAreOneLoopClosedByTheCutWeld) {
  const SdfImport sdf = TwinSliders();
  ASSERT_EQ(sdf.loops.size(), 1u);
  EXPECT_EQ(sdf.loops[0].name, "box::weld");
  EXPECT_EQ(sdf.loops[0].type, LoopJointType::kFixed);
  EXPECT_EQ(sdf.model.nv(), 4);
  EXPECT_EQ(sdf.model.collisions.size(), 2u);
}

// The oracle: dropped 5 cm, bouncing and settling (dissipation 20 s/m a surface), the loop
// run's box follows the tree run's at every output frame, with the same contact forces.
TEST(LoopContactTest, ALoopRetracesTheTreeThroughTheDropAndTheBounces) {
  const SdfImport loop = TwinSliders();
  const Model tree = Scene("box_on_slider.sdf");
  RunConfig config = Config(1.0, 0.005);
  config.contact.dissipation = 20.0;
  const RunResult a = RunLoops(loop, config);
  const RunResult b = RunScene(tree, config);
  ASSERT_EQ(a.t.size(), b.t.size());
  const int za = Coordinate(loop.model, "drop_a"), zb = Coordinate(tree, "drop");
  const int zw = Coordinate(loop.model, "drop_b");
  double dz = 0.0, dv = 0.0, df = 0.0, weld = 0.0, peak = 0.0;
  for (size_t f = 0; f < a.t.size(); ++f) {
    dz = std::max(dz, std::abs(Q(a, f, za) - Q(b, f, zb)));
    dv = std::max(dv, std::abs(Qd(a, f, za) - Qd(b, f, zb)));
    df = std::max(df, std::abs(NormalForce(a, f) - NormalForce(b, f)));
    weld = std::max(weld, std::abs(Q(a, f, za) - Q(a, f, zw)));
    peak = std::max(peak, NormalForce(b, f));
  }
  printf("RESULT loop vs tree: |dz| %.3g m |dv| %.3g m/s |dF| %.3g N (peak %.4g N) weld %.3g m\n",
         dz, dv, df, peak, weld);
  printf("RESULT cpu loop %.4g s tree %.4g s; steps loop %ld tree %ld; roots loop %ld tree %ld\n",
         a.stats.cpu_s, b.stats.cpu_s, a.stats.solver.steps, b.stats.solver.steps,
         a.stats.solver.roots_found, b.stats.solver.roots_found);
  printf("RESULT energy balance loop %.3g (quadrature %.3g, trust %s: %s) tree %.3g\n",
         a.stats.energy_error_max, a.stats.energy_quadrature_error_max, TrustName(a.stats.trust),
         a.stats.trust_reason.c_str(), b.stats.energy_error_max);
  // The two runs integrate the same equations of motion in different coordinates (4 with a
  // loop's multipliers against 2), each at rtol 1e-10, atol 1e-12: they differ by the two
  // integrations' errors, measured 1.4e-12 m and 5e-10 m/s. The bounds leave a factor of 100 to
  // 1000 for other compilers and libraries and are still 4e-7 of the 0.39 mm the box sinks at
  // rest; the normal force (k depth plus dissipation) to 1e-8 of its peak.
  EXPECT_LT(dz, 1e-9);
  EXPECT_LT(dv, 1e-7);
  EXPECT_LT(df, 1e-8 * peak);
  EXPECT_LT(weld, 1e-9);      // the loop holds (projection after each BDF step)
  EXPECT_GT(peak, 2.0 * kG);  // the impact: more than the weight
  // Contact as for a tree: the frames' contacts, the summary, the roots, the step cap.
  EXPECT_TRUE(a.contacts.active);
  EXPECT_TRUE(a.stats.contact.active);
  EXPECT_EQ(a.contacts.count_peak, b.contacts.count_peak);
  EXPECT_NEAR(a.contacts.depth_max, b.contacts.depth_max, 1e-9);
  EXPECT_GE(a.stats.solver.roots_found, 1);  // the landing (it never leaves the plane again)
  EXPECT_EQ(a.stats.solver.roots_found, b.stats.solver.roots_found);
  EXPECT_NE(a.stats.formulation_reason.find("contact on"), std::string::npos)
      << a.stats.formulation_reason;
  // The energy balance counts the contacts' work as a quadrature of the ODE, as the tree's
  // does (the impact falls between frames: a trapezoid over the frames measured 0.32): both
  // balance to 5e-9 and the run is trusted.
  EXPECT_EQ(a.stats.energy_work, kEnergyWorkIntegrated);
  EXPECT_LT(a.stats.energy_error_max, 1e-7);
  EXPECT_LT(a.stats.energy_error_max, 10.0 * b.stats.energy_error_max + 1e-9);
  EXPECT_EQ(a.stats.trust, Trust::kOk) << a.stats.trust_reason;
}

// At rest the closed loop's box sinks by its mechanism's weight over the pair's stiffness (in
// series), m g / k with m = 2 kg (both columns), as the tree's box does (ContactChecksTest).
TEST(LoopContactTest, TheLoopAtRestSinksByItsWeightOverTheStiffness) {
  const SdfImport loop = TwinSliders();
  RunConfig config = Config(5.0, 0.01);
  config.contact.dissipation = 20.0;
  const RunResult r = RunLoops(loop, config);
  const double k = contact_law::CombineStiffness(1e5, 1e5);
  const double expected = 2.0 * kG / k;
  const size_t last = r.t.size() - 1;
  // The box's bottom face is 0.05 m above the plane at q = 0.
  const double depth = -0.05 - Q(r, last, Coordinate(loop.model, "drop_a"));
  printf("RESULT loop penetration %.12g expected %.12g rel %.3g; normal force %.9g N\n", depth,
         expected, depth / expected - 1, NormalForce(r, last));
  EXPECT_NEAR(depth / expected, 1.0, 1e-6) << depth;
  EXPECT_NEAR(NormalForce(r, last), 2.0 * kG, 1e-5 * 2.0 * kG);
  double fastest = 0.0;
  for (size_t f = 0; f < r.t.size(); ++f) {
    if (r.t[f] < 3.0) continue;
    for (int j = 0; j < 4; ++j) fastest = std::max(fastest, std::abs(Qd(r, f, j)));
  }
  EXPECT_LE(fastest, config.contact.stiction_tolerance);
}

// Friction through the loop: on a 30 degree incline (gravity turned about y) the box slides
// along x against Coulomb friction; the loop's two carriages move as the tree's one.
TEST(LoopContactTest, ALoopSlidesDownAnInclineAsTheTreeDoes) {
  const SdfImport loop = TwinSliders();
  const Model tree = Scene("box_on_slider.sdf");
  const double theta = 30.0 * M_PI / 180.0;
  RunConfig config = Config(1.0, 0.01);
  config.gravity = Eigen::Vector3d(kG * std::sin(theta), 0.0, -kG * std::cos(theta));
  config.contact.dissipation = 20.0;
  config.contact.mu_static = 0.4;
  config.contact.mu_dynamic = 0.3;
  const RunResult a = RunLoops(loop, config);
  const RunResult b = RunScene(tree, config);
  ASSERT_EQ(a.t.size(), b.t.size());
  const int xa = Coordinate(loop.model, "carriage_a"), xb = Coordinate(tree, "carriage");
  double dx = 0.0;
  for (size_t f = 0; f < a.t.size(); ++f) dx = std::max(dx, std::abs(Q(a, f, xa) - Q(b, f, xb)));
  const size_t last = a.t.size() - 1;
  printf("RESULT incline: loop x %.9g tree x %.9g max |dx| %.3g m\n", Q(a, last, xa),
         Q(b, last, xb), dx);
  EXPECT_GT(Q(b, last, xb), 0.5);  // it slides (2.1 kg along x: the carriage too)
  EXPECT_LT(dx, 1e-9);             // measured 5.5e-13 m (the oracle test above says why 1e-9)
}

// What still has no contact with loops is refused at the door, naming what to use instead.
TEST(LoopContactTest, TheLoopsDaeAndTheBodyDaesAreRefusedWithContact) {
  const SdfImport loop = TwinSliders();
  RunConfig config = Config(0.1, 0.01);
  config.drives.assign(static_cast<size_t>(loop.model.nv()), DriveConfig{});
  config.method = Method::kIda;
  try {
    ValidateLoopRun(loop.model, loop.loops, config);
    ADD_FAILURE() << "method ida with contact and loops accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use method bdf"), std::string::npos) << e.what();
  }
  config.formulation = Formulation::kBodyIndex2;
  try {
    ValidateLoopRun(loop.model, loop.loops, config);
    ADD_FAILURE() << "a body DAE with contact and loops accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use formulation body-baumgarte"), std::string::npos)
        << e.what();
  }
  config.method = Method::kIda;
  config.formulation = Formulation::kJoint;
  config.contact.enabled = false;  // without contact ida runs the loops
  EXPECT_NO_THROW(ValidateLoopRun(loop.model, loop.loops, config));
}

// The closed-loop ODE's right-hand side, root functions and projection with the box 1 mm
// into the plane, and CVODE BDF stepping through the landing, allocate nothing once the first
// call has grown the contact buffers.
TEST(LoopContactTest, TheClosedLoopOdeWithContactStepsWithoutAllocating) {
  const SdfImport loop = TwinSliders();
  const Model& model = loop.model;
  RunConfig config = Config(1.0, 0.01);
  config.contact.dissipation = 20.0;
  config.drives.assign(static_cast<size_t>(model.nv()), DriveConfig{});
  const DriveSet drives(model, config.drives);
  ContactForces contact(model, config.contact);
  ASSERT_TRUE(contact.active());
  const Eigen::VectorXd q0 = Eigen::VectorXd::Zero(model.nq());
  ClosedLoopOde ode(model, loop.loops, drives, q0, config.baumgarte, 1e-12, &contact);
  ASSERT_EQ(ode.num_roots(), 1);
  const int za = Coordinate(model, "drop_a"), zb = Coordinate(model, "drop_b");
  Eigen::VectorXd y = Eigen::VectorXd::Zero(ode.size());
  y(za) = y(zb) = -0.05 - 1e-3;
  Eigen::VectorXd ydot(y.size()), correction(y.size());
  double g = 0.0;
  ASSERT_EQ(ode.Rhs(0.0, y.data(), ydot.data()), 0);  // grows the buffers
  ASSERT_EQ(contact.contacts().size(), 4u);
  const long before = testing::AllocationCount();
  bool ok = true;
  for (int k = 0; k < 20; ++k) {
    y(model.nq() + za) = y(model.nq() + zb) = -1e-3 * k;  // moving into the plane
    ok = ok && ode.Rhs(0.01 * k, y.data(), ydot.data()) == 0;
    ok = ok && ode.Roots(0.01 * k, y.data(), &g) == 0;
    ok = ok && ode.Project(0.01 * k, y.data(), correction.data()) == 0;
  }
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_TRUE(ok);
  EXPECT_NEAR(g, -1e-3, 1e-12);  // the signed distance: 1 mm deep
  // Upwards: the contact forces (k = 5e4 N/m times 1 mm, 50 N) beat the 2 kg's weight; the two
  // columns accelerate as one.
  EXPECT_GT(ydot(model.nq() + za), 0.0);
  EXPECT_NEAR(ydot(model.nq() + za), ydot(model.nq() + zb), 1e-9);

  IntegratorOptions options;
  options.method = Method::kBdf;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  options.t_final = 1.0;
  CapContactStep(model, config.contact, &options);
  y.setZero();
  std::unique_ptr<Integrator> integrator = MakeIntegrator(ode, 0.0, y.data(), options);
  ASSERT_EQ(integrator->AdvanceTo(0.05, y.data()).status, IntegratorStatus::kOk);
  const long stepping = testing::AllocationCount();
  for (int k = 2; k <= 20; ++k) {  // the landing is at t = sqrt(2 0.05 / g) = 0.1 s
    ok = ok && integrator->AdvanceTo(0.05 * k, y.data()).status == IntegratorStatus::kOk;
  }
  EXPECT_TRUE(ok);
  EXPECT_EQ(testing::AllocationCount() - stepping, 0);
  EXPECT_GE(integrator->stats().roots_found, 1);
  EXPECT_LT(y(za), -0.05);  // resting on the plane, a little into it
  EXPECT_GT(y(za), -0.051);
}

}  // namespace
}  // namespace mbstream
