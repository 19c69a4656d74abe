// Every kind of bad URDF gets an InputError that names the file, the line when known, the
// joint or link, what is wrong and what to do.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/parse/urdf_import.h"
#include "tests/server/parse/urdf_test_util.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::ImportError;
using testing::InertialXml;
using testing::JointXml;
using testing::kAxisAndLimits;
using testing::kInertial;
using testing::LinkXml;
using testing::OneJoint;
using testing::Robot;

TEST(UrdfImportErrorsTest, MalformedXmlNamesTheLine) {
  EXPECT_THAT(ImportError("<robot name=\"r\">\n<link name=\"base\">\n</robot>\n"),
              AllOf(HasSubstr("bad.urdf:3: "), HasSubstr("not well formed"),
                    HasSubstr("urdfdom cannot parse it")));
}

TEST(UrdfImportErrorsTest, EmptyFileAndMissingRobot) {
  EXPECT_THAT(ImportError(""), AllOf(HasSubstr("bad.urdf: "), HasSubstr("empty")));
  EXPECT_THAT(ImportError("<model/>"), AllOf(HasSubstr("bad.urdf: "), HasSubstr("no <robot>")));
}

TEST(UrdfImportErrorsTest, UrdfdomRejectionIsQuoted) {
  // urdfdom needs effort and velocity in <limit>; its message points at the joint.
  EXPECT_THAT(
      ImportError(OneJoint(R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1"/>)")),
      AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("urdfdom cannot parse"),
            HasSubstr("no effort")));
  // A joint whose child link does not exist.
  EXPECT_THAT(ImportError(Robot(JointXml("j1", "fixed", "base", "ghost", ""))),
              AllOf(HasSubstr("bad.urdf:3: joint 'j1'"), HasSubstr("urdfdom cannot parse"),
                    HasSubstr("ghost")));
  // Two links that no joint connects: two roots.
  EXPECT_THAT(ImportError(Robot(LinkXml("island"))),
              AllOf(HasSubstr("bad.urdf: urdfdom cannot parse"), HasSubstr("Two root links")));
}

TEST(UrdfImportErrorsTest, UrdfdomErrorsItCarriesOnAfterAreFatal) {
  // urdfdom logs a malformed <inertial> and keeps the link with zero mass.
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, "<inertial><mass value=\"1\"/></inertial>")),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("urdfdom cannot parse"),
                    HasSubstr("inertia")));
}

TEST(UrdfImportErrorsTest, NonFiniteAxisIsRefused) {
  EXPECT_THAT(ImportError(OneJoint(
                  R"(<axis xyz="nan 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>)")),
              AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("axis")));
}

TEST(UrdfImportErrorsTest, LinkWithTwoParentsIsRefused) {
  const std::string text =
      Robot(LinkXml("a") + LinkXml("b") + LinkXml("c") + JointXml("ja", "revolute", "base", "a") +
            JointXml("jb", "revolute", "base", "b") + JointXml("jc1", "revolute", "a", "c") +
            JointXml("jc2", "revolute", "b", "c"));
  EXPECT_THAT(ImportError(text),
              AllOf(HasSubstr("bad.urdf:9: joint 'jc2'"), HasSubstr("link 'c'"),
                    HasSubstr("'jc1' (line 8)"), HasSubstr("closes a kinematic loop"),
                    HasSubstr("remove one")));
}

TEST(UrdfImportErrorsTest, ClosedLoopDetachedFromTheRoot) {
  // Each link has one parent, but a and b hang from each other, not from the base.
  const std::string text =
      Robot(LinkXml("a") + LinkXml("b") + JointXml("j1", "revolute", "b", "a") +
            JointXml("j2", "revolute", "a", "b"));
  EXPECT_THAT(ImportError(text),
              AllOf(HasSubstr("bad.urdf:5: joint 'j1'"), HasSubstr("not connected to the root"),
                    HasSubstr("closed loop"), HasSubstr("'j2'")));
}

// A floating joint from the root is a free joint now (urdf_floating_test.cc, which also checks
// the refusal of one deeper in the tree); a planar joint is still refused.
TEST(UrdfImportErrorsTest, PlanarJointsAreRefused) {
  EXPECT_THAT(ImportError(OneJoint("", kInertial, "planar")),
              AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("'planar' is not supported"),
                    HasSubstr("make it 'fixed'"), HasSubstr("revolute")));
}

