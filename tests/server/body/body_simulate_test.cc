// The body formulations on the seed scenario: TCP against direct kinematics, constraint
// drift, drive torques against the joint formulation, and the reported sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "server/engine/engine.h"
#include "server/sim/run_validation.h"
#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::SeedRun;

class BodySeedAccuracyTest
    : public ::testing::TestWithParam<std::tuple<Formulation, Method, double>> {};

TEST_P(BodySeedAccuracyTest, TcpErrorWithinTenTimesRtolAndDriftReported) {
  const auto& [formulation, method, rtol] = GetParam();
  const RunConfig config = SeedRun(formulation, method, rtol);
  const RunResult result = Simulate(Irb1600(), config);
  const RunStats& s = result.stats;
  ASSERT_EQ(s.status, RunStatus::kFinished) << s.message;
  EXPECT_EQ(s.formulation, FormulationName(formulation));
  EXPECT_EQ(result.num_frames(), 401);
  std::printf(
      "%s/%s rtol %.0e: TCP error %.3g m, drift position %.3g m, orientation %.3g, "
      "velocity %.3g, |e|-1 %.3g, steps %ld, cpu %.3g s\n",
      FormulationName(formulation), MethodName(method), rtol, s.tcp_error_max, s.drift_position_max,
      s.drift_orientation_max, s.drift_velocity_max, s.quaternion_norm_error_max, s.solver.steps,
      s.cpu_s);
  EXPECT_LE(s.tcp_error_max, 10 * rtol);
  EXPECT_GE(s.drift_position_max, 0.0);
  EXPECT_GE(s.drift_orientation_max, 0.0);
  EXPECT_GE(s.drift_velocity_max, 0.0);
  EXPECT_GE(s.quaternion_norm_error_max, 0.0);
  EXPECT_LE(s.drift_position_max, 10 * rtol);
}

INSTANTIATE_TEST_SUITE_P(
    Tolerances, BodySeedAccuracyTest,
    ::testing::Values(std::make_tuple(Formulation::kBodyIndex2, Method::kIda, 1e-4),
                      std::make_tuple(Formulation::kBodyIndex2, Method::kIda, 1e-5),
                      std::make_tuple(Formulation::kBodyIndex2, Method::kIda, 1e-6),
                      std::make_tuple(Formulation::kBodyIndex2, Method::kIda, 1e-7),
                      std::make_tuple(Formulation::kBodyIndex2, Method::kIda, 1e-8),
                      std::make_tuple(Formulation::kBodyBaumgarte, Method::kBdf, 1e-4),
                      std::make_tuple(Formulation::kBodyBaumgarte, Method::kBdf, 1e-5),
                      std::make_tuple(Formulation::kBodyBaumgarte, Method::kBdf, 1e-6),
                      std::make_tuple(Formulation::kBodyBaumgarte, Method::kBdf, 1e-7),
                      std::make_tuple(Formulation::kBodyBaumgarte, Method::kBdf, 1e-8)),
    [](const auto& info) {
      const double rtol = std::get<2>(info.param);
      return std::string(std::get<0>(info.param) == Formulation::kBodyIndex2 ? "index2"
                                                                             : "baumgarte") +
             "_rtol1e" + std::to_string(static_cast<int>(std::round(-std::log10(rtol))));
    });

}  // namespace
}  // namespace mbstream

