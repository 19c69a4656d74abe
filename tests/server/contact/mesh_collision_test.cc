// Collision meshes read into the Model as convex pieces (server/parse/collision_reading.h,
// collision_meshes.h; issue 44): a URDF <mesh filename scale> and an SDFormat <mesh><uri>
// <scale>; an OBJ with two objects gives two pieces; a mesh that is not convex is a warning
// naming its file; a mesh not supplied is skipped with a warning; one that cannot be read, or
// without volume, is an InputError naming the file and the <collision>.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "server/parse/collision_meshes.h"
#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kData = std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/";

std::string Bytes(const std::string& file) {
  std::ifstream in(kData + file, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A URDF of one fixed link whose collision is <mesh filename="FILE" SCALE/>.
std::string MeshUrdf(const std::string& file, const std::string& scale = "") {
  return R"(<robot name="meshy">
  <link name="base">
    <collision name="hull">
      <origin xyz="0 0 0.5"/>
      <geometry><mesh filename=")" +
         file + "\"" + (scale.empty() ? "" : " scale=\"" + scale + "\"") + R"(/></geometry>
    </collision>
  </link>
</robot>
)";
}

// The meshes of `files` (mesh name -> bytes), as a bundle would supply them.
UrdfImportOptions Supplying(std::map<std::string, std::string> files) {
  UrdfImportOptions options;
  options.collision_meshes = [files](const std::string& name) -> std::optional<std::string> {
    const auto found = files.find(name);
    if (found == files.end()) return std::nullopt;
    return found->second;
  };
  return options;
}

std::string AllWarnings(const std::vector<std::string>& warnings) {
  std::string all;
  for (const std::string& w : warnings) all += w + "\n";
  return all;
}

TEST(MeshCollisionTest, AUrdfMeshIsItsScaledHull) {
  const UrdfImport urdf =
      ImportUrdf(MeshUrdf("package://demo/meshes/cube.stl", "0.2 0.4 0.6"), "meshy.urdf", {},
                 Supplying({{"package://demo/meshes/cube.stl", Bytes("unit_cube.stl")}}));
  ASSERT_EQ(urdf.model.collisions.size(), 1u) << AllWarnings(urdf.warnings);
  const CollisionGeometry& g = urdf.model.collisions[0];
  EXPECT_EQ(g.shape.type, ShapeType::kConvex);
  EXPECT_EQ(g.name, "hull");
  EXPECT_EQ(g.shape.convex.vertices->size(), 8u);
  EXPECT_NEAR(g.shape.convex.volume, 0.2 * 0.4 * 0.6, 1e-12);
  EXPECT_TRUE(g.shape.convex.lower.isApprox(Vector3d(-0.1, -0.2, -0.3)));
  EXPECT_TRUE(g.shape.convex.upper.isApprox(Vector3d(0.1, 0.2, 0.3)));
  EXPECT_NEAR(g.X_BG.p.z(), 0.5, 1e-15);
  EXPECT_THAT(AllWarnings(urdf.warnings), Not(HasSubstr("convex")));
}

TEST(MeshCollisionTest, AnObjWithTwoObjectsGivesTwoPieces) {
  const UrdfImport urdf = ImportUrdf(MeshUrdf("two_cubes.obj"), "meshy.urdf", {},
                                     Supplying({{"two_cubes.obj", Bytes("two_cubes.obj")}}));
  ASSERT_EQ(urdf.model.collisions.size(), 2u) << AllWarnings(urdf.warnings);
  for (int k = 0; k < 2; ++k) {
    const CollisionGeometry& g = urdf.model.collisions[static_cast<size_t>(k)];
    EXPECT_EQ(g.piece, k);
    EXPECT_EQ(g.name, "hull");
    EXPECT_EQ(g.shape.convex.vertices->size(), 8u);
    EXPECT_NEAR(g.shape.convex.volume, 1e-3, 1e-9);  // Assimp keeps vertices as float
  }
  // left, then right: each its own cube, not the hull of both
  EXPECT_NEAR(urdf.model.collisions[0].shape.convex.upper.x(), -0.05, 1e-7);
  EXPECT_NEAR(urdf.model.collisions[1].shape.convex.lower.x(), 0.05, 1e-7);
  EXPECT_THAT(AllWarnings(urdf.warnings), Not(HasSubstr("convex")));
}

TEST(MeshCollisionTest, ANonConvexMeshIsWarnedAboutByFileAndItsHullUsed) {
  const UrdfImport urdf = ImportUrdf(MeshUrdf("meshes/l_shape.stl"), "meshy.urdf", {},
                                     Supplying({{"meshes/l_shape.stl", Bytes("l_shape.stl")}}));
  ASSERT_EQ(urdf.model.collisions.size(), 1u);
  const ConvexPolytope& hull = urdf.model.collisions[0].shape.convex;
  EXPECT_EQ(hull.vertices->size(), 10u);  // the inner corner's two vertices are not on the hull
  EXPECT_NEAR(hull.volume / (0.02875 * 0.1), 1.0, 1e-6);  // Assimp keeps vertices as float
  EXPECT_THAT(AllWarnings(urdf.warnings),
              AllOf(HasSubstr("meshy.urdf:3: link 'base': collision 'hull': mesh "
                              "'meshes/l_shape.stl' is not convex"),
                    HasSubstr("61 % of its hull's volume"), HasSubstr("its convex hull is used")));
  // Several: one warning, every file named.
  const std::string two = R"(<robot name="two">
  <link name="a"><collision name="x"><geometry><mesh filename="l.stl"/></geometry></collision>
    <collision name="y"><geometry><mesh filename="m.stl" scale="2 2 2"/></geometry></collision>
    <collision name="z"><geometry><mesh filename="cube.stl"/></geometry></collision></link>
</robot>
)";
  const UrdfImport both = ImportUrdf(two, "two.urdf", {},
                                     Supplying({{"l.stl", Bytes("l_shape.stl")},
                                                {"m.stl", Bytes("l_shape.stl")},
                                                {"cube.stl", Bytes("unit_cube.stl")}}));
  ASSERT_EQ(both.model.collisions.size(), 3u);
  int concave = 0;
  for (const std::string& w : both.warnings) concave += w.find("not convex") != std::string::npos;
  EXPECT_EQ(concave, 1) << AllWarnings(both.warnings);
  EXPECT_THAT(AllWarnings(both.warnings),
              AllOf(HasSubstr("two.urdf:2: link 'a': collision 'x': mesh 'l.stl' is not convex"),
                    HasSubstr("and 1 more meshes not convex: 'm.stl' (61 %)"),
                    HasSubstr("their convex hulls are used"), Not(HasSubstr("cube.stl"))));
}

