// Hertz contact for spheres (ContactSettings::hertz_modulus; docs/contact.md, "The law"): a
// ball thrown at a plane without gravity stays in contact for the closed-form Hertz impact
// time and leaves at its arrival speed; other pairs keep point contact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "server/contact/contact_law.h"
#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

Model HertzScene(const std::string& name) {
  return ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/" + name).model;
}

// The time z(t) = level between frames k and k + 1, from the cubic Hermite of z and z' there.
double Crossing(const std::vector<double>& t, const std::vector<double>& z,
                const std::vector<double>& v, size_t k, double level) {
  const double h = t[k + 1] - t[k];
  const auto at = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * z[k] + (s3 - 2 * s2 + s) * h * v[k] +
           (-2 * s3 + 3 * s2) * z[k + 1] + (s3 - s2) * h * v[k + 1] - level;
  };
  double lo = 0.0, hi = 1.0;
  const bool rising = at(1.0) > at(0.0);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((at(mid) < 0.0) == rising ? lo : hi) = mid;
  }
  return t[k] + 0.5 * (lo + hi) * h;
}

// m x'' = -K x^1.5 from x' = v: the deepest x_max = (5 m v^2 / (4 K))^(2/5) and the contact
// time T = 2 (x_max / v) \int_0^1 (1 - u^2.5)^(-1/2) du = 2 (x_max / v) (2/5) B(2/5, 1/2).
TEST(HertzContactTest, ABallStaysInContactForTheHertzImpactTime) {
  const Model model = HertzScene("ball_on_plane.sdf");  // 1 kg, r = 0.1 m, centre at 1 m
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.method = Method::kBdf;
  config.duration = 0.5;
  config.output_interval = 1e-5;
  config.rtol = 1e-10;
  config.atol = 1e-13;
  config.want_torques = false;
  config.gravity.setZero();
  config.contact.dissipation = 0.0;
  config.contact.hertz_modulus = 1e7;  // Pa
  const double v = 2.0, r = 0.1, m = 1.0;
  config.qd0 = Eigen::VectorXd::Zero(model.nv());
  config.qd0(2) = -v;
  config.drives.resize(static_cast<size_t>(model.nv()));
  ValidateRun(model, config);
  const RunResult run = Simulate(model, config);
  ASSERT_EQ(run.stats.status, RunStatus::kFinished) << run.stats.message;
  std::vector<double> z, vz;
  for (size_t f = 0; f < run.t.size(); ++f) {
    z.push_back(run.q[f * run.num_positions + 2]);
    vz.push_back(run.qd[f * run.num_dofs + 2]);
  }
  double begin = -1.0, end = -1.0, lowest = 1.0;
  for (size_t k = 0; k + 1 < z.size(); ++k) {
    lowest = std::min(lowest, z[k]);
    if (begin < 0.0 && z[k] >= r && z[k + 1] < r) begin = Crossing(run.t, z, vz, k, r);
    if (begin >= 0.0 && end < 0.0 && z[k] < r && z[k + 1] >= r) end = Crossing(run.t, z, vz, k, r);
  }
  ASSERT_GT(begin, 0.0);
  ASSERT_GT(end, begin);
  const double K = contact_law::HertzStiffness(1e7, r, std::numeric_limits<double>::infinity());
  const double x_max = std::pow(5.0 * m * v * v / (4.0 * K), 0.4);
  const double integral = 0.4 * std::tgamma(0.4) * std::tgamma(0.5) / std::tgamma(0.9);
  const double expected = 2.0 * x_max / v * integral;
  const double measured = end - begin;
  printf(
      "RESULT Hertz impact time %.10g s, closed form %.10g s, rel %.3g; deepest %.6g m "
      "(closed form %.6g m); arrival at %.10g s (0.45 s)\n",
      measured, expected, measured / expected - 1.0, r - lowest, x_max, begin);
  EXPECT_NEAR(begin, 0.9 / v, 1e-9);
  EXPECT_NEAR(measured / expected, 1.0, 1e-8);
  EXPECT_NEAR(r - lowest, x_max, 1e-3 * x_max);  // sampled at the frames: a little shallower
  EXPECT_NEAR(vz.back(), v, 1e-6 * v);           // elastic: back up at the arrival speed
}

TEST(HertzContactTest, AnAbsurdModulusIsRefusedByName) {
  const Model model = HertzScene("ball_on_plane.sdf");
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.drives.resize(static_cast<size_t>(model.nv()));
  for (const double bad : {-1.0, 1e20, std::nan("")}) {
    config.contact.hertz_modulus = bad;
    try {
      ValidateRun(model, config);
      FAIL() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("contact.hertz_modulus"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mbstream
