// Trust that follows the tolerance on real closed-loop runs (issue 42, item 4): a four-bar
// whose constraints drift beyond what its rtol allows is flagged with what to change, the
// same run projected is trusted; the energy balance of an unprojected loop counts the
// constraint forces' work (the multipliers' power) and stays within its tolerance's limit.
#include <gmock/gmock.h>

#include <cstdio>
#include <string>

#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_trust.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";

RunConfig PassiveFourBar(const SdfImport& sdf) {
  RunConfig config;
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.drives.assign(static_cast<size_t>(sdf.model.num_dofs()), DriveConfig{});
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.q0 = Eigen::Vector3d(0.3, 0.0, 0.0);  // assembled near it: the crank swings
  return config;
}

// Adams is not projected: with no Baumgarte gains nothing holds the loop, and its drift at
// rtol 1e-10 is far beyond what that tolerance allows.
TEST(LoopTrustTest, AnUnheldLoopDriftingBeyondItsToleranceIsFlagged) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = PassiveFourBar(sdf);
  config.method = Method::kAdams;
  config.baumgarte.alpha = 0.0;
  config.baumgarte.beta = 0.0;
  config.duration = 20.0;
  const RunResult drifting = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(drifting.stats.status, RunStatus::kFinished) << drifting.stats.message;
  const TrustLimits limits = TrustLimitsOf(TrustScaleOf(sdf.model, config, Formulation::kJoint));
  std::printf("four-bar, adams, no gains, rtol 1e-10: drift %.3g m (limit %.3g m), energy %.3g\n",
              drifting.stats.drift_position_max, limits.length, drifting.stats.energy_error_max);
  EXPECT_GT(drifting.stats.drift_position_max, limits.length);
  EXPECT_LT(drifting.stats.drift_position_max, kTrustDriftPosition);  // ok under the old limit
  EXPECT_EQ(drifting.stats.trust, Trust::kLow);
  EXPECT_THAT(drifting.stats.trust_reason, HasSubstr("constraint drift (m)"));
  EXPECT_THAT(drifting.stats.trust_reason, HasSubstr("relative tolerance 1e-10, absolute 1e-12"));
  EXPECT_THAT(drifting.stats.trust_reason, HasSubstr("use method bdf"));

  config.method = Method::kBdf;  // projected after each step: held to the tolerance
  const RunResult held = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(held.stats.status, RunStatus::kFinished) << held.stats.message;
  std::printf("four-bar, bdf projected: drift %.3g m, energy %.3g\n", held.stats.drift_position_max,
              held.stats.energy_error_max);
  EXPECT_EQ(held.stats.trust, Trust::kOk) << held.stats.trust_reason;
}

// With the Baumgarte gains and no projection the constraint forces do work wherever the
// velocity constraints are off (ClosedLoopOde::ConstraintPower, counted in the balance): the
// passive four-bar balances within what its tolerance allows, and is trusted.
TEST(LoopTrustTest, AnUnprojectedLoopBalancesWithinItsTolerance) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = PassiveFourBar(sdf);
  config.method = Method::kAdams;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  const RunResult result = SimulateLoops(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  std::printf("four-bar, adams, Baumgarte: drift %.3g m, energy %.3g\n",
              result.stats.drift_position_max, result.stats.energy_error_max);
  EXPECT_EQ(result.stats.trust, Trust::kOk) << result.stats.trust_reason;
  const TrustLimits limits = TrustLimitsOf(TrustScaleOf(sdf.model, config, Formulation::kJoint));
  EXPECT_LT(result.stats.energy_error_max, limits.energy);
}

}  // namespace
}  // namespace mbstream
