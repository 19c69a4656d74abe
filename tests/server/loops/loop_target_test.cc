// Accuracy targets on mechanisms with closed loops (server/choose/loop_target_run.h): the
// four-bar's passive run meets a target, verified by a tighter run of the mechanism; a driven
// run is the closed form; a method without a tolerance of its own is refused.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "server/engine/engine.h"
#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";

RunConfig PassiveWithTarget(const Model& model) {
  RunConfig config;  // models/linkages/four_bar-passive.json with a target instead of a method
  config.duration = 2.0;
  config.output_interval = 0.01;
  config.drives.assign(model.num_dofs(), DriveConfig{});
  config.formulation = Formulation::kAuto;
  config.method_auto = true;
  config.target.joint_error_rad = 1e-4;
  return config;
}

TEST(LoopTargetTest, TheFourBarsPassiveRunMeetsItsTargetVerified) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const RunConfig config = PassiveWithTarget(sdf.model);
  EXPECT_EQ(ValidateLoopRun(sdf.model, sdf.loops, config).formulation, Formulation::kJoint);
  const RunResult result = Simulate(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "joint");
  ASSERT_TRUE(result.stats.target_met.has_value()) << result.stats.message;
  EXPECT_TRUE(*result.stats.target_met) << result.stats.message << "\n" << result.stats.choice_json;
  const auto choice = nlohmann::json::parse(result.stats.choice_json);
  ASSERT_EQ(choice["candidates"].size(), 2u);
  EXPECT_EQ(choice["candidates"][0]["name"], "bdf");
  EXPECT_EQ(choice["candidates"][1]["name"], "ida");
  EXPECT_TRUE(choice["verification"]["ran"].get<bool>());
  const double joint = choice["verification"]["achieved"]["joint_rad"].get<double>();
  EXPECT_LT(joint, 1e-4);
  EXPECT_GT(joint, 1e-7);  // measured, not assumed
  // The loops held as the chosen tolerance promises.
  EXPECT_LT(result.stats.drift_position_max, 1e-8);
  EXPECT_EQ(result.stats.loops.mobility, 1);
}

// At the loops' smallest tolerance the check is the other method at the same tolerance: IDA on
// the GGL DAE, which runs there since its multipliers got tolerances of their own (before,
// it failed at t = 0 and the run ended unverified, "out of reach"). The four-bar's passive
// swing is not resolved to 1e-9 rad by either: the target is reported missed, with the
// horizon up to which the two agree.
TEST(LoopTargetTest, ATargetBeyondTheLoopsSmallestToleranceIsCheckedByTheOtherMethodThere) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = PassiveWithTarget(sdf.model);
  config.target.joint_error_rad = 1e-9;  // the four-bar reaches 3e-5 rad at rtol 1e-10
  const RunResult result = Simulate(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.stats.target_met.has_value());
  EXPECT_FALSE(*result.stats.target_met);
  EXPECT_THAT(result.stats.message, ::testing::HasSubstr("smallest tolerance 1e-10"));
  EXPECT_THAT(result.stats.message, ::testing::HasSubstr("against ida at rtol 1e-10"));
  EXPECT_THAT(result.stats.message, ::testing::HasSubstr("agree within the target only up to"));
  const auto choice = nlohmann::json::parse(result.stats.choice_json);
  EXPECT_EQ(choice["pick"]["rtol"].get<double>(), 1e-10);
  EXPECT_FALSE(choice["pick"]["resolvable"].get<bool>());
  EXPECT_TRUE(choice["verification"]["ran"].get<bool>());
}

TEST(LoopTargetTest, AFourBarDrivenByItsCrankIsTheClosedForm) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = PassiveWithTarget(sdf.model);
  config.drives[0].kind = DriveConfig::Kind::kPrescribed;
  config.drives[0].trajectory.amplitude = {0.5};
  config.drives[0].trajectory.omega = {M_PI};
  config.drives[0].trajectory.phase = {0.0};
  const RunResult result = Simulate(sdf.model, sdf.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.formulation, "kinematic");
  ASSERT_TRUE(result.stats.target_met.has_value());
  EXPECT_TRUE(*result.stats.target_met);
  const auto choice = nlohmann::json::parse(result.stats.choice_json);
  EXPECT_EQ(choice["pick"]["formulation"], "kinematic");
}

TEST(LoopTargetTest, ATargetWithAMethodTheLoopsCannotTuneIsRefused) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  RunConfig config = PassiveWithTarget(sdf.model);
  config.method_auto = false;
  config.method = Method::kErk;
  try {
    ValidateLoopRun(sdf.model, sdf.loops, config);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use method auto, bdf or ida"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mbstream
