// Contact runs against closed forms (issue 44, "Checks"; docs/contact.md): the elastic bounce,
// a box resting on a plane, a box sliding down an incline and one held by static friction.
// The scenes are SDFormat worlds in tests/data/contact/; the incline is the run's gravity
// turned by the incline's angle about y, so that the plane stays z = 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "server/contact/contact_law.h"
#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using namespace contact_testing;

constexpr double kG = 9.81;

// The apexes of z (position 2) between bounces: each the vertex of the parabola through a
// frame that is a local maximum and its neighbours (exact in free flight).
std::vector<double> Apexes(const RunResult& r) {
  std::vector<double> apexes;
  for (size_t k = 1; k + 1 < r.t.size(); ++k) {
    const double z0 = Q(r, k - 1, 2), z1 = Q(r, k, 2), z2 = Q(r, k + 1, 2);
    if (!(z1 > z0 && z1 >= z2)) continue;
    const double h = r.t[k] - r.t[k - 1];
    const double a = (z0 - 2 * z1 + z2) / (2 * h * h);  // z = a s^2 + b s + z1 about t[k]
    const double b = (z2 - z0) / (2 * h);
    apexes.push_back(z1 - b * b / (4 * a));
  }
  return apexes;
}

TEST(ContactChecksTest, ElasticBallBouncesBackToItsDropHeightTenTimes) {
  const Model model = Scene("ball_on_plane.sdf");
  ASSERT_EQ(model.collisions.size(), 2u);
  RunConfig config = Config(9.0, 1e-3);
  config.method = Method::kErk;
  config.contact.dissipation = 0.0;
  const RunResult r = RunScene(model, config);
  const std::vector<double> apexes = Apexes(r);
  ASSERT_GE(apexes.size(), 10u);
  double worst = 0.0;
  for (size_t k = 0; k < 10; ++k) worst = std::max(worst, std::abs(apexes[k] - 1.0));
  printf("RESULT apex error %.3g\n", worst);
  // The contact forces' work is in the integrated work: the energy balance is the integrator's.
  printf("RESULT energy balance %.3g\n", r.stats.energy_error_max);
  EXPECT_LT(r.stats.energy_error_max, 1e-8);
  EXPECT_EQ(r.stats.trust, Trust::kOk) << r.stats.trust_reason;
  EXPECT_LT(worst, 1e-6);
}

// CVODE and ARKODE end a step at each contact's beginning and end (the pair's signed distance
// is a root function), so no step straddles an impact: two roots per bounce.
TEST(ContactChecksTest, TheIntegratorStopsWhereEachBounceBeginsAndEnds) {
  const Model model = Scene("ball_on_plane.sdf");
  for (const Method method : {Method::kBdf, Method::kErk, Method::kDirk}) {
    RunConfig config = Config(4.0, 0.01);
    config.method = method;
    config.rtol = 1e-8;
    config.atol = 1e-10;
    config.contact.dissipation = 0.0;
    const RunResult r = RunScene(model, config);
    // Impacts at t0 = sqrt(2 h / g) (h = 0.9 m) and every 2 t0 + the contact time after.
    const double t0 = std::sqrt(2 * 0.9 / kG);
    printf("RESULT %s roots %ld steps %ld\n", MethodName(method), r.stats.solver.roots_found,
           r.stats.solver.steps);
    EXPECT_GE(r.stats.solver.roots_found, 2 * static_cast<long>((4.0 - t0) / (2 * t0 + 0.02)))
        << MethodName(method);
    EXPECT_LE(r.stats.solver.roots_found, 2 * static_cast<long>((4.0 - t0) / (2 * t0) + 1))
        << MethodName(method);
  }
}

