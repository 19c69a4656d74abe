// Collision geometry from URDF and SDFormat <collision> (issue 44): shapes, poses in the
// body frame, surface parameters (drake:proximity_properties, SDFormat friction), the collide
// bitmask; meshes not supplied skipped with a warning naming the file; bad values refused with the
// place.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

std::string Sdf(const std::string& models) {
  return "<?xml version=\"1.0\"?>\n<sdf version=\"1.8\" xmlns:drake=\"http://drake.mit.edu\">\n"
         "<world name=\"w\">\n" +
         models + "\n</world>\n</sdf>\n";
}

const std::string kGround =
    "<model name=\"ground\"><static>true</static><link name=\"floor\">"
    "<collision name=\"plane\"><pose>0 0 -0.1 0 0 0</pose><geometry><plane><normal>0 1 1</normal>"
    "<size>10 10</size></plane></geometry>"
    "<surface><friction><ode><mu>0.7</mu></ode></friction>"
    "<contact><collide_bitmask>0x0003</collide_bitmask></contact></surface></collision>"
    "</link></model>";

const std::string kBall =
    "<model name=\"ball\"><pose>0 0 1 0 0 0</pose><link name=\"body\">"
    "<inertial><mass>2</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia>"
    "</inertial>"
    "<collision name=\"s\"><pose>0.1 0 0 0 0 0</pose><geometry><sphere><radius>0.25</radius>"
    "</sphere></geometry><drake:proximity_properties>"
    "<drake:point_contact_stiffness>2e5</drake:point_contact_stiffness>"
    "<drake:hunt_crossley_dissipation>0.5</drake:hunt_crossley_dissipation>"
    "<drake:mu_static>0.9</drake:mu_static><drake:mu_dynamic>0.6</drake:mu_dynamic>"
    "</drake:proximity_properties></collision>"
    "<collision name=\"c\"><geometry><capsule><radius>0.1</radius><length>0.4</length></capsule>"
    "</geometry></collision>"
    "<collision name=\"m\"><geometry><mesh><uri>meshes/hull.stl</uri></mesh></geometry>"
    "</collision></link></model>";

const CollisionGeometry& Named(const Model& model, const std::string& name) {
  for (const CollisionGeometry& g : model.collisions) {
    if (g.name == name) return g;
  }
  throw std::runtime_error("no collision " + name);
}

