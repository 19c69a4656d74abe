// Contact scenes against closed forms and a separate integration (issue 44, "Checks";
// docs/contact.md): a dissipative bounce against the 1-D Hunt-Crossley ODE, a solid cylinder
// rolling down an incline, five stacked boxes standing. Scenes in tests/data/contact/.
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
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using namespace contact_testing;

constexpr double kG = 9.81;

// The 1-D Hunt-Crossley bounce of a ball of radius r on a floor: from an apex at height z
// (its centre), the next apex. Free flight in closed form; the contact, m z'' = -m g +
// k delta (1 + d delta') with delta = r - z, by RK4 at 1e-7 s, its end found by cubic Hermite
// interpolation of delta between the steps that bracket it.
double NextApex(double apex, double r, double k, double d, double m) {
  double z = r, v = -std::sqrt(2.0 * kG * (apex - r));
  auto accel = [&](double zz, double vv) {
    const double delta = r - zz;
    return -kG + (delta > 0.0 ? contact_law::NormalForce(k, d, delta, -vv) / m : 0.0);
  };
  const double h = 1e-7;
  for (;;) {
    const double k1z = v, k1v = accel(z, v);
    const double k2z = v + 0.5 * h * k1v, k2v = accel(z + 0.5 * h * k1z, v + 0.5 * h * k1v);
    const double k3z = v + 0.5 * h * k2v, k3v = accel(z + 0.5 * h * k2z, v + 0.5 * h * k2v);
    const double k4z = v + h * k3v, k4v = accel(z + h * k3z, v + h * k3v);
    const double z1 = z + h / 6 * (k1z + 2 * k2z + 2 * k3z + k4z);
    const double v1 = v + h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (v1 > 0.0 && z1 >= r) {  // left the floor within this step: Hermite for z(s) = r
      double lo = 0.0, hi = 1.0;
      auto zs = [&](double s) {  // cubic Hermite of z on [0, h]
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * z + (s3 - 2 * s2 + s) * h * v + (-2 * s3 + 3 * s2) * z1 +
               (s3 - s2) * h * v1;
      };
      auto vs = [&](double s) {
        const double s2 = s * s;
        return ((6 * s2 - 6 * s) * z + (3 * s2 - 4 * s + 1) * h * v + (-6 * s2 + 6 * s) * z1 +
                (3 * s2 - 2 * s) * h * v1) /
               h;
      };
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        (zs(mid) < r ? lo : hi) = mid;
      }
      const double out = vs(hi);
      return r + out * out / (2.0 * kG);
    }
    z = z1;
    v = v1;
  }
}

std::vector<double> Apexes(const RunResult& r) {
  std::vector<double> apexes;
  for (size_t k = 1; k + 1 < r.t.size(); ++k) {
    const double z0 = Q(r, k - 1, 2), z1 = Q(r, k, 2), z2 = Q(r, k + 1, 2);
    if (!(z1 > z0 && z1 >= z2)) continue;
    const double h = r.t[k] - r.t[k - 1];
    const double a = (z0 - 2 * z1 + z2) / (2 * h * h);
    const double b = (z2 - z0) / (2 * h);
    apexes.push_back(z1 - b * b / (4 * a));
  }
  return apexes;
}