TEST(MeshCollisionTest, AMeshNotSuppliedIsSkippedWithAWarning) {
  const UrdfImport urdf =
      ImportUrdf(MeshUrdf("package://demo/meshes/absent.stl"), "meshy.urdf", {}, Supplying({}));
  EXPECT_TRUE(urdf.model.collisions.empty());
  EXPECT_THAT(AllWarnings(urdf.warnings),
              AllOf(HasSubstr("meshy.urdf: 1 collision mesh(es) not supplied; those collisions "
                              "touch nothing"),
                    HasSubstr("meshy.urdf:3: link 'base': collision 'hull': mesh "
                              "'package://demo/meshes/absent.stl' is not supplied; skipped"),
                    HasSubstr("--with-collision")));
}

TEST(MeshCollisionTest, UnreadableOrFlatMeshesAreRefusedByFileAndCollision) {
  const auto refusal = [](const std::string& bytes) {
    try {
      ImportUrdf(MeshUrdf("bad.stl"), "meshy.urdf", {}, Supplying({{"bad.stl", bytes}}));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_THAT(refusal("solid empty\nendsolid empty\n"),
              HasSubstr("meshy.urdf:3: link 'base': collision 'hull': mesh 'bad.stl'"));
  EXPECT_THAT(refusal("not a mesh at all"), HasSubstr("mesh 'bad.stl': cannot be read"));
  EXPECT_THAT(refusal("solid flat\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n"
                      "   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
                      " facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n"
                      "   vertex 0 1 0\n  endloop\n endfacet\nendsolid flat\n"),
              HasSubstr("mesh 'bad.stl': its vertices span no volume"));
  try {
    ImportUrdf(MeshUrdf("cube.stl", "1 0 1"), "meshy.urdf", {},
               Supplying({{"cube.stl", Bytes("unit_cube.stl")}}));
    FAIL() << "a zero scale";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the scale has a zero"));
  }
}

TEST(MeshCollisionTest, AnSdfMeshFileIsFoundBesideTheWorld) {
  const SdfImport sdf = ImportSdfFile(kData + "box_mesh_on_plane.sdf");
  ASSERT_EQ(sdf.model.collisions.size(), 2u) << AllWarnings(sdf.warnings);
  const CollisionGeometry& box = sdf.model.collisions[1];
  EXPECT_EQ(box.shape.type, ShapeType::kConvex);
  EXPECT_TRUE(box.shape.convex.upper.isApprox(Vector3d::Constant(0.1)));
  const SdfImport ell = ImportSdfFile(kData + "l_shape_on_plane.sdf");
  EXPECT_THAT(AllWarnings(ell.warnings),
              AllOf(HasSubstr("mesh 'l_shape.stl' is not convex"), HasSubstr("hull is used")));
}

}  // namespace
}  // namespace mbstream