// The box's penetration at rest: m g / k of the pair (stiffness in series), shared by its
// four bottom corners.
TEST(ContactChecksTest, RestingBoxSinksByWeightOverStiffnessAndStaysStill) {
  const Model model = Scene("box_on_plane.sdf");
  RunConfig config = Config(10.0, 0.01);
  config.contact.dissipation = 20.0;
  const RunResult r = RunScene(model, config);
  const double k = contact_law::CombineStiffness(1e5, 1e5);
  const double expected = 2.0 * kG / k;
  const size_t last = r.t.size() - 1;
  const double depth = 0.1 - Q(r, last, 2);
  printf("RESULT penetration %.12g expected %.12g rel %.3g\n", depth, expected,
         depth / expected - 1);
  EXPECT_NEAR(depth / expected, 1.0, 1e-6) << depth;
  double fastest = 0.0;
  for (size_t f = 0; f < r.t.size(); ++f) {
    if (r.t[f] < 5.0) continue;
    for (int j = 0; j < 6; ++j) fastest = std::max(fastest, std::abs(Qd(r, f, j)));
  }
  EXPECT_LE(fastest, config.contact.stiction_tolerance);
}

// The incline runs: the plane tilted by theta (gravity turned about y), d = 20 s/m,
// mu_s = 0.4, mu_d = 0.3 (the friction angle 21.8 degrees).
RunConfig InclineConfig(double theta, double duration, double interval) {
  RunConfig config = Config(duration, interval);
  config.gravity = Eigen::Vector3d(kG * std::sin(theta), 0.0, -kG * std::cos(theta));
  config.contact.dissipation = 20.0;
  config.contact.mu_static = 0.4;
  config.contact.mu_dynamic = 0.3;
  return config;
}

// A box on a plane tilted by theta (gravity turned about y): it slides with
// a = g (sin theta - mu_d cos theta) above the friction angle.
TEST(ContactChecksTest, BoxSlidesDownASteepInclineWithCoulombsAcceleration) {
  const Model model = Scene("box_on_plane.sdf");
  const double theta = 30.0 * M_PI / 180.0;
  const RunResult r = RunScene(model, InclineConfig(theta, 2.0, 0.01));
  const double expected = kG * (std::sin(theta) - 0.3 * std::cos(theta));
  const size_t a = r.t.size() / 2, b = r.t.size() - 1;
  const double measured = (Qd(r, b, 0) - Qd(r, a, 0)) / (r.t[b] - r.t[a]);
  printf("RESULT acceleration %.12g expected %.12g rel %.3g\n", measured, expected,
         measured / expected - 1);
  EXPECT_NEAR(measured / expected, 1.0, 1e-6) << measured << " against " << expected;
}

// The sliding box's dissipated contact work (RunStats.contact, a quadrature of the contacts'
// dissipated power): while it slides at a steady depth, friction alone dissipates, mu_d N per
// metre slid. Between a 1 s and a 2 s run of the same scene the work grows by
// mu_d m g cos(theta) times the distance slid meanwhile.
TEST(ContactChecksTest, ASlidingBoxDissipatesMuDTimesItsWeightPerMetre) {
  const Model model = Scene("box_on_plane.sdf");
  const double theta = 30.0 * M_PI / 180.0;
  RunConfig config = InclineConfig(theta, 1.0, 0.01);
  const RunResult first = RunScene(model, config);
  config.duration = 2.0;
  const RunResult second = RunScene(model, config);
  ASSERT_TRUE(first.stats.contact.active);
  const double slid = Q(second, second.t.size() - 1, 0) - Q(first, first.t.size() - 1, 0);
  const double expected = 0.3 * model.TotalMass() * kG * std::cos(theta) * slid;
  const double measured =
      second.stats.contact.dissipated_work_j - first.stats.contact.dissipated_work_j;
  printf("RESULT dissipated from 1 s to 2 s: %.12g J, mu_d N s %.12g J (rel %.3g); by 1 s %.9g J\n",
         measured, expected, measured / expected - 1, first.stats.contact.dissipated_work_j);
  EXPECT_GT(slid, 1.0);
  EXPECT_NEAR(measured / expected, 1.0, 1e-6);
}

// Below the friction angle the box holds: it creeps no faster than the stiction tolerance.
TEST(ContactChecksTest, BoxHoldsOnAnInclineBelowTheFrictionAngle) {
  const Model model = Scene("box_on_plane.sdf");
  const double theta = 15.0 * M_PI / 180.0;
  const RunConfig config = InclineConfig(theta, 5.0, 0.05);
  const RunResult r = RunScene(model, config);
  const size_t last = r.t.size() - 1;
  const double drift = Q(r, last, 0) - Q(r, 0, 0);
  printf("RESULT drift %.6g bound %.6g\n", drift,
         config.contact.stiction_tolerance * config.duration);
  EXPECT_LE(std::abs(drift), config.contact.stiction_tolerance * config.duration);
}