namespace mbstream {
namespace {

// max over frames of |a - b|, per joint relative to that joint's largest |b|; the worst joint.
double TorqueRelativeDifference(const RunResult& a, const RunResult& b) {
  const int n = b.num_dofs;
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    double scale = 0.0, diff = 0.0;
    for (int k = 0; k < b.num_frames(); ++k) {
      scale = std::max(scale, std::abs(b.tau[k * n + i]));
      diff = std::max(diff, std::abs(a.tau[k * n + i] - b.tau[k * n + i]));
    }
    worst = std::max(worst, diff / scale);
  }
  return worst;
}

// The largest relative energy balance error of `r` with the work of the drives the
// trapezoid rule over its frames (the arm has no damping): what a formulation without the
// work state (body-index2) reports, computed for a run that has one.
double TrapezoidEnergyError(const RunResult& r) {
  const int n = r.num_dofs;
  double work = 0.0, last_power = 0.0, scale = 0.0, worst = 0.0;
  const double energy0 = r.kinetic[0] + r.potential[0];
  for (int k = 0; k < r.num_frames(); ++k) {
    double power = 0.0;
    for (int i = 0; i < n; ++i) power += r.tau[k * n + i] * r.qd[k * n + i];
    if (k > 0) work += 0.5 * (power + last_power) * (r.t[k] - r.t[k - 1]);
    last_power = power;
    const double energy = r.kinetic[k] + r.potential[k];
    scale = std::max({scale, std::abs(energy0), std::abs(energy)});
    worst = std::max(worst, std::abs(energy - energy0 - work) / scale);
  }
  return worst;
}

class BodyTorqueTest : public ::testing::TestWithParam<std::pair<Formulation, Method>> {};

TEST_P(BodyTorqueTest, SameDriveTorquesAsJointFormulation) {
  RunConfig joint = testing::SeedRun(Formulation::kJoint, Method::kErk, 1e-10);
  joint.want_torques = true;
  const RunResult reference = Simulate(testing::Irb1600(), joint);
  ASSERT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
  RunConfig body = testing::SeedRun(GetParam().first, GetParam().second, 1e-10);
  body.want_torques = true;
  const RunResult result = Simulate(testing::Irb1600(), body);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.has_torques);
  ASSERT_EQ(result.num_frames(), reference.num_frames());
  const double difference = TorqueRelativeDifference(result, reference);
  std::printf("%s: drive torques differ from the joint formulation's by %.3g (relative)\n",
              FormulationName(GetParam().first), difference);
  EXPECT_LT(difference, 1e-6);
  // Energy balance with the drives' work: integrated with the motion by the joint
  // formulation and body-baumgarte, the trapezoid over the frames for body-index2, which is
  // then compared with the same trapezoid over the reference's frames.
  const bool trapezoid = result.stats.energy_work_approximate;
  EXPECT_EQ(trapezoid, GetParam().first == Formulation::kBodyIndex2);
  EXPECT_FALSE(reference.stats.energy_work_approximate);
  const double expected =
      trapezoid ? TrapezoidEnergyError(reference) : reference.stats.energy_error_max;
  EXPECT_LT(result.stats.energy_error_max, 1.2 * expected + 1e-9);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, BodyTorqueTest,
    ::testing::Values(std::make_pair(Formulation::kBodyIndex2, Method::kIda),
                      std::make_pair(Formulation::kBodyBaumgarte, Method::kBdf)),
    [](const auto& info) {
      return std::string(info.param.first == Formulation::kBodyIndex2 ? "index2" : "baumgarte");
    });

TEST(BodySimulateTest, ReportsSizesOfTheIrb1600) {
  struct Expected {
    Formulation formulation;
    Method method;
    const char* scene;
    int equations;
  };
  // seed-run: 6 prescribed joints (6 rows each); seed-servo: none prescribed (5 rows each).
  const Expected cases[] = {
      {Formulation::kBodyIndex3, Method::kIda, "seed-run", 78 + 36},
      {Formulation::kBodyIndex2, Method::kIda, "seed-run", 78 + 36},
      {Formulation::kBodyBaumgarte, Method::kBdf, "seed-run", 78},
      {Formulation::kBodyIndex3, Method::kIda, "seed-servo", 78 + 30},
      {Formulation::kBodyIndex2, Method::kIda, "seed-servo", 78 + 30},
      {Formulation::kBodyBaumgarte, Method::kBdf, "seed-servo", 78},
  };
  for (const Expected& e : cases) {
    RunConfig config = testing::Scene(e.scene);
    config.formulation = e.formulation;
    config.method = e.method;
    config.duration = 0.1;
    const RunResult result = Simulate(testing::Irb1600(), config);
    EXPECT_EQ(result.stats.equations, e.equations) << e.scene;
    EXPECT_GT(result.stats.jacobian_nnz, result.stats.equations);
    std::printf("%s %s: %d equations, %d Jacobian non-zeros, integrator %s\n", e.scene,
                FormulationName(e.formulation), result.stats.equations, result.stats.jacobian_nnz,
                result.stats.integrator.c_str());
  }
}

