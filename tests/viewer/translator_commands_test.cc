// Every command of the scene script language, read correctly.
#include <gtest/gtest.h>

#include <numbers>

#include "tests/viewer/script_test_util.h"
#include "viewer/script/lexer.h"

namespace mbstream::scene_script {
namespace {

using namespace testing;  // NOLINT

Script Translate(const std::string& text) {
  const Translation translation = TranslateScript(text);
  EXPECT_TRUE(translation.ok()) << (translation.ok() ? "" : ErrorsOf(translation).front());
  return translation.script;
}

template <typename T>
const T& ShapeOf(const Script& script, const std::string& name) {
  const PartCommand* part = script.FindPart(name);
  EXPECT_NE(part, nullptr) << name;
  return std::get<T>(part->shape);
}

TEST(Lexer, SplitsWordsNumbersAndPunctuationAndSkipsComments) {
  Diagnostics diagnostics;
  const std::vector<Token> tokens =
      Tokenize("! a comment line\nCube $ a\nblock $ c1 1.5 -2 3e1;(x-150,)", &diagnostics);
  ASSERT_TRUE(diagnostics.empty());
  ASSERT_EQ(tokens.size(), 11u);
  EXPECT_EQ(tokens[0].text, "Cube");
  EXPECT_EQ(tokens[0].position.line, 2);
  EXPECT_EQ(tokens[1].text, "c1");
  EXPECT_EQ(tokens[1].kind, TokenKind::kWord);
  EXPECT_EQ(tokens[1].position.line, 3);
  EXPECT_EQ(tokens[1].position.column, 9);
  EXPECT_EQ(tokens[2].number, 1.5);
  EXPECT_EQ(tokens[3].number, -2);
  EXPECT_EQ(tokens[4].number, 30);
  EXPECT_EQ(tokens[5].kind, TokenKind::kSemicolon);
  EXPECT_EQ(tokens[6].kind, TokenKind::kLeftParen);
  EXPECT_EQ(tokens[7].text, "x-150");
  EXPECT_EQ(tokens[7].kind, TokenKind::kWord);
  EXPECT_EQ(tokens[8].kind, TokenKind::kComma);
  EXPECT_EQ(tokens[9].kind, TokenKind::kRightParen);
  EXPECT_EQ(tokens[10].kind, TokenKind::kEnd);
}

TEST(Lexer, NumbersAreWholeTokensOnly) {
  double v = 0;
  EXPECT_TRUE(ParseNumber("+2", &v));
  EXPECT_EQ(v, 2);
  EXPECT_TRUE(ParseNumber(".5", &v));
  EXPECT_TRUE(ParseNumber("-0.25e-1", &v));
  EXPECT_EQ(v, -0.025);
  for (const char* word : {"inf", "nan", "1.5.3", "12abc", "-", "+", "x1", "0x10"}) {
    EXPECT_FALSE(ParseNumber(word, &v)) << word;
  }
}

TEST(DeviceCommand, ReadsTheSeedDevice) {
  const Script script = Translate(kSeedDevice);
  ASSERT_TRUE(script.device);
  const DeviceCommand& device = *script.device;
  EXPECT_EQ(device.name, "IRB1600");
  EXPECT_EQ(device.placement.euler_deg, Eigen::Vector3d(-90, -90, 0));
  EXPECT_EQ(*device.lbox_mm, 1200);
  ASSERT_EQ(device.joints.size(), 6u);
  const int axes[] = {2, 1, 1, 0, 1, 0};
  for (int i = 0; i < 6; ++i) {
    EXPECT_EQ(device.joints[i].number, i + 1);
    EXPECT_EQ(device.joints[i].parent, i);
    EXPECT_EQ(device.joints[i].axis, axes[i]);
    EXPECT_EQ(device.joints[i].type, JointType::kRevolute);
  }
  EXPECT_EQ(device.joints[1].pre.shift_mm, Eigen::Vector3d(150, 0, 486.5));
  EXPECT_EQ(device.joints[3].pre.shift_mm, Eigen::Vector3d(600, 0, 0));
  ASSERT_TRUE(device.tcp);
  EXPECT_EQ(device.tcp->shift_mm, Eigen::Vector3d(65, 0, 0));
  EXPECT_EQ(device.tcp_frame, 6);
  EXPECT_EQ(*device.initial, std::vector<double>(6, 0.0));
}

TEST(DeviceCommand, PrismaticPostTransformsExtendAndGluedNumbers) {
  const Script script = Translate(R"(
    DEVICE Gantry (Shift x10 y-20 z+30 EULER 90 0 0)
      joint 1 prismatic X (shift z 5)
      JOINT 2 (euler 0 90 0) Revolute y
      Extend 1
      Joint 3 (x-150) revolute z (shift y 7 euler 0 0 45)
      Extend 0
      Joint 4 prismatic z
      TCP (shift z 12)
      Initial (100, 45, -30, 5);)");
  const DeviceCommand& device = *script.device;
  EXPECT_EQ(device.placement.shift_mm, Eigen::Vector3d(10, -20, 30));
  EXPECT_FALSE(device.lbox_mm);
  ASSERT_EQ(device.joints.size(), 4u);
  EXPECT_EQ(device.joints[0].type, JointType::kPrismatic);
  EXPECT_EQ(device.joints[0].axis, 0);
  EXPECT_EQ(device.joints[0].post.shift_mm, Eigen::Vector3d(0, 0, 5));
  EXPECT_EQ(device.joints[1].pre.euler_deg, Eigen::Vector3d(0, 90, 0));
  EXPECT_EQ(device.joints[1].parent, 1);
  EXPECT_EQ(device.joints[2].parent, 1);  // Extend 1
  EXPECT_EQ(device.joints[2].pre.shift_mm, Eigen::Vector3d(-150, 0, 0));
  EXPECT_EQ(device.joints[2].post.euler_deg, Eigen::Vector3d(0, 0, 45));
  EXPECT_EQ(device.joints[3].parent, 0);  // Extend 0
  EXPECT_EQ(device.tcp_frame, 4);
  EXPECT_EQ(*device.initial, (std::vector<double>{100, 45, -30, 5}));
  EXPECT_EQ(device.extends.size(), 2u);
}

TEST(TransformClause, IsShiftAfterZyzEulerRotation) {
  TransformClause clause;
  clause.shift_mm = Eigen::Vector3d(100, 200, 300);
  clause.euler_deg = Eigen::Vector3d(30, 40, 50);
  const double d = std::numbers::pi / 180;
  const Eigen::Isometry3d expected = Eigen::Translation3d(0.1, 0.2, 0.3) *
                                     Eigen::AngleAxisd(30 * d, Eigen::Vector3d::UnitZ()) *
                                     Eigen::AngleAxisd(40 * d, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(50 * d, Eigen::Vector3d::UnitZ());
  EXPECT_TRUE(clause.ToIsometry(0.001).isApprox(expected, 1e-14));
}

TEST(PartCommands, CylinderConeCubeSphereAndStlPart) {
  const Script script = Translate(R"(
    Cylinder Post dia 80 res 12 len 300;
    cylinder Short LEN 10 dia 5;
    Cone Tip (Center x 1 y 2 z 3 Direction x 0 y 0 z -2) dia 40 res 8 len 60;
    Cone Plain dia 10 len 20;
    Cube Block 10 20 30;
    Sphere Ball radius 25 res 16;
    Sphere Dot radius 1;)");
  const auto& post = ShapeOf<CylinderShape>(script, "Post");
  EXPECT_EQ(post.diameter, 80);
  EXPECT_EQ(post.resolution, 12);
  EXPECT_EQ(post.length, 300);
  EXPECT_EQ(ShapeOf<CylinderShape>(script, "Short").resolution, 24);  // default
  const auto& tip = ShapeOf<ConeShape>(script, "Tip");
  EXPECT_EQ(tip.center, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(tip.direction, Eigen::Vector3d(0, 0, -1));  // normalised
  EXPECT_EQ(tip.resolution, 8);
  EXPECT_EQ(ShapeOf<ConeShape>(script, "Plain").direction, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(ShapeOf<CubeShape>(script, "Block").size, Eigen::Vector3d(10, 20, 30));
  EXPECT_EQ(ShapeOf<SphereShape>(script, "Ball").radius, 25);
  EXPECT_EQ(ShapeOf<SphereShape>(script, "Ball").resolution, 16);
  EXPECT_EQ(script.parts.size(), 7u);
  EXPECT_EQ(script.parts[0].keyword, "Cylinder");
  EXPECT_EQ(script.parts[2].keyword, "Cone");
}

TEST(PartCommands, StlPartFoundInAnAssetDirectory) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbstream_stl_part";
  std::filesystem::create_directories(dir);
  WriteTinyStl(dir / "Flange.stl");
  const DirectoryAssetLocator assets({dir});
  TranslateOptions options;
  options.assets = &assets;
  const Translation translation = TranslateScript("Part Flange;", options);
  ASSERT_TRUE(translation.ok());
  EXPECT_EQ(std::get<StlShape>(translation.script.parts[0].shape).resolved_path,
            dir / "Flange.stl");
  std::filesystem::remove_all(dir);
}

TEST(PartCommands, PolyprismWithStraightEdgesAndArcs) {
  const Script script = Translate(R"(
    Polyprism Plate Height 20 0 0 100 0 100 50
      Arc to 0 50 radius 50 res 8
      ;
    Polyprism Cam height 5 0 0 10 0 arc large to 0 0 radius -6 res 20 ;)");
  const auto& plate = ShapeOf<PolyprismShape>(script, "Plate");
  EXPECT_EQ(plate.height, 20);
  ASSERT_EQ(plate.steps.size(), 4u);
  EXPECT_FALSE(plate.steps[2].arc);
  EXPECT_TRUE(plate.steps[3].arc);
  EXPECT_FALSE(plate.steps[3].large);
  EXPECT_EQ(plate.steps[3].radius, 50);
  EXPECT_EQ(plate.steps[3].resolution, 8);
  EXPECT_EQ(plate.steps[3].to, Eigen::Vector2d(0, 50));
  const auto& cam = ShapeOf<PolyprismShape>(script, "Cam");
  EXPECT_TRUE(cam.steps[2].large);
  EXPECT_EQ(cam.steps[2].radius, -6);
}

TEST(PartCommands, TheSeedWedgeModule) {
  const Script script = Translate(R"(
Module Wedge
Points
0 0.0 0.0 0.0
1 50.0 15.0 0.0
2 50.0 75.0 0.0
3 0.0 75.0 0.0
4 50.0 15.0 15.0
5 50.0 75.0 15.0
6 0.0 75.0 20.0
7 0.0 0.0 20.0
Polygons
(0 1 2 3)
(1 2 5 4)(2 3 6 5)
(3 6 7 0)
(7, 4, 1, 0)(4 5 6 7)
;)");
  const auto& wedge = ShapeOf<ModuleShape>(script, "Wedge");
  ASSERT_EQ(wedge.points.size(), 8u);
  EXPECT_EQ(wedge.point_ids[6], 6);
  EXPECT_EQ(wedge.points[6], Eigen::Vector3d(0, 75, 20));
  ASSERT_EQ(wedge.polygons.size(), 6u);
  EXPECT_EQ(wedge.polygons[4], (std::vector<int>{7, 4, 1, 0}));
  EXPECT_EQ(wedge.polygons[5], (std::vector<int>{4, 5, 6, 7}));
}

TEST(AssemblyCommands, SetRenderProbe) {
  const Script script = Translate(std::string(kSeedDevice) + R"(
    Cube A 10 10 10;
    Sphere B radius 5;
    Set Pair add A (shift x 10) add B (y-20 euler 0 0 90);
    Set IRB1600#2 add Pair (shift x-150 z -486.5) A;
    Set IRB1600 add B;
    Render Pair color 1 0 0;
    render IRB1600#2 COLOUR 0.5 0.5 0.5;
    Render A colour 0 0.25 1.0;
    Probe Tip IRB1600#6 (shift x 65) refer IRB1600;
    Probe Fixed World (shift z 100);
    Probe Base IRB1600 refer IRB1600#3;)");
  ASSERT_EQ(script.sets.size(), 3u);
  const SetCommand& pair = *script.FindSet("Pair");
  ASSERT_EQ(pair.components.size(), 2u);
  EXPECT_EQ(pair.components[0].placement.shift_mm, Eigen::Vector3d(10, 0, 0));
  EXPECT_EQ(pair.components[1].placement.shift_mm, Eigen::Vector3d(0, -20, 0));
  EXPECT_EQ(pair.components[1].placement.euler_deg, Eigen::Vector3d(0, 0, 90));
  const SetCommand& link2 = *script.FindSet("IRB1600#2");
  EXPECT_EQ(link2.components[0].placement.shift_mm, Eigen::Vector3d(-150, 0, -486.5));
  EXPECT_EQ(link2.components[1].name, "A");
  ASSERT_EQ(script.renders.size(), 3u);
  EXPECT_EQ(script.FindRender("Pair")->color, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(script.FindRender("A")->color, Eigen::Vector3d(0, 0.25, 1));
  ASSERT_EQ(script.probes.size(), 3u);
  EXPECT_EQ(script.probes[1].frame_in, "World");
  EXPECT_EQ(script.probes[1].refer, "World");  // Refer left out
  EXPECT_EQ(script.probes[2].offset.shift_mm, Eigen::Vector3d::Zero());
  EXPECT_EQ(script.probes[2].refer, "IRB1600#3");
}

TEST(Comments, LinesAndBlocksAnywhere) {
  const Script script = Translate(R"(! heading
    $ a block
      spanning lines; Cube Hidden 1 1 1; $
    Cube Shown $inline$ 1 2 3; ! trailing
    ;;)");
  EXPECT_EQ(script.parts.size(), 1u);
  EXPECT_EQ(script.parts[0].name, "Shown");
}

}  // namespace
}  // namespace mbstream::scene_script