// A ball thrown at 20 m/s onto a plate 1 cm thick does not pass through it: it comes back up,
// with every method (the step cap, contact_forces.h, keeps a step from jumping over it).
TEST(ContactChecksTest, AFastBallDoesNotTunnelThroughAThinPlate) {
  const Model model = Scene("thin_plate.sdf");
  for (const Method method : {Method::kBdf, Method::kErk, Method::kDirk}) {
    RunConfig config = Config(0.1, 2e-4);
    config.method = method;
    config.rtol = 1e-6;
    config.atol = 1e-9;
    config.gravity.setZero();
    config.contact.dissipation = 0.0;
    config.qd0 = Eigen::VectorXd::Zero(model.nv());
    config.qd0(2) = -20.0;
    const RunResult r = RunScene(model, config);
    double lowest = 1.0;
    for (size_t f = 0; f < r.t.size(); ++f) lowest = std::min(lowest, Q(r, f, 2));
    const size_t last = r.t.size() - 1;
    printf("RESULT %s lowest centre %.6g m, final vz %.6g m/s\n", MethodName(method), lowest,
           Qd(r, last, 2));
    EXPECT_GT(lowest, 0.0) << MethodName(method);  // the centre stayed above the plate's middle
    // Elastic and without gravity the deepest point is delta = v sqrt(m / k) below contact
    // (sampled at the output frames, so a little above it).
    const double deepest = 0.055 - 20.0 * std::sqrt(1.0 / contact_law::CombineStiffness(1e6, 1e6));
    EXPECT_NEAR(lowest, deepest, 1e-4) << MethodName(method);
    EXPECT_NEAR(Qd(r, last, 2), 20.0, 1e-2) << MethodName(method);  // back up, elastic
    EXPECT_GT(Q(r, last, 2), 0.05) << MethodName(method);
  }
}

// A contact too soft for its load is named in the run's warnings; past half the geometry's
// size the run is not trusted either, and the remedy named is the stiffness.
TEST(ContactChecksTest, ATooSoftContactIsWarnedAbout) {
  const Model model = Scene("box_on_plane.sdf");
  RunConfig config = Config(1.0, 0.05);
  config.contact.stiffness = 2e3;  // 2 kg sinks 2 g m / k = 2 cm of the 0.1 m half-size
  config.contact.dissipation = 20.0;
  const RunResult r = RunScene(model, config);
  ASSERT_FALSE(r.stats.warnings.empty());
  printf("RESULT %s\n", r.stats.warnings.back().c_str());
  EXPECT_NE(r.stats.warnings.back().find("'box::body' ('cube')"), std::string::npos)
      << r.stats.warnings.back();
  EXPECT_NE(r.stats.warnings.back().find("contact.stiffness_n_per_m"), std::string::npos);
  EXPECT_EQ(r.stats.trust, Trust::kOk) << r.stats.trust_reason;  // 19 %: warned only
  config.contact.stiffness = 600.0;  // 2 g m / k = 6.5 cm of the 0.1 m half-size at rest
  const RunResult sunk = RunScene(model, config);
  EXPECT_GT(sunk.stats.contact.penetration_relative_max, 0.5);  // 0.518 at the output frames
  EXPECT_EQ(sunk.stats.trust, Trust::kLow);
  EXPECT_NE(sunk.stats.trust_reason.find("contact penetration relative to the smaller "
                                         "geometry's size"),
            std::string::npos)
      << sunk.stats.trust_reason;
  EXPECT_NE(sunk.stats.trust_reason.find("raise the stiffness"), std::string::npos);
  EXPECT_EQ(sunk.stats.trust_reason.find("tighten rtol"), std::string::npos)
      << sunk.stats.trust_reason;
  config.contact.stiffness = 1e5;
  const RunResult stiff = RunScene(model, config);
  for (const std::string& w : stiff.stats.warnings) {
    EXPECT_EQ(w.find("contact:"), std::string::npos) << w;
  }
  EXPECT_EQ(stiff.stats.trust, Trust::kOk) << stiff.stats.trust_reason;
}