TEST(BodySimulateTest, ServoSceneAgreesWithJointFormulation) {
  RunConfig joint = testing::Scene("seed-servo");
  joint.duration = 5.0;
  joint.rtol = 1e-9;
  joint.atol = 1e-11;
  const RunResult reference = Simulate(testing::Irb1600(), joint);
  for (const auto& [formulation, method] :
       {std::make_pair(Formulation::kBodyIndex2, Method::kIda),
        std::make_pair(Formulation::kBodyBaumgarte, Method::kBdf)}) {
    RunConfig body = joint;
    body.formulation = formulation;
    body.method = method;
    const RunResult result = Simulate(testing::Irb1600(), body);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
    double tcp = 0.0, q = 0.0;
    for (size_t k = 0; k < result.tcp.size(); ++k) {
      tcp = std::max(tcp, std::abs(result.tcp[k] - reference.tcp[k]));
    }
    for (size_t k = 0; k < result.q.size(); ++k) {
      q = std::max(q, std::abs(result.q[k] - reference.q[k]));
    }
    EXPECT_LT(tcp, 1e-6) << FormulationName(formulation);
    EXPECT_LT(q, 1e-6) << FormulationName(formulation);
    EXPECT_LT(TorqueRelativeDifference(result, reference), 1e-5) << FormulationName(formulation);
  }
}

TEST(BodySimulateTest, RefusesMethodsOfTheWrongKind) {
  RunConfig config = testing::Scene("seed-run");
  config.formulation = Formulation::kBodyIndex2;
  config.method = Method::kBdf;
  EXPECT_THROW(ValidateRun(testing::Irb1600(), config), InputError);
  config.formulation = Formulation::kBodyBaumgarte;
  config.method = Method::kIda;
  EXPECT_THROW(ValidateRun(testing::Irb1600(), config), InputError);
}

}  // namespace
}  // namespace mbstream

namespace mbstream {
namespace {

// Rotor inertia and damping as the joint formulation models them (the dense mass-matrix
// path of the acceleration solve, and the residual's armature terms).
TEST(BodySimulateTest, ArmatureAndDampingAsInJointFormulation) {
  Model model = testing::Irb1600();
  for (int i = 0; i < model.num_dofs(); ++i) {
    model.bodies[i].joint.armature = 0.02 * (i + 1);
    model.bodies[i].joint.damping = 1.5;
  }
  RunConfig joint = testing::Scene("seed-servo");
  joint.duration = 3.0;
  joint.rtol = 1e-9;
  joint.atol = 1e-11;
  const RunResult reference = Simulate(model, joint);
  ASSERT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
  for (const auto& [formulation, method] :
       {std::make_pair(Formulation::kBodyIndex2, Method::kIda),
        std::make_pair(Formulation::kBodyBaumgarte, Method::kBdf)}) {
    RunConfig body = joint;
    body.formulation = formulation;
    body.method = method;
    const RunResult result = Simulate(model, body);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
    double q = 0.0;
    for (size_t k = 0; k < result.q.size(); ++k) {
      q = std::max(q, std::abs(result.q[k] - reference.q[k]));
    }
    EXPECT_LT(q, 1e-6) << FormulationName(formulation);
    EXPECT_LT(TorqueRelativeDifference(result, reference), 1e-5) << FormulationName(formulation);
  }
}

}  // namespace
}  // namespace mbstream

namespace mbstream {
namespace {

// The run spec's JSON reaches the body formulations: names, method and Baumgarte parameters.
TEST(BodySimulateTest, RunSpecJsonSelectsBodyFormulationAndBaumgarte) {
  v1::RunSpec spec = LoadRunSpecFile("models/irb1600/seed-run.json");
  const v1::RunSpec overrides = ParseRunSpecJson(
      R"({"formulation": "body-baumgarte", "method": "bdf", "duration_s": 5,
          "baumgarte": {"alpha": 0, "beta": 0}})",
      "test");
  spec.MergeFrom(overrides);
  std::vector<std::string> joints;
  for (const Body& body : testing::Irb1600().bodies) joints.push_back(body.joint.name);
  const RunConfig config = ToRunConfig(spec, joints, "test");
  EXPECT_EQ(config.formulation, Formulation::kBodyBaumgarte);
  EXPECT_EQ(config.baumgarte.alpha, 0.0);
  EXPECT_EQ(config.baumgarte.beta, 0.0);
  const RunResult result = Simulate(testing::Irb1600(), config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "body-baumgarte");
  EXPECT_NE(result.stats.formulation_reason.find("alpha = 0"), std::string::npos)
      << result.stats.formulation_reason;
}

}  // namespace
}  // namespace mbstream