TEST(UrdfImportErrorsTest, MovingLinkWithoutMassIsRefused) {
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, "")),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("no <inertial>"),
                    HasSubstr("joint 'j1' moves it"), HasSubstr("<mass")));
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, InertialXml("0", "1", "1", "1"))),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("mass is 0 kg"),
                    HasSubstr("positive mass")));
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, InertialXml("-2", "1", "1", "1"))),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("mass is -2 kg")));
}

TEST(UrdfImportErrorsTest, NegativeMassOnAFixedLink) {
  const std::string text = Robot(LinkXml("a", InertialXml("-1", "1", "1", "1")) +
                                 JointXml("f", "fixed", "base", "a", ""));
  EXPECT_THAT(ImportError(text),
              AllOf(HasSubstr("bad.urdf:3: link 'a'"), HasSubstr("mass is -1 kg"),
                    HasSubstr("cannot be negative")));
}

TEST(UrdfImportErrorsTest, InertiaNotPositiveDefiniteIsRefused) {
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, InertialXml("1", "1", "1", "1", "2"))),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("not positive definite")));
}

TEST(UrdfImportErrorsTest, InertiaBreaksTheTriangleInequality) {
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits, InertialXml("1", "0.1", "0.1", "1"))),
              AllOf(HasSubstr("bad.urdf:3: link 'link1'"), HasSubstr("triangle inequality")));
}

TEST(UrdfImportErrorsTest, ZeroAxisIsRefused) {
  EXPECT_THAT(ImportError(OneJoint(
                  R"(<axis xyz="0 0 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>)")),
              AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("axis (0 0 0) is zero"),
                    HasSubstr("<axis xyz=")));
}

TEST(UrdfImportErrorsTest, DuplicateLinkNameIsRefusedWithBothLines) {
  const std::string text =
      Robot(LinkXml("a") + LinkXml("a") + JointXml("j1", "revolute", "base", "a"));
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("bad.urdf:4: link 'a'"), HasSubstr("used twice"),
                                       HasSubstr("first on line 3"), HasSubstr("unique")));
}

TEST(UrdfImportErrorsTest, DuplicateJointNameIsRefusedWithBothLines) {
  const std::string text =
      Robot(LinkXml("a") + LinkXml("b") + JointXml("j", "revolute", "base", "a") +
            JointXml("j", "revolute", "a", "b"));
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("bad.urdf:6: joint 'j'"), HasSubstr("used twice"),
                                       HasSubstr("first on line 5")));
}

TEST(UrdfImportErrorsTest, LowerLimitAboveUpperIsRefused) {
  EXPECT_THAT(ImportError(OneJoint(
                  R"(<axis xyz="0 0 1"/><limit lower="1" upper="-1" effort="1" velocity="1"/>)")),
              AllOf(HasSubstr("bad.urdf:4: joint 'j1'"),
                    HasSubstr("lower limit 1 rad is above upper limit -1 rad"), HasSubstr("swap")));
}

TEST(UrdfImportErrorsTest, NegativeEffortVelocityOrDamping) {
  EXPECT_THAT(
      ImportError(OneJoint(R"(<limit lower="-1" upper="1" effort="-5" velocity="1"/>)")),
      AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("effort limit -5 N*m is negative")));
  EXPECT_THAT(
      ImportError(OneJoint(R"(<limit lower="-1" upper="1" effort="5" velocity="-1"/>)", kInertial,
                           "prismatic")),
      AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("velocity limit -1 m/s is negative")));
  EXPECT_THAT(
      ImportError(OneJoint(kAxisAndLimits + R"(<dynamics damping="-0.5"/>)")),
      AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("damping -0.5 N*m*s/rad is negative")));
}

TEST(UrdfImportErrorsTest, BadRotorInertiaIsRefused) {
  EXPECT_THAT(
      ImportError(OneJoint(kAxisAndLimits + R"(<mbstream:rotor_inertia value="-1"/>)")),
      AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("rotor inertia -1"), HasSubstr(">= 0")));
  EXPECT_THAT(ImportError(OneJoint(kAxisAndLimits + R"(<mbstream:rotor_inertia val="1"/>)")),
              AllOf(HasSubstr("bad.urdf:4: joint 'j1'"), HasSubstr("numeric value attribute")));
}

TEST(UrdfImportErrorsTest, FileThatCannotBeRead) {
  try {
    ImportUrdfFile("/nonexistent/robot.urdf");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("/nonexistent/robot.urdf: cannot open"),
                                HasSubstr("check the path")));
  }
}

}  // namespace
}  // namespace mbstream