TEST(ContactScenesTest, DissipativeBounceMatchesTheOneDimensionalHuntCrossleyOde) {
  const Model model = Scene("ball_on_plane.sdf");
  RunConfig config;
  config.method = Method::kErk;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.duration = 3.0;
  config.output_interval = 1e-3;
  config.contact.stiffness = 1e5;
  config.contact.dissipation = 0.3;
  const RunResult r = RunScene(model, config);
  const std::vector<double> apexes = Apexes(r);
  ASSERT_GE(apexes.size(), 4u);
  const double k = contact_law::CombineStiffness(1e5, 1e5);
  const double d = contact_law::CombineDissipation(1e5, 0.3, 1e5, 0.3);
  double worst = 0.0;
  double previous = 1.0;  // the drop height
  for (size_t n = 0; n < 4; ++n) {
    const double expected = NextApex(previous, 0.1, k, d, 1.0) - 0.1;
    const double ratio = (apexes[n] - 0.1) / (previous - 0.1);
    const double expected_ratio = expected / (previous - 0.1);
    worst = std::max(worst, std::abs(ratio / expected_ratio - 1.0));
    printf("RESULT bounce %zu ratio %.10f expected %.10f\n", n + 1, ratio, expected_ratio);
    previous = apexes[n];
  }
  EXPECT_LT(worst, 1e-6);
  // The dissipated work is in the integrated work (the contacts' power qd . J^T f), so the
  // energy balance E - E0 - W measures the integrator alone.
  printf("RESULT dissipative energy balance %.3g, dissipated %.6g J of %.6g J\n",
         r.stats.energy_error_max, r.work.empty() ? 0.0 : -r.work.back(), 0.9 * kG);
  EXPECT_LT(r.stats.energy_error_max, 1e-8);
  // The dissipated work reported apart (a quadrature of the damping's power): ended in flight
  // after the first bounce, where no spring is compressed, it is the mechanical energy the
  // 1 kg ball lost since the drop.
  config.duration = 0.7;  // near the first bounce's apex (0.25 m above the plane at 0.66 s)
  const RunResult one = RunScene(model, config);
  const size_t last = one.t.size() - 1;
  ASSERT_GT(Q(one, last, 2), 0.1 + 1e-3);  // in flight
  const double lost = kG * (1.0 - Q(one, last, 2)) - 0.5 * Qd(one, last, 2) * Qd(one, last, 2);
  printf("RESULT dissipated work after one bounce %.12g J, energy lost %.12g J\n",
         one.stats.contact.dissipated_work_j, lost);
  EXPECT_GT(lost, 0.1);
  // Measured 1.0e-8 J apart (1.6e-9 of the loss): the appended quadrature is not error-
  // controlled.
  EXPECT_NEAR(one.stats.contact.dissipated_work_j, lost, 1e-8 * 0.9 * kG);
  EXPECT_EQ(r.stats.trust, Trust::kOk) << r.stats.trust_reason;
}

// A solid cylinder rolls down a 20 degree incline without slipping: a = (2/3) g sin theta.
TEST(ContactScenesTest, SolidCylinderRollsWithTwoThirdsOfGSinTheta) {
  const Model model = Scene("cylinder_on_plane.sdf");
  const double theta = 20.0 * M_PI / 180.0;
  RunConfig config;
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.duration = 0.5;
  config.output_interval = 0.01;
  config.max_steps = 2'000'000;
  config.gravity = Eigen::Vector3d(kG * std::sin(theta), 0.0, -kG * std::cos(theta));
  // Stiff, so that the rolling radius r - delta / 2 (the force acts midway into the overlap)
  // is r to 2e-6.
  config.contact.stiffness = 1e8;
  config.contact.stiction_tolerance = 1e-3;
  config.contact.dissipation = 20.0;
  config.contact.mu_static = 0.8;
  config.contact.mu_dynamic = 0.8;
  const RunResult r = RunScene(model, config);
  const size_t a = r.t.size() / 2, b = r.t.size() - 1;
  const double measured = (Qd(r, b, 0) - Qd(r, a, 0)) / (r.t[b] - r.t[a]);
  const double expected = 2.0 / 3.0 * kG * std::sin(theta);
  printf("RESULT rolling %.12g expected %.12g rel %.3g\n", measured, expected,
         measured / expected - 1);
  EXPECT_NEAR(measured / expected, 1.0, 1e-5);
}

// Five stacked boxes stand for 10 s: no box moves sideways by more than 1 micrometre or turns,
// and the top one sinks by the stack's penetrations (4, 3, 2 and 1 boxes' weight over k).
TEST(ContactScenesTest, FiveStackedBoxesStandForTenSeconds) {
  const Model model = Scene("box_stack.sdf");
  RunConfig config;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.duration = 10.0;
  config.output_interval = 0.1;
  config.contact.stiffness = 1e6;
  config.contact.dissipation = 20.0;
  const RunResult r = RunScene(model, config);
  ASSERT_EQ(r.t.size(), 101u);
  const size_t last = r.t.size() - 1;
  double sideways = 0.0, turn = 0.0;
  for (int b = 0; b < 5; ++b) {
    const int i = 7 * b;
    sideways = std::max({sideways, std::abs(Q(r, last, i) - Q(r, 0, i)),
                         std::abs(Q(r, last, i + 1) - Q(r, 0, i + 1))});
    turn = std::max({turn, std::abs(Q(r, last, i + 4)), std::abs(Q(r, last, i + 5)),
                     std::abs(Q(r, last, i + 6))});
  }
  const double k = contact_law::CombineStiffness(1e6, 1e6);
  const double sink = 2.0 * kG * (5 + 4 + 3 + 2 + 1) / k;  // each interface carries the boxes above
  const double top = Q(r, last, 7 * 4 + 2);
  printf("RESULT stack sideways %.3g m turn %.3g top sink %.9g expected %.9g\n", sideways, turn,
         0.9 - top, sink);
  EXPECT_LT(sideways, 1e-6);
  EXPECT_LT(turn, 1e-6);
  EXPECT_NEAR((0.9 - top) / sink, 1.0, 1e-4);
}

