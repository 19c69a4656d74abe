// Input that is merely odd imports, with a warning that names the file, line and element.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "server/parse/urdf_import.h"
#include "tests/server/parse/urdf_test_util.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using testing::ImportWarnings;
using testing::InertialXml;
using ::testing::IsEmpty;
using testing::JointXml;
using testing::kAxisAndLimits;
using testing::kInertial;
using testing::LinkXml;
using ::testing::Not;
using testing::OneJoint;
using testing::Robot;

constexpr double kInf = std::numeric_limits<double>::infinity();

// One moving link and a fixed leaf "tcp" (no inertial), so that only the case under test
// warns.
std::string WithTcp(const std::string& joint_inner, const std::string& link_inner = kInertial,
                    const std::string& type = "revolute") {
  return Robot(LinkXml("link1", link_inner) + JointXml("j1", type, "base", "link1", joint_inner) +
               LinkXml("tcp", "") + JointXml("t", "fixed", "link1", "tcp", ""));
}

TEST(UrdfImportWarningsTest, CleanModelAndMasslessFixedLeafDoNotWarn) {
  EXPECT_THAT(ImportWarnings(WithTcp(kAxisAndLimits)), IsEmpty());
}

TEST(UrdfImportWarningsTest, NonUnitAxisIsNormalised) {
  const UrdfImport imported = ImportUrdf(
      WithTcp(R"(<axis xyz="0 3 4"/><limit lower="-1" upper="1" effort="1" velocity="1"/>)"),
      "odd.urdf", {});
  EXPECT_THAT(imported.warnings, ElementsAre(AllOf(HasSubstr("odd.urdf:4: joint 'j1'"),
                                                   HasSubstr("axis (0 3 4) is not a unit vector"),
                                                   HasSubstr("normalised to (0 0.6 0.8)"))));
  EXPECT_LT((imported.model.bodies[0].joint.axis - Vector3d(0, 0.6, 0.8)).norm(), 1e-15);
}

TEST(UrdfImportWarningsTest, RevoluteWithoutLimitsIsUnlimited) {
  const UrdfImport imported = ImportUrdf(WithTcp(R"(<axis xyz="0 0 1"/>)"), "odd.urdf", {});
  EXPECT_THAT(imported.warnings,
              ElementsAre(AllOf(HasSubstr("odd.urdf:4: joint 'j1'"), HasSubstr("no <limit>"),
                                HasSubstr("type=\"continuous\""))));
  const JointLimits& limits = imported.model.bodies[0].joint.limits;
  EXPECT_EQ(limits.lower, -kInf);
  EXPECT_EQ(limits.upper, kInf);
  EXPECT_EQ(limits.effort, kInf);
  EXPECT_EQ(imported.model.bodies[0].joint.type, JointType::kRevolute);
}

TEST(UrdfImportWarningsTest, ZeroEffortAndVelocityLimitsMeanNoLimit) {
  const UrdfImport imported = ImportUrdf(
      WithTcp(R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="0" velocity="0"/>)"),
      "odd.urdf", {});
  EXPECT_THAT(imported.warnings,
              ElementsAre(AllOf(HasSubstr("odd.urdf:4: joint 'j1'"),
                                HasSubstr("velocity limit is 0, read as no limit")),
                          AllOf(HasSubstr("odd.urdf:4: joint 'j1'"),
                                HasSubstr("effort limit is 0, read as no limit"))));
  EXPECT_EQ(imported.model.bodies[0].joint.limits.effort, kInf);
  EXPECT_EQ(imported.model.bodies[0].joint.limits.velocity, kInf);
  EXPECT_EQ(imported.model.bodies[0].joint.limits.upper, 1.0);
}

TEST(UrdfImportWarningsTest, EmptyPositionRangeIsWarned) {
  EXPECT_THAT(ImportWarnings(WithTcp(R"(<limit effort="1" velocity="1"/>)")),
              ElementsAre(AllOf(HasSubstr("odd.urdf:4: joint 'j1'"),
                                HasSubstr("position range is empty"))));
}

TEST(UrdfImportWarningsTest, VerySmallMassIsWarned) {
  EXPECT_THAT(ImportWarnings(WithTcp(kAxisAndLimits, InertialXml("1e-7", "1e-9", "1e-9", "1e-9"))),
              ElementsAre(AllOf(HasSubstr("odd.urdf:3: link 'link1'"),
                                HasSubstr("mass 1e-07 kg is below 1e-6 kg"))));
}