TEST(CollisionReadingTest, SdfShapesPosesSurfacesAndBitmask) {
  const SdfImport sdf = ImportSdf(Sdf(kGround + kBall), "w.sdf");
  const Model& model = sdf.model;
  ASSERT_EQ(model.collisions.size(), 3u);  // the mesh skipped: not supplied
  const CollisionGeometry& plane = Named(model, "plane");
  EXPECT_EQ(plane.link, "ground::floor");
  EXPECT_EQ(plane.body, kBase);
  EXPECT_EQ(plane.shape.type, ShapeType::kPlane);
  EXPECT_LT((plane.X_BG.p - Vector3d(0, 0, -0.1)).norm(), 1e-12);
  EXPECT_LT((plane.X_BG.R.col(2) - Vector3d(0, 1, 1).normalized()).norm(), 1e-12);
  EXPECT_EQ(plane.collide_bitmask, 3);
  EXPECT_DOUBLE_EQ(plane.surface.mu_dynamic, 0.7);
  EXPECT_DOUBLE_EQ(plane.surface.mu_static, 0.7);
  EXPECT_TRUE(std::isnan(plane.surface.stiffness));

  const CollisionGeometry& sphere = Named(model, "s");
  EXPECT_EQ(sphere.body, model.FindBody("ball::body"));
  EXPECT_EQ(sphere.shape.type, ShapeType::kSphere);
  EXPECT_DOUBLE_EQ(sphere.shape.radius, 0.25);
  EXPECT_LT((sphere.X_BG.p - Vector3d(0.1, 0, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(sphere.surface.stiffness, 2e5);
  EXPECT_DOUBLE_EQ(sphere.surface.dissipation, 0.5);
  EXPECT_DOUBLE_EQ(sphere.surface.mu_static, 0.9);
  EXPECT_DOUBLE_EQ(sphere.surface.mu_dynamic, 0.6);
  EXPECT_EQ(sphere.collide_bitmask, 0xffff);

  const CollisionGeometry& capsule = Named(model, "c");
  EXPECT_EQ(capsule.shape.type, ShapeType::kCapsule);
  EXPECT_DOUBLE_EQ(capsule.shape.radius, 0.1);
  EXPECT_DOUBLE_EQ(capsule.shape.length, 0.4);

  bool warned = false;
  for (const std::string& w : sdf.warnings) {
    warned = warned || (w.find("meshes/hull.stl") != std::string::npos &&
                        w.find("collision 'm'") != std::string::npos);
  }
  EXPECT_TRUE(warned);
}

TEST(CollisionReadingTest, SdfNegativeDrakeFrictionIsRefusedWithItsPlace) {
  const std::string bad =
      "<model name=\"b\"><link name=\"l\"><inertial><mass>1</mass></inertial>"
      "<collision name=\"s\"><geometry><sphere><radius>0.1</radius></sphere></geometry>"
      "<drake:proximity_properties><drake:mu_dynamic>-1</drake:mu_dynamic>"
      "</drake:proximity_properties></collision></link></model>";
  try {
    ImportSdf(Sdf(bad), "w.sdf");
    FAIL() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("w.sdf:"), std::string::npos) << what;
    EXPECT_NE(what.find("collision 's'"), std::string::npos) << what;
    EXPECT_NE(what.find("drake:mu_dynamic"), std::string::npos) << what;
  }
}

TEST(CollisionReadingTest, UrdfShapesOnMergedLinksAndDrakeProperties) {
  const std::string urdf =
      "<robot name=\"r\"><link name=\"base\"><collision name=\"floor_box\">"
      "<origin xyz=\"0 0 -0.5\"/><geometry><box size=\"2 2 1\"/></geometry></collision></link>"
      "<link name=\"arm\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" iyy=\"0.1\" "
      "izz=\"0.1\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial></link>"
      "<link name=\"pad\"><collision name=\"pad\"><origin xyz=\"0 0 0.2\" rpy=\"0 "
      "1.5707963267948966 0\"/>"
      "<geometry><cylinder radius=\"0.05\" length=\"0.1\"/></geometry>"
      "<drake:proximity_properties><drake:mu_dynamic value=\"0.4\"/>"
      "<drake:point_contact_stiffness value=\"1e4\"/></drake:proximity_properties></collision>"
      "<collision><geometry><mesh filename=\"package://r/pad.dae\"/></geometry></collision></link>"
      "<joint name=\"j\" type=\"continuous\"><parent link=\"base\"/><child link=\"arm\"/>"
      "<axis xyz=\"0 0 1\"/></joint>"
      "<joint name=\"f\" type=\"fixed\"><parent link=\"arm\"/><child link=\"pad\"/>"
      "<origin xyz=\"1 0 0\"/></joint></robot>";
  const UrdfImport imported = ImportUrdf(urdf, "r.urdf", {});
  const Model& model = imported.model;
  ASSERT_EQ(model.collisions.size(), 2u);
  const CollisionGeometry& box = Named(model, "floor_box");
  EXPECT_EQ(box.body, kBase);
  EXPECT_EQ(box.shape.type, ShapeType::kBox);
  EXPECT_LT((box.shape.size - Vector3d(2, 2, 1)).norm(), 1e-12);
  const CollisionGeometry& pad = Named(model, "pad");
  EXPECT_EQ(pad.body, model.FindBody("arm"));  // the fixed link merged into its body
  EXPECT_LT((pad.X_BG.p - Vector3d(1, 0, 0.2)).norm(), 1e-12);
  EXPECT_LT((pad.X_BG.R.col(2) - Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(pad.surface.mu_dynamic, 0.4);
  EXPECT_DOUBLE_EQ(pad.surface.mu_static, 0.4);
  EXPECT_DOUBLE_EQ(pad.surface.stiffness, 1e4);
  bool warned = false;
  for (const std::string& w : imported.warnings) {
    warned = warned || w.find("package://r/pad.dae") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(CollisionReadingTest, UrdfZeroRadiusIsRefused) {
  const std::string urdf =
      "<robot name=\"r\"><link name=\"base\"><collision name=\"s\"><geometry>"
      "<sphere radius=\"0\"/></geometry></collision></link></robot>";
  EXPECT_THROW(ImportUrdf(urdf, "r.urdf", {}), InputError);
}

}  // namespace
}  // namespace mbstream
