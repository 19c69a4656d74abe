// Matching a bundle's asset names to URDF meshes and scene-script Parts.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/parse/asset_references.h"
#include "server/parse/urdf_meshes.h"
#include "shared/model_files/mesh_lookup.h"

namespace mbstream {
namespace {

using ::testing::ElementsAre;

TEST(AssetReferencesTest, UrdfMeshesAreLookedUpByEveryNameTheViewerUses) {
  EXPECT_THAT(UrdfMeshAssetNames("package://robot/meshes/base.stl"),
              ElementsAre("package://robot/meshes/base.stl", "robot/meshes/base.stl",
                          "meshes/base.stl", "base.stl"));
  // The name mbstream submit stores a mesh under: the path written, as a relative path.
  EXPECT_EQ(model_files::BundleAssetName("package://robot/meshes/base.stl"),
            "robot/meshes/base.stl");
  EXPECT_EQ(model_files::BundleAssetName("../meshes/visual/./link0.stl"),
            "meshes/visual/link0.stl");
  EXPECT_EQ(model_files::BundleAssetName("file:///opt/robot/meshes/a.dae"),
            "opt/robot/meshes/a.dae");
  EXPECT_THAT(UrdfMeshAssetNames("../meshes/visual/link0.stl"),
              ElementsAre("../meshes/visual/link0.stl", "meshes/visual/link0.stl", "link0.stl"));
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

TEST(AssetReferencesTest, AnObjKeepsItsMaterialAndImageAndAnUnrelatedFileIsStillDropped) {
  const std::vector<std::string> assets = {"meshes/cube.obj", "meshes/cube.mtl",
                                           "textures/skin.png", "notes.txt", "spare.stl"};
  EXPECT_THAT(UnreferencedAssets(assets, {"package://r/meshes/cube.obj"}, ""),
              ElementsAre("notes.txt", "spare.stl"));
  // Meshes that name no files (STL) keep no images.
  EXPECT_THAT(UnreferencedAssets({"base.stl", "skin.png", "base.mtl"}, {"base.stl"}, ""),
              ElementsAre("skin.png", "base.mtl"));
}

}  // namespace
}  // namespace mbstream
