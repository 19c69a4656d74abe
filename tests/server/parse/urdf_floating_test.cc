// A URDF whose base is not bolted down (issue 43, docs/worlds.md): a 'floating' joint from the
// root link is a free joint (its child starts at the joint's <origin>), and
// UrdfImportOptions::floating_base (--floating-base) frees the root link itself; a floating
// joint deeper in the tree, or with --floating-base, is refused with its line.
#include <gtest/gtest.h>

#include <string>

#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// A trunk with one leg on a revolute joint; `head` goes before the trunk's link.
std::string Robot(const std::string& head) {
  return "<robot name=\"walker\">\n" + head +
         "  <link name=\"trunk\"><inertial><mass value=\"10\"/>"
         "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" "
         "iyz=\"0\"/></inertial></link>\n"
         "  <link name=\"leg\"><inertial><mass value=\"2\"/>"
         "<inertia ixx=\"0.1\" iyy=\"0.1\" izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>"
         "</link>\n"
         "  <joint name=\"hip\" type=\"revolute\"><parent link=\"trunk\"/><child link=\"leg\"/>"
         "<origin xyz=\"0 0 -0.3\"/><axis xyz=\"0 1 0\"/>"
         "<limit lower=\"-1\" upper=\"1\" effort=\"10\" velocity=\"1\"/></joint>\n"
         "</robot>\n";
}

const char kFloating[] =
    "  <link name=\"world\"/>\n"
    "  <joint name=\"base_free\" type=\"floating\"><parent link=\"world\"/>"
    "<child link=\"trunk\"/><origin xyz=\"0 0 1\" rpy=\"0 0 1.5707963267948966\"/></joint>\n";

std::string ImportError(const std::string& text, const UrdfImportOptions& options) {
  try {
    ImportUrdf(text, "walker.urdf", {}, options);
  } catch (const InputError& error) {
    return error.what();
  }
  return "imported";
}

TEST(UrdfFloatingTest, AFloatingJointFromTheWorldIsAFreeJointStartingAtItsOrigin) {
  const UrdfImport urdf = ImportUrdf(Robot(kFloating), "walker.urdf", {});
  const Model& model = urdf.model;
  ASSERT_EQ(model.num_bodies(), 2);
  const Body& trunk = model.bodies[0];
  EXPECT_TRUE(trunk.free());
  EXPECT_EQ(trunk.joint.name, "base_free");
  EXPECT_EQ(trunk.name, "trunk");
  EXPECT_LT((trunk.X_W0.p - Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_LT((trunk.X_W0.R * Vector3d::UnitX() - Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_EQ(model.nq(), 7 + 1);
  EXPECT_EQ(model.nv(), 6 + 1);
  EXPECT_DOUBLE_EQ(model.TotalMass(), 12.0);
}

TEST(UrdfFloatingTest, FloatingBaseFreesTheRootLinkUnderItsOwnName) {
  const UrdfImport urdf =
      ImportUrdf(Robot(""), "walker.urdf", {}, UrdfImportOptions{.floating_base = true});
  const Model& model = urdf.model;
  EXPECT_EQ(model.base_name, "world");
  ASSERT_EQ(model.num_bodies(), 2);
  EXPECT_TRUE(model.bodies[0].free());
  EXPECT_EQ(model.bodies[0].joint.name, "trunk");
  EXPECT_LT(model.bodies[0].X_W0.p.norm(), 1e-15);
  EXPECT_EQ(model.bodies[1].joint.name, "hip");
  EXPECT_EQ(model.nv(), 7);
  // Without it the trunk is the fixed base, as before.
  EXPECT_EQ(ImportUrdf(Robot(""), "walker.urdf", {}).model.nv(), 1);
}

TEST(UrdfFloatingTest, AFloatingJointElsewhereOrTwiceFreedIsRefusedWithItsLine) {
  const std::string deep =
      "<robot name=\"r\">\n  <link name=\"base\"/>\n"
      "  <link name=\"a\"><inertial><mass value=\"1\"/>"
      "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n"
      "  <link name=\"b\"><inertial><mass value=\"1\"/>"
      "<inertia ixx=\"1\" iyy=\"1\" izz=\"1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>\n"
      "  <joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"a\"/>"
      "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n"
      "  <joint name=\"loose\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint>\n"
      "</robot>\n";
  EXPECT_EQ(ImportError(deep, {}).rfind("walker.urdf:6: joint 'loose': a 'floating' joint's "
                                        "parent must be the root link 'base' (the world), not 'a'",
                                        0),
            0u)
      << ImportError(deep, {});
  EXPECT_NE(ImportError(Robot(kFloating), {.floating_base = true})
                .find("--floating-base: the root link is 'world' already"),
            std::string::npos)
      << ImportError(Robot(kFloating), {.floating_base = true});
}

}  // namespace
}  // namespace mbstream