TEST(UrdfImportWarningsTest, ScaledMeshIsWarned) {
  const std::string visual =
      R"(<visual><geometry><mesh filename="m.stl" scale="0.001 0.001 0.001"/></geometry></visual>)";
  EXPECT_THAT(ImportWarnings(WithTcp(kAxisAndLimits, kInertial + visual), {"m.stl"}),
              ElementsAre(AllOf(HasSubstr("odd.urdf:3: link 'link1'"),
                                HasSubstr("mesh 'm.stl' is scaled by (0.001 0.001 0.001)"))));
}

TEST(UrdfImportWarningsTest, MissingVisualMeshesAreSaidOnceAsACount) {
  std::string body;
  for (int i = 1; i <= 5; ++i) {
    const std::string link = "link" + std::to_string(i);
    body += LinkXml(link, kInertial + "<visual><geometry><mesh filename=\"package://p/m" +
                              std::to_string(i) + ".dae\"/></geometry></visual>") +
            JointXml("j" + std::to_string(i), "revolute",
                     i == 1 ? "base" : "link" + std::to_string(i - 1), link);
  }
  const std::vector<std::string> warnings = ImportWarnings(Robot(body));
  const auto meshes = std::count_if(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.find("mesh") != std::string::npos;
  });
  EXPECT_EQ(meshes, 1);
  EXPECT_THAT(warnings, Contains(AllOf(HasSubstr("odd.urdf: 5 visual meshes are not supplied"),
                                       HasSubstr("link 'link1'"), HasSubstr("m3.dae"),
                                       Not(HasSubstr("m4.dae")), HasSubstr("--asset m1.dae"))));
}

TEST(UrdfImportWarningsTest, IgnoredJointFeaturesAreWarned) {
  EXPECT_THAT(ImportWarnings(WithTcp(R"(<limit lower="-1" upper="1" effort="1" velocity="1"/>)",
                                     kInertial, "continuous")),
              ElementsAre(HasSubstr("position limits of a continuous joint are ignored")));
  EXPECT_THAT(ImportWarnings(WithTcp(kAxisAndLimits + R"(<dynamics damping="0" friction="2"/>)")),
              ElementsAre(HasSubstr("friction 2 is ignored")));
  const std::string mimic = Robot(
      LinkXml("link1") + JointXml("j1", "revolute", "base", "link1") + LinkXml("link2") +
      JointXml("j2", "revolute", "link1", "link2", kAxisAndLimits + R"(<mimic joint="j1"/>)") +
      LinkXml("tcp", "") + JointXml("t", "fixed", "link2", "tcp", ""));
  EXPECT_THAT(ImportWarnings(mimic),
              ElementsAre(AllOf(HasSubstr("odd.urdf:6: joint 'j2'"),
                                HasSubstr("<mimic> of joint 'j1' is ignored"))));
}

TEST(UrdfImportWarningsTest, ExtensionsInTheWrongPlace) {
  EXPECT_THAT(ImportWarnings(WithTcp(kAxisAndLimits + R"(<mbstream:gear ratio="3"/>)")),
              ElementsAre(AllOf(HasSubstr("odd.urdf:4: joint 'j1'"),
                                HasSubstr("unknown extension <mbstream:gear>"))));
  const std::string fixed_rotor =
      Robot(LinkXml("link1") + JointXml("j1", "revolute", "base", "link1") + LinkXml("tcp", "") +
            JointXml("t", "fixed", "link1", "tcp", R"(<mbstream:rotor_inertia value="1"/>)"));
  EXPECT_THAT(ImportWarnings(fixed_rotor),
              ElementsAre(AllOf(HasSubstr("odd.urdf:6: joint 't'"),
                                HasSubstr("rotor_inertia> on a fixed joint is ignored"))));
}

TEST(UrdfImportWarningsTest, InertiaWithoutMassIsWarned) {
  const std::string text = Robot(LinkXml("link1") + JointXml("j1", "revolute", "base", "link1") +
                                 LinkXml("tcp", InertialXml("0", "1", "1", "1")) +
                                 JointXml("t", "fixed", "link1", "tcp", ""));
  EXPECT_THAT(ImportWarnings(text),
              ElementsAre(AllOf(HasSubstr("odd.urdf:5: link 'tcp'"), HasSubstr("zero mass"))));
}

TEST(UrdfImportWarningsTest, NoTcpAndNoMovingJoints) {
  EXPECT_THAT(
      ImportWarnings(OneJoint()),
      ElementsAre(AllOf(HasSubstr("odd.urdf: the model has no TCP"),
                        HasSubstr("last moving link 'link1'"), HasSubstr("add a link 'tcp'"))));
  const std::string rigid = Robot(LinkXml("tcp", "") + JointXml("t", "fixed", "base", "tcp", ""));
  EXPECT_THAT(ImportWarnings(rigid),
              ElementsAre(HasSubstr("odd.urdf: the model has no moving joints")));
}

}  // namespace
}  // namespace mbstream