// Five boxes stacked off-centre and turned (tests/data/contact/messy_stack.sdf) stand for 10 s:
// the stack leans by its contacts' compliance (the off-centre loads sink the faces unevenly) and
// comes to rest. With box-box culled to 4 of its overlap's up to 8 points, which 4 jumped as a
// box tilted and BDF stalled: 1,050,000 steps (283 s of CPU) without passing t = 7.2 ms.
TEST(ContactScenesTest, AMessyStackOfTurnedOffCentreBoxesStandsForTenSeconds) {
  const Model model = Scene("messy_stack.sdf");
  RunConfig config;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.duration = 10.0;
  config.output_interval = 0.1;
  config.contact.stiffness = 1e6;
  config.contact.dissipation = 20.0;
  config.max_steps = 100000;
  const RunResult r = RunScene(model, config);
  ASSERT_EQ(r.t.size(), 101u);
  const size_t last = r.t.size() - 1;
  double sideways = 0.0, speed = 0.0;
  for (int b = 0; b < 5; ++b) {
    const int i = 7 * b;
    sideways = std::max(sideways,
                        std::hypot(Q(r, last, i) - Q(r, 0, i), Q(r, last, i + 1) - Q(r, 0, i + 1)));
    EXPECT_NEAR(Q(r, last, i + 2), 0.1 + 0.2 * b, 1e-3) << "box" << b;  // on the one below
  }
  for (int k = 0; k < model.nv(); ++k) speed = std::max(speed, std::abs(Qd(r, last, k)));
  printf("RESULT messy stack: %ld steps, sideways %.3g m, speed at 10 s %.3g\n",
         r.stats.solver.steps, sideways, speed);
  EXPECT_LT(sideways, 1e-3);                            // m: leaning, not sliding off
  EXPECT_LT(speed, config.contact.stiction_tolerance);  // at rest
}

// Cylinders and capsules on a table's face (NarrowPhase::FaceContacts): the round shape's
// points under the face of least overlap, as on a plane (a lying cylinder on its two rim
// points, a standing one on four, a capsule on its end spheres), on a box and on a hull. Placed
// exactly touching, each sinks by its weight over the pair's stiffness and stays. With GJK/EPA's
// one point a can on a box table, lying or standing, used 20,000 steps without leaving t = 0.
TEST(ContactScenesTest, RoundShapesRestOnTheFaceOfABoxAndOfAHull) {
  const Model model = Scene("round_on_tables.sdf");
  RunConfig config = Config(1.0, 0.05);
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.contact.dissipation = 20.0;
  const RunResult r = RunScene(model, config);
  ASSERT_EQ(r.t.size(), 21u);
  const size_t last = r.t.size() - 1;
  const double sink = 0.5 * kG / contact_law::CombineStiffness(1e5, 1e5);
  printf("RESULT %ld steps, %ld Newton failures\n", r.stats.solver.steps,
         r.stats.solver.convergence_failures);
  EXPECT_LT(r.stats.solver.steps, 5000);
  for (const char* table : {"box", "mesh"}) {
    for (const auto& [name, height] : std::vector<std::pair<std::string, double>>{
             {"_lying", 0.05}, {"_standing", 0.075}, {"_capsule", 0.04}}) {
      const std::string body = table + name + "::link";
      const int b = model.FindBody(body);
      ASSERT_GE(b, 0) << body;
      const int q = model.bodies[static_cast<size_t>(b)].q_index;
      const int v = model.bodies[static_cast<size_t>(b)].v_index;
      printf("RESULT %s z %.12g expected %.12g\n", body.c_str(), Q(r, last, q + 2), height - sink);
      EXPECT_NEAR(Q(r, last, q + 2), height - sink, 1e-8) << body;
      for (int k : {0, 1, 3, 4, 5, 6}) {  // x, y and the quaternion: where it was put, unturned
        EXPECT_NEAR(Q(r, last, q + k), Q(r, 0, q + k), 1e-8) << body << " coordinate " << k;
      }
      for (int k = 0; k < 6; ++k) EXPECT_LT(std::abs(Qd(r, last, v + k)), 1e-6) << body;
    }
  }
}

