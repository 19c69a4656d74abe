// Every error message of the translator: position, what was expected, what to do.
#include <gtest/gtest.h>

#include <gmock/gmock.h>

#include "tests/viewer/script_test_util.h"

namespace mbstream::scene_script {
namespace {

using ::testing::ElementsAre;
using namespace testing;  // NOLINT

struct Case {
  const char* name;
  std::string script;
  std::vector<std::string> errors;
};

// Names the case in test names instead of dumping its bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::string Dev(const std::string& rest) { return std::string(kSeedDevice) + rest; }

// kSeedDevice has 9 lines; line 10 is the first after it.
const std::vector<Case>& Cases() {
  static const std::vector<Case> cases = {
      // ---- lexer and command level
      {"UnknownCommand",
       "Cylnder C dia 1 len 2;\nCube A 1 1 1;",
       {"1:1: expected a command (Device, Cylinder, Cone, Cube, Sphere, Polyprism, Module, "
        "Part, Set, Render or Probe), found 'Cylnder' (did you mean Cylinder?)"}},
      {"NumberInsteadOfCommand",
       "12;",
       {"1:1: expected a command (Device, Cylinder, Cone, Cube, Sphere, Polyprism, Module, "
        "Part, Set, Render or Probe), found number 12"}},
      {"MissingSemicolonBeforeNextCommand",
       "Cube A 1 1 1\nCube B 1 1 1;\nCube B 2 2 2;",
       {"2:1: expected ';' ending the Cube command, found 'Cube'; every command ends with ';'",
        "3:6: 'B' is already defined at line 2; give this Cube another name"}},
      {"MissingSemicolonAtEnd",
       "Cube A 1 1 1",
       {"1:13: expected ';' ending the Cube command, found the end of the script; every "
        "command ends with ';'"}},
      {"UnclosedCommentBlock",
       "Cube A 1 1 1; $ never closed\nCube B 1 1 1;",
       {"1:15: comment block opened with '$' is never closed; add a closing '$'"}},
      // ---- transform clause
      {"TransformUnknownItem",
       "Cube A 1 1 1;\nSet S add A (shift w 3);",
       {"2:20: expected x, y, z, shift or euler in a transform, found 'w'"}},
      {"TransformUnclosed",
       "Cube A 1 1 1;\nSet S add A (x 3;",
       {"2:17: expected ')' closing the transform opened at 2:13, found ';'"}},
      {"TransformAxisTwice",
       "Cube A 1 1 1;\nSet S add A (x 3 x4);",
       {"2:18: x is given twice in one transform; keep one value"}},
      {"TransformAxisWithoutNumber",
       "Cube A 1 1 1;\nSet S add A (x y 3);",
       {"2:16: expected a number after 'x', found 'y'"}},
      {"EulerNeedsThreeAngles",
       "Cube A 1 1 1;\nSet S add A (euler 1 2);",
       {"2:23: expected three Euler angles (degrees) after 'euler', found ')'"}},
      {"LboxOnlyInDevice",
       "Cube A 1 1 1;\nSet S add A (lbox 3);",
       {"2:14: expected x, y, z, shift or euler in a transform, found 'lbox'"}},
      {"LboxMustBePositive",
       "Device D (lbox -5) Joint 1 revolute z;",
       {"1:16: expected the scene box size (mm) after 'lbox', found number -5; it must be "
        "greater than 0"}},
      // ---- Device
      {"JointNumbering",
       "Device D Joint 1 revolute z Joint 3 revolute y;",
       {"1:35: expected Joint 2, found Joint 3; joints are numbered 1, 2, 3 ... in order"}},
      {"JointType",
       "Device D Joint 1 revolut z;",
       {"1:18: expected Revolute or Prismatic for joint 1, found 'revolut' (did you mean "
        "Revolute?)"}},
      {"JointAxis",
       "Device D Joint 1 revolute w;",
       {"1:27: expected the joint axis x, y or z after 'revolute', found 'w'"}},
      {"JointNumberMissing",
       "Device D Joint revolute z;",
       {"1:16: expected the joint number after 'Joint', found 'revolute'"}},
      {"ExtendOutOfRange",
       "Device D Joint 1 revolute z Extend 3 Joint 2 revolute y;",
       {"1:36: Extend 3: only frames 0..1 exist here; branch from the base (0) or a joint "
        "defined above"}},
      {"InitialCount",
       "Device D Joint 1 revolute z Joint 2 revolute y Initial (1 2 3);",
       {"1:48: Initial gives 3 values but the device has 2 joints; give one value per joint "
        "(degrees or mm)"}},
      {"InitialNotANumber",
       "Device D Joint 1 revolute z Initial (a);",
       {"1:38: expected a joint value (degrees or mm) or ')' in Initial, found 'a'"}},
      {"TcpTwice",
       "Device D Joint 1 revolute z Tcp (x 1) Tcp (x 2);",
       {"1:39: Tcp is given twice in the Device; keep one"}},
      {"TcpWithoutTransform",
       "Device D Joint 1 revolute z Tcp;",
       {"1:32: expected '(shift ...)' placing the TCP after 'Tcp', found ';'"}},
      {"UnknownDeviceWord",
       "Device D Joint 1 revolute z Initail (0);",
       {"1:29: expected Joint, Tcp, Extend, Initial or ';' in the Device command, found "
        "'Initail' (did you mean Initial?)"}},
      {"TwoDevices",
       "Device D Joint 1 revolute z;\nDevice E Joint 1 revolute z;",
       {"2:1: a script describes one Device; 'D' is already defined at line 1; describe 'E' "
        "in a script of its own"}},
      {"DeviceNameWithHash",
       "Device D#1 Joint 1 revolute z;",
       {"1:8: a device name cannot contain '#' ('D#1#k' names its link k); choose a name "
        "without it"}},
      // ---- parts
      {"CylinderMissingSizes",
       "Cylinder C res 8;",
       {"1:10: Cylinder 'C' has no diameter ('dia D', mm); add it",
        "1:10: Cylinder 'C' has no length ('len L', mm); add it"}},
      {"CylinderUnknownWord",
       "Cylinder C dia 3 lenght 4;",
       {"1:18: expected dia, res or len or ';' in Cylinder 'C', found 'lenght' (did you mean "
        "length?)"}},
      {"ResolutionTooSmall",
       "Cylinder C dia 3 len 4 res 2;",
       {"1:28: expected the resolution (number of sides, at least 3) after 'res', found "
        "number 2; give a whole number from 3 to 512"}},
      {"NegativeLength",
       "Cylinder C dia 3 len -4;",
       {"1:22: expected the length (mm) after 'len', found number -4; it must be greater "
        "than 0"}},
      {"CubeTwoNumbers", "Cube A 1 2;", {"1:11: expected the cube's zLen (mm), found ';'"}},
      {"CubeWithoutName", "Cube ;", {"1:6: expected the Cube's name after 'Cube', found ';'"}},
      {"SphereMissingRadius",
       "Sphere S res 8;",
       {"1:8: Sphere 'S' has no radius ('radius R', mm); add it"}},
      {"ConeZeroDirection",
       "Cone K (Direction x 0) dia 2 len 3;",
       {"1:9: the cone's Direction is zero; give the apex direction, e.g. z 1"}},
      {"ConeUnknownClauseWord",
       "Cone K (Apex z 1) dia 2 len 3;",
       {"1:9: expected Center, Direction or ')' in the cone's clause, found 'Apex'"}},
      {"PolyprismStartsWithArc",
       "Polyprism P Height 1 Arc to 1 1 radius 1;",
       {"1:22: a Polyprism outline starts with a point 'x y', not an Arc; write the arc's "
        "start point first"}},
      {"PolyprismRadiusTooSmall",
       "Polyprism P Height 1 0 0 10 0 Arc to 10 10 radius 4;",
       {"1:31: Arc to (10, 10): radius 4 is shorter than half the chord (5); use a radius of "
        "at least 5"}},
      {"PolyprismZeroRadius",
       "Polyprism P Height 1 0 0 10 0 Arc to 10 10 radius 0;",
       {"1:51: the arc's radius is 0; give > 0 for clockwise, < 0 for anticlockwise"}},
      {"PolyprismTooFewPoints",
       "Polyprism P Height 1 0 0 10 0;",
       {"1:11: Polyprism 'P' has 2 outline points; it needs at least 3"}},
      {"PolyprismNoArea",
       "Polyprism P Height 1 0 0 10 0 20 0;",
       {"1:22: the Polyprism outline encloses no area; check its points"}},
      {"PolyprismMissingHeight",
       "Polyprism P 0 0 1 0 1 1;",
       {"1:13: expected 'height' and the prism's height after its name, found number 0"}},
      {"PolyprismOddCoordinates",
       "Polyprism P Height 1 0 0 1 0 1;",
       {"1:31: expected the point's y after its x in Polyprism 'P', found ';'"}},
      {"PolyprismArcWithoutRadius",
       "Polyprism P Height 1 0 0 10 0 Arc to 10 10;",
       {"1:43: expected 'radius' and the arc's radius after its end point, found ';'"}},
      {"ModuleUndefinedPoint",
       "Module M Points 0 0 0 0 1 1 0 0 2 0 1 0 Polygons (0 1 9);",
       {"1:55: polygon uses point 9, which Points does not define (it defines 0..2)"}},
      {"ModuleDuplicatePoint",
       "Module M Points 0 0 0 0 0 1 0 0 1 0 1 0 2 1 1 1 Polygons (0 1 2);",
       {"1:25: point 0 is defined twice (first at line 1); number each point once"}},
      {"ModuleDegeneratePolygon",
       "Module M Points 0 0 0 0 1 1 0 0 Polygons (0 1 1);",
       {"1:42: a polygon needs at least 3 different points, this one has 2"}},
      {"ModuleNoPolygons",
       "Module M Points 0 0 0 0 Polygons;",
       {"1:8: Module 'M' has no polygons; list faces as (i j k ...)"}},
      {"ModuleMissingPolygonsKeyword",
       "Module M Points 0 0 0 0 (0 1 2);",
       {"1:25: expected 'polygons' after the module's points (Points i x y z ...), found '('"}},
      {"ModuleMissingPoints",
       "Module M 0 0 0 0;",
       {"1:10: expected 'points' after the module's name, found number 0"}},
      {"ModulePointCoordinates",
       "Module M Points 0 0 0 Polygons (0 1 2);",
       {"1:23: expected the point's x y z after its number 0, found 'Polygons'"}},
      {"PartWithoutName", "Part;", {"1:5: expected the Part's name after 'Part', found ';'"}},
      {"PartTwoWords",
       "Part A B;",
       {"1:8: expected ';' ending the Part command (Part FileName;), found 'B'; every command "
        "ends with ';'"}},
      {"DuplicatePartName",
       "Cube A 1 1 1;\nSphere A radius 2;",
       {"2:8: 'A' is already defined at line 1; give this Sphere another name"}},
      {"PartNamedAsLink",
       Dev("Cube IRB1600#2 1 1 1;"),
       {"10:6: 'IRB1600#2' names the device or one of its links; a Cube cannot take it: give "
        "the part another name and attach it with Set IRB1600#2 add ..."}},
      // ---- Set
      {"SetUndefinedComponent",
       "Cube Block 1 1 1;\nSet S add Blok;",
       {"2:11: undefined component 'Blok' in Set 'S' (did you mean Block?); define it with "
        "Set or a part command (Cylinder, Cone, Cube, Sphere, Polyprism, Module, Part) above "
        "this line"}},
      {"SetComponentDefinedLater",
       "Set S add Block;\nCube Block 1 1 1;",
       {"1:11: undefined component 'Block' in Set 'S'; it is defined later, at line 2; move "
        "its definition above this line"}},
      {"SetWithoutAdd",
       "Cube A 1 1 1;\nSet S A;",
       {"2:7: expected 'add' and the components after the Set's name, found 'A'"}},
      {"SetWithoutComponents",
       "Set S add;",
       {"1:5: Set 'S' adds no component; name at least one after 'add'"}},
      {"SetLinkOutOfRange",
       Dev("Cube A 1 1 1;\nSet IRB1600#7 add A;"),
       {"11:5: 'IRB1600#7': device 'IRB1600' has links IRB1600#1..IRB1600#6 (and IRB1600 for "
        "its base); use one of them"}},
      {"SetLinkTwice",
       Dev("Cube A 1 1 1;\nSet IRB1600#2 add A;\nSet IRB1600#2 add A;"),
       {"12:5: link 'IRB1600#2' is already built by the Set at line 11; add all the link's "
        "components in one Set"}},
      {"SetLinkAsComponent",
       Dev("Cube A 1 1 1;\nSet IRB1600#2 add A;\nSet S add IRB1600#2;"),
       {"12:11: 'IRB1600#2' is a device link and cannot be a component; add its parts to Set "
        "'S' instead"}},
      {"SetNameTaken",
       "Cube A 1 1 1;\nSet A add A;",
       {"2:5: 'A' is already defined at line 1; give this Set another name"}},
      // ---- Render
      {"RenderUndefined",
       "Cube Block 1 1 1;\nRender Blok color 1 0 0;",
       {"2:8: undefined name 'Blok' in Render (did you mean Block?); define it with Set or a "
        "part command (Cylinder, Cone, Cube, Sphere, Polyprism, Module, Part) above this line"}},
      {"RenderChannelOutOfRange",
       "Cube A 1 1 1;\nRender A color 1.5 0 -1;",
       {"2:16: colour channel 1.5 is outside 0.0-1.0",
        "2:22: colour channel -1 is outside "
        "0.0-1.0"}},
      {"RenderWithoutColor",
       "Cube A 1 1 1;\nRender A colr 1 0 0;",
       {"2:10: expected 'color r g b' after the Render target, found 'colr' (did you mean "
        "color?)"}},
      {"RenderTwoChannels",
       "Cube A 1 1 1;\nRender A color 1 0;",
       {"2:19: expected three colour channels r g b (0.0-1.0), found ';'"}},
      // ---- Probe
      {"ProbeUnknownFrame",
       Dev("Probe P IRB1600#9 (x 65) refer IRB160;"),
       {"10:9: probe 'P': unknown frame 'IRB1600#9' in (did you mean IRB1600#1?); use World, "
        "IRB1600 or IRB1600#1..IRB1600#6",
        "10:32: probe 'P': unknown frame 'IRB160' to refer to (did you mean IRB1600?); use "
        "World, IRB1600 or IRB1600#1..IRB1600#6"}},
      {"ProbeWithoutDevice",
       "Probe P Robot#6;",
       {"1:9: probe 'P': unknown frame 'Robot#6' in; use World (no Device is defined above)"}},
      {"ProbeTwice",
       Dev("Probe P World;\nProbe P World;"),
       {"11:7: probe 'P' is already defined at line 10; give it another name"}},
      {"ProbeMissingSemicolon",
       Dev("Probe P IRB1600#6 refer World x"),
       {"10:31: expected ';' ending the Probe command, found 'x'; every command ends with ';'"}},
  };
  return cases;
}

class TranslatorErrors : public ::testing::TestWithParam<Case> {};

TEST_P(TranslatorErrors, GivesExactlyTheseMessages) {
  const Case& c = GetParam();
  const Translation translation = TranslateScript(c.script);
  EXPECT_EQ(ErrorsOf(translation), c.errors);
  EXPECT_FALSE(translation.ok());
}

INSTANTIATE_TEST_SUITE_P(All, TranslatorErrors, ::testing::ValuesIn(Cases()),
                         [](const ::testing::TestParamInfo<Case>& info) {
                           return std::string(info.param.name);
                         });

TEST(TranslatorErrorsMore, MissingStlSaysWhereItLookedAndWhatToDo) {
  const DirectoryAssetLocator assets({"/nonexistent/a", "/nonexistent/b"});
  TranslateOptions options;
  options.assets = &assets;
  options.missing_asset_advice = "pass --asset-dir DIR holding it";
  EXPECT_THAT(Errors("Part Body0;", options),
              ElementsAre("1:6: Part 'Body0': STL file 'Body0.stl' not found (looked in "
                          "/nonexistent/a, /nonexistent/b); pass --asset-dir DIR holding it"));
}

TEST(TranslatorErrorsMore, InvalidStlFile) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbstream_bad_stl";
  std::filesystem::create_directories(dir);
  { std::ofstream(dir / "Bad.stl") << "this is not an stl file at all, just text"; }
  const DirectoryAssetLocator assets({dir});
  TranslateOptions options;
  options.assets = &assets;
  EXPECT_THAT(Errors("Part Bad;", options),
              ElementsAre("1:6: Part 'Bad': STL file '" + (dir / "Bad.stl").string() +
                          "' is not an STL file (neither ASCII 'solid ...' nor binary with a "
                          "matching size); replace it with a valid STL file"));
  std::filesystem::remove_all(dir);
}

TEST(TranslatorErrorsMore, UnreadableFile) {
  const Translation translation = TranslateScriptFile("/nonexistent/scene.txt");
  EXPECT_THAT(ErrorsOf(translation),
              ElementsAre("1:1: cannot read the scene script; check the path"));
}

TEST(TranslatorErrorsMore, FormatDiagnosticIsFileLineColumnMessage) {
  EXPECT_EQ(FormatDiagnostic("robot.scene", {{3, 14}, "expected x"}),
            "robot.scene:3:14: expected x");
}

TEST(TranslatorErrorsMore, EveryErrorOfAScriptIsReportedInOrder) {
  const std::vector<std::string> errors = Errors(
      "Cube A 1 1;\nCylnder B;\nSphere C radius 2 res 1;\nRender D color 1 1 1;\nCube E 1 1 1;");
  ASSERT_EQ(errors.size(), 4u);
  EXPECT_EQ(errors[0].substr(0, 5), "1:11:");
  EXPECT_EQ(errors[1].substr(0, 4), "2:1:");
  EXPECT_EQ(errors[2].substr(0, 5), "3:23:");
  EXPECT_EQ(errors[3].substr(0, 4), "4:8:");
}

}  // namespace
}  // namespace mbstream::scene_script