// A stiff contact (k = 1e9 N/m) that starts 1 mm in: ERK runs until its step budget, and the
// root finder does not refuse a signed distance of exactly 0 at a root just found (it did:
// ARK_ILL_INPUT, "Root found at and very near t").
TEST(ContactChecksTest, AStiffContactRunsToItsBudgetWithoutARootFailure) {
  const Model model = Scene("ball_on_plane.sdf");
  RunConfig config = Config(1.0, 0.01);
  config.method = Method::kErk;
  config.rtol = 1e-6;
  config.atol = 1e-9;
  config.max_steps = 500;
  config.contact.stiffness = 1e9;
  config.q0 = Eigen::VectorXd::Zero(model.nq());
  config.q0(2) = 0.099;
  config.q0(3) = 1.0;
  config.drives.resize(static_cast<size_t>(model.nv()));
  ValidateRun(model, config);
  const RunResult r = Simulate(model, config);
  EXPECT_EQ(r.stats.status, RunStatus::kTooMuchWork) << r.stats.message;
  EXPECT_EQ(r.stats.message.find("ILL_INPUT"), std::string::npos) << r.stats.message;
  for (size_t k = 0; k < r.q.size(); ++k) ASSERT_TRUE(std::isfinite(r.q[k]));  // no NaN kept
}

TEST(ContactChecksTest, ContactOffLetsTheBallFallThrough) {
  const Model model = Scene("ball_on_plane.sdf");
  RunConfig config = Config(1.0, 0.1);
  config.contact.enabled = false;
  const RunResult r = RunScene(model, config);
  const double t = r.t.back();
  EXPECT_NEAR(Q(r, r.t.size() - 1, 2), 1.0 - 0.5 * kG * t * t, 1e-9);
  EXPECT_NE(r.stats.formulation_reason.find("contact off (contact.enabled false)"),
            std::string::npos)
      << r.stats.formulation_reason;
  config.contact.enabled = true;
  EXPECT_NE(RunScene(model, config).stats.formulation_reason.find("contact on: 1 geometry pair"),
            std::string::npos);
}

TEST(ContactChecksTest, AFilteredPairNeverTouches) {
  const Model model = Scene("ball_on_plane.sdf");
  RunConfig config = Config(1.0, 0.1);
  config.contact.filter = {{"ball::body", "plane"}};  // a link and a collision name
  const RunResult r = RunScene(model, config);
  const double t = r.t.back();
  EXPECT_NEAR(Q(r, r.t.size() - 1, 2), 1.0 - 0.5 * kG * t * t, 1e-9);
}

// Bad settings are refused at the door, naming the field.
TEST(ContactChecksTest, AbsurdOrNonFiniteSettingsAreRefusedByName) {
  const Model model = Scene("ball_on_plane.sdf");
  auto refused = [&](void (*change)(RunConfig*), const std::string& field) {
    RunConfig config = Config(1.0, 0.1);
    config.drives.resize(static_cast<size_t>(model.nv()));
    change(&config);
    try {
      ValidateRun(model, config);
      ADD_FAILURE() << field << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  refused([](RunConfig* c) { c->contact.stiffness = -1.0; }, "contact.stiffness_n_per_m");
  refused([](RunConfig* c) { c->contact.stiffness = 1e20; }, "contact.stiffness_n_per_m");
  refused([](RunConfig* c) { c->contact.dissipation = NAN; }, "contact.dissipation_s_per_m");
  refused([](RunConfig* c) { c->contact.mu_static = -0.1; }, "contact.mu_static");
  refused([](RunConfig* c) { c->contact.mu_dynamic = INFINITY; }, "contact.mu_dynamic");
  refused([](RunConfig* c) { c->contact.mu_dynamic = 0.9; }, "contact.mu_dynamic");
  refused([](RunConfig* c) { c->contact.stiction_tolerance = 0.0; },
          "contact.stiction_tolerance_m_per_s");
  refused(
      [](RunConfig* c) {
        c->contact.filter = {{"ball::body", "nothing"}};
      },
      "contact.collision_filter: 'nothing'");
  refused(
      [](RunConfig* c) {
        c->formulation = Formulation::kBodyIndex2;
        c->contact.filter.clear();
      },
      "formulation body-index2");
}

}  // namespace
}  // namespace mbstream