// Cans stacked cap on cap (tests/data/contact/stacked_cans.sdf; NarrowPhase::CapContacts): the
// centred stack rests each can sunk the weight above it over k into the one below, unturned;
// the offset, turned stack with a narrower can on top stands too. With GJK/EPA's one point a
// pair, as before, a can on a can rocked on it.
TEST(ContactScenesTest, CansStandStackedOnCans) {
  const Model model = Scene("stacked_cans.sdf");
  RunConfig config = Config(6.0, 0.1);
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.contact.dissipation = 20.0;
  const RunResult r = RunScene(model, config);
  const size_t last = r.t.size() - 1;
  const double k = contact_law::CombineStiffness(1e5, 1e5);
  printf("RESULT %ld steps, %ld Newton failures, peak contacts %d\n", r.stats.solver.steps,
         r.stats.solver.convergence_failures, r.contacts.count_peak);
  EXPECT_LT(r.stats.solver.steps, 40000);
  const auto coordinate = [&](const std::string& can, bool velocity) {
    const int b = model.FindBody(can + "::link");
    EXPECT_GE(b, 0) << can;
    const Body& body = model.bodies[static_cast<size_t>(std::max(b, 0))];
    return velocity ? body.v_index : body.q_index;
  };
  // Stack a: the weight above each cap (the can's own and those on it), 0.5 kg a can.
  double sink = 0.0;
  for (int level = 0; level < 3; ++level) {
    const std::string can = "a" + std::to_string(level);
    sink += (3 - level) * 0.5 * kG / k;
    const int q = coordinate(can, false), v = coordinate(can, true);
    const double expected = 0.075 + 0.15 * level - sink;
    printf("RESULT %s z %.12g expected %.12g\n", can.c_str(), Q(r, last, q + 2), expected);
    EXPECT_NEAR(Q(r, last, q + 2), expected, 1e-8) << can;
    // Where it was put, unturned: the rims' equal polygons clip to points on each other's
    // edges, a few of them in or out by round-off, and the friction creeps below v_s under what
    // is left (measured up to 2.7e-7 over the 6 s).
    for (int c : {0, 1, 3, 4, 5, 6}) {
      EXPECT_NEAR(Q(r, last, q + c), Q(r, 0, q + c), 1e-6) << can << " coordinate " << c;
    }
    for (int c = 0; c < 6; ++c) EXPECT_LT(std::abs(Qd(r, last, v + c)), 1e-6) << can;
  }
  // Stack b: standing, hardly tilted (its lower cans lean on their loads' side, by 2.6e-3 rad
  // at 2 s), at rest by 6 s: the lean settles over about 5 s, and its friction creeps below
  // the stiction tolerance v_s.
  for (const char* can : {"b0", "b1", "b2"}) {
    const int q = coordinate(can, false), v = coordinate(can, true);
    const double tilt = 2.0 * std::hypot(Q(r, last, q + 4), Q(r, last, q + 5));  // rad, about
    printf("RESULT %s z %.9g (from %.9g), tilt %.3g rad\n", can, Q(r, last, q + 2), Q(r, 0, q + 2),
           tilt);
    EXPECT_NEAR(Q(r, last, q + 2), Q(r, 0, q + 2), 1e-3) << can;
    EXPECT_LT(tilt, 1e-2) << can;
    for (int c = 0; c < 6; ++c) {
      EXPECT_LT(std::abs(Qd(r, last, v + c)), config.contact.stiction_tolerance) << can;
    }
  }
}

}  // namespace
}  // namespace mbstream
