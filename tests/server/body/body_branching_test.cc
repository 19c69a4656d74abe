// The body formulations on the branching test model: a tree with prismatic and revolute
// joints about skew axes, a fixed link, armature and damping, against the joint formulation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "server/engine/engine.h"
#include "tests/common/test_models.h"
#include "tests/server/body/body_test_util.h"

namespace mbstream {
namespace {

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double d = 0.0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

class BodyBranchingTest : public ::testing::TestWithParam<std::pair<Formulation, Method>> {};

TEST_P(BodyBranchingTest, FreeMotionMatchesJointFormulation) {
  const Model model = testing::BranchingModel();
  RunConfig joint = testing::BranchingDrives(model, /*all_prescribed=*/false);
  joint.formulation = Formulation::kJoint;
  joint.rtol = 1e-10;
  joint.atol = 1e-12;
  const RunResult reference = Simulate(model, joint);
  ASSERT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
  RunConfig body = joint;
  body.formulation = GetParam().first;
  body.method = GetParam().second;
  body.rtol = 1e-9;
  body.atol = 1e-11;
  const RunResult result = Simulate(model, body);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_EQ(result.num_frames(), reference.num_frames());
  const double q = MaxDifference(result.q, reference.q);
  const double tcp = MaxDifference(result.tcp, reference.tcp);
  std::printf("%s: q differs by %.3g, TCP by %.3g m; %d equations, %d non-zeros\n",
              FormulationName(body.formulation), q, tcp, result.stats.equations,
              result.stats.jacobian_nnz);
  EXPECT_LT(q, 1e-6);
  EXPECT_LT(tcp, 1e-6);
  EXPECT_LT(MaxDifference(result.tau, reference.tau), 1e-5);
}

TEST_P(BodyBranchingTest, PrescribedMotionGivesInverseDynamicsEfforts) {
  const Model model = testing::BranchingModel();
  RunConfig kinematic = testing::BranchingDrives(model, /*all_prescribed=*/true);
  kinematic.formulation = Formulation::kKinematic;
  const RunResult reference = Simulate(model, kinematic);
  RunConfig body = kinematic;
  body.formulation = GetParam().first;
  body.method = GetParam().second;
  body.rtol = 1e-10;
  body.atol = 1e-12;
  const RunResult result = Simulate(model, body);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  double scale = 0.0;
  for (double tau : reference.tau) scale = std::max(scale, std::abs(tau));
  const double difference = MaxDifference(result.tau, reference.tau) / scale;
  std::printf("%s: efforts differ from inverse dynamics by %.3g (relative), TCP error %.3g m\n",
              FormulationName(body.formulation), difference, result.stats.tcp_error_max);
  EXPECT_LT(difference, 1e-6);
  EXPECT_LT(result.stats.tcp_error_max, 1e-8);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, BodyBranchingTest,
    ::testing::Values(std::make_pair(Formulation::kBodyIndex2, Method::kIda),
                      std::make_pair(Formulation::kBodyBaumgarte, Method::kBdf)),
    [](const auto& info) {
      return std::string(info.param.first == Formulation::kBodyIndex2 ? "index2" : "baumgarte");
    });

}  // namespace
}  // namespace mbstream
