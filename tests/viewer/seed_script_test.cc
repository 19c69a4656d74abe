// The seed chapter's script as printed (its OCR damage repaired) gives exactly its real errors.
#include <gtest/gtest.h>

#include <gmock/gmock.h>

#include "tests/viewer/script_test_util.h"
#include "viewer/model/script_scene.h"

namespace mbstream::scene_script {
namespace {

using ::testing::ElementsAre;
using namespace testing;  // NOLINT

const char* kBodies[] = {
    "IRB1600_X-120_m2004_rev0_01-1_Body0", "IRB1600_X-120_m2004_rev0_01-7_Body1",
    "IRB1600_X-120_m2004_rev0_01-4_Body2", "IRB1600_X-120_m2004_rev0_01-5_Body3",
    "IRB1600_X-120_m2004_rev0_01-3_Body4", "IRB1600_X-120_m2004_rev0_01-2_Body5",
    "IRB1600_X-120_m2004_rev0_01-6_Body6"};

const std::string kRenderError =
    "30:8: undefined name 'IRB1600_12#5' in Render (did you mean IRB1600#5?); define it with "
    "Set or a part command (Cylinder, Cone, Cube, Sphere, Polyprism, Module, Part) above this "
    "line";

std::string SeedScript() { return ReadFile(SourcePath("tests/viewer/data/seed_script.txt")); }

TEST(SeedScript, WithoutAssetsGivesTheSevenMissingPartsAndTheUndefinedRenderTarget) {
  const std::vector<std::string> errors = Errors(SeedScript());
  std::vector<std::string> expected;
  for (int i = 0; i < 7; ++i) {
    expected.push_back(std::to_string(12 + i) + ":6: Part '" + kBodies[i] + "': STL file '" +
                       kBodies[i] +
                       ".stl' not found (no asset directory given); supply the STL file or "
                       "build the part from primitives");
  }
  expected.push_back(kRenderError);
  EXPECT_EQ(errors, expected);
}

TEST(SeedScript, WithItsStlFilesGivesOnlyTheUndefinedRenderTarget) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbstream_seed_stl";
  std::filesystem::create_directories(dir);
  for (const char* body : kBodies) WriteTinyStl(dir / (std::string(body) + ".stl"));
  const DirectoryAssetLocator assets({dir});
  TranslateOptions options;
  options.assets = &assets;
  EXPECT_THAT(Errors(SeedScript(), options), ElementsAre(kRenderError));

  // With the typo repaired the script translates and builds a scene.
  std::string repaired = SeedScript();
  repaired.replace(repaired.find("IRB1600_12#5"), 12, "IRB1600#5");
  const Translation translation = TranslateScript(repaired, options);
  ASSERT_TRUE(translation.ok()) << ErrorsOf(translation).front();
  const viewer::SceneDescription scene = viewer::SceneFromScript(translation.script);
  EXPECT_EQ(scene.chain.dof(), 6);
  EXPECT_EQ(scene.visuals.size(), 7u);
  ASSERT_EQ(scene.probes.size(), 1u);
  EXPECT_EQ(scene.probes[0].refer_name, "IRB1600");
  EXPECT_EQ(scene.probes[0].frame, 6);
  EXPECT_DOUBLE_EQ(*scene.scene_box_m, 1.2);
  for (const viewer::VisualPart& visual : scene.visuals) {
    EXPECT_TRUE(std::holds_alternative<viewer::MeshFile>(visual.geometry));
    EXPECT_EQ(visual.color, Eigen::Vector3d::Constant(0.5));
  }
  // Body2's component shift (x-150 z -486.5) is glued and kept, in metres.
  EXPECT_TRUE(
      scene.visuals[2].placement.translation().isApprox(Eigen::Vector3d(-0.15, 0, -0.4865)));
  EXPECT_EQ(scene.visuals[2].frame, 2);
  std::filesystem::remove_all(dir);
}

TEST(SeedScript, IsTranslatedCommandByCommand) {
  const Translation translation = TranslateScript(SeedScript());
  const Script& script = translation.script;
  ASSERT_TRUE(script.device);
  EXPECT_EQ(script.device->name, "IRB1600");
  EXPECT_EQ(script.device->joints.size(), 6u);
  EXPECT_EQ(script.parts.size(), 7u);
  EXPECT_EQ(script.sets.size(), 7u);
  EXPECT_EQ(script.renders.size(), 6u);  // the undefined target is left out
  ASSERT_EQ(script.probes.size(), 1u);
  EXPECT_EQ(script.probes[0].frame_in, "IRB1600#6");
  EXPECT_EQ(script.probes[0].refer, "IRB1600");
  EXPECT_EQ(script.probes[0].offset.shift_mm, Eigen::Vector3d(65, 0, 0));
}

}  // namespace
}  // namespace mbstream::scene_script
