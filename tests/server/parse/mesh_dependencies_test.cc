// The files a mesh names (OBJ mtllib, MTL maps, Collada images, glTF uris) and the asset
// names they get beside the mesh in a bundle.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "server/parse/mesh_dependencies.h"

namespace mbstream {
namespace {

using ::testing::ElementsAre;
using ::testing::IsEmpty;

TEST(MeshDependenciesTest, AnObjNamesItsMaterialLibrariesAndTheyNameTheirImages) {
  EXPECT_THAT(MeshFileReferences("a.OBJ",
                                 "# mtllib not.mtl\nmtllib  my parts.mtl \r\nv 0 0 0\n"
                                 "mtllib my parts.mtl\nusemtl x\n"),
              ElementsAre("my parts.mtl"));
  EXPECT_THAT(MeshFileReferences("a.mtl",
                                 "newmtl x\nKd 0 0 0\nmap_Kd -s 1 1 1 tex\\skin.png\n"
                                 "map_bump -bm 0.5 bump.png\nnorm n%20map.png\n"
                                 "refl -type sphere file:///abs/env.jpg\nmap_Kd\n"),
              ElementsAre("tex/skin.png", "bump.png", "n map.png", "/abs/env.jpg"));
}

TEST(MeshDependenciesTest, ColladaNamesTheImagesOfItsLibraryNotItsEffectsSurfaces) {
  const std::string dae = R"(<COLLADA><library_images>
    <image id="i1"><init_from>../textures/skin.png</init_from></image>
    <image id="i2"><init_from><ref>file://wood.jpg</ref></init_from></image>
    <image id="i3"><init_from>http://example.com/x.png</init_from></image>
  </library_images><library_effects><newparam sid="s"><surface type="2D">
    <init_from>i1</init_from></surface></newparam></library_effects></COLLADA>)";
  EXPECT_THAT(MeshFileReferences("m.dae", dae), ElementsAre("../textures/skin.png", "wood.jpg"));
}

TEST(MeshDependenciesTest, GltfNamesItsBuffersAndImagesButNotEmbeddedData) {
  const std::string gltf = R"({"buffers":[{"uri":"m.bin","byteLength":4},
    {"uri" : "data:application/octet-stream;base64,AAAA"}],"images":[{"uri":"tex\/a.png"}]})";
  EXPECT_THAT(MeshFileReferences("m.gltf", gltf), ElementsAre("m.bin", "tex/a.png"));
  EXPECT_THAT(MeshFileReferences("m.stl", "mtllib a.mtl"), IsEmpty());
  EXPECT_TRUE(MayReferenceFiles("package://r/m.DAE"));
  EXPECT_FALSE(MayReferenceFiles("m.stl"));
  EXPECT_TRUE(IsMeshCompanionName("T.PNG"));
  EXPECT_FALSE(IsMeshCompanionName("notes.txt"));
}

TEST(MeshDependenciesTest, CompanionsAreNamedBesideTheMeshAndNeverLeaveTheBundle) {
  EXPECT_EQ(CompanionAssetName("r/meshes/a.obj", "a.mtl"), "r/meshes/a.mtl");
  EXPECT_EQ(CompanionAssetName("r/meshes/a.obj", "../textures/./t.png"), "r/textures/t.png");
  EXPECT_EQ(CompanionAssetName("a.obj", "t.png"), "t.png");
  EXPECT_EQ(CompanionAssetName("meshes/a.obj", "../../t.png"), "");
  EXPECT_EQ(CompanionAssetName("a.obj", "/etc/passwd"), "");
  EXPECT_EQ(CompanionAssetName("a.obj", "C:/textures/t.png"), "");
  EXPECT_EQ(CompanionAssetName("a.obj", "."), "");
}

}  // namespace
}  // namespace mbstream
