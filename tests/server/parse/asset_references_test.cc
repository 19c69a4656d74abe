// Matching a bundle's asset names to URDF meshes and scene-script Parts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/parse/asset_references.h"
#include "server/parse/urdf_meshes.h"

namespace mbstream {
namespace {

using ::testing::ElementsAre;

TEST(AssetReferencesTest, UrdfMeshNames) {
  EXPECT_THAT(UrdfMeshAssetNames("package://robot/meshes/base.stl"),
              ElementsAre("package://robot/meshes/base.stl", "robot/meshes/base.stl",
                          "meshes/base.stl", "base.stl"));
  EXPECT_TRUE(MeshSupplied("file://meshes/a.stl", {"meshes/a.stl"}));
  EXPECT_TRUE(MeshSupplied("package://r/meshes/a.stl", {"a.stl"}));
  EXPECT_FALSE(MeshSupplied("package://r/meshes/a.stl", {"b.stl"}));
}

TEST(AssetReferencesTest, ScenePartsSkipCommentsAndIgnoreCase) {
  const std::string scene =
      "Device Robot;\n! Part commented;\nPART base ;part(x) arm;\n$ Part hidden\n$ Part tool;\n";
  EXPECT_THAT(ScenePartNames(scene), ElementsAre("base", "tool"));
  EXPECT_THAT(ScenePartAssetNames("tool"), ElementsAre("tool.stl", "tool.STL", "tool"));
}

TEST(AssetReferencesTest, UnreferencedAssetsInTheOrderGiven) {
  EXPECT_THAT(UnreferencedAssets({"spare.stl", "base.stl", "tool.STL", "notes.txt", "meshes/x.stl"},
                                 {"package://r/meshes/base.stl", "meshes/x.stl"}, "Part tool;"),
              ElementsAre("spare.stl", "notes.txt"));
}

}  // namespace
}  // namespace mbstream
