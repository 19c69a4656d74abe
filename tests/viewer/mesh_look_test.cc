// How meshes look (issue 30, "Looking like itself"): a link whose mesh is missing is a
// tinted box named on one HUD line, not a text label per link; a mesh whose colour comes from
// a texture (an OBJ .mtl with map_Kd and a black Kd, a Collada <texture>) is drawn with it.
// Under Xvfb; the page's scene export is checked to carry the same.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkActor2DCollection.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkProp.h>
#include <vtkPropCollection.h>
#include <vtkProperty.h>
#include <vtkTextActor.h>
#include <vtkTexture.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/viewer/xvfb_display.h"
#include "viewer/model/urdf_scene.h"
#include "viewer/scene/scene.h"
#include "viewer/scene/visual_pipeline.h"
#include "viewer/web/scene_export.h"

namespace mbstream::viewer {
namespace {

namespace fs = std::filesystem;

SceneOptions SmallOffscreen() {
  SceneOptions options;
  options.width = 320;
  options.height = 240;
  options.offscreen = true;
  return options;
}

std::string LinkWithMesh(const std::string& link, const std::string& file) {
  return "<link name=\"" + link +
         "\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" "
         "ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial><visual><geometry><mesh filename=\"" +
         file + "\"/></geometry></visual></link>\n";
}

std::string FixedJoint(const std::string& parent, const std::string& child) {
  return "<joint name=\"" + child + "_joint\" type=\"fixed\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/><origin xyz=\"0 0 0.3\"/></joint>\n";
}

std::vector<vtkTextActor*> TextActors(vtkRenderer* renderer) {
  std::vector<vtkTextActor*> texts;
  vtkActor2DCollection* actors = renderer->GetActors2D();
  actors->InitTraversal();
  while (vtkActor2D* actor = actors->GetNextActor2D()) {
    if (auto* text = vtkTextActor::SafeDownCast(actor)) texts.push_back(text);
  }
  return texts;
}

int PropsOfClass(vtkRenderer* renderer, const char* name) {
  int count = 0;
  vtkPropCollection* props = renderer->GetViewProps();
  props->InitTraversal();
  while (vtkProp* prop = props->GetNextProp()) count += prop->IsA(name) ? 1 : 0;
  return count;
}

TEST(MissingMeshesLine, CountsNamesOnceAndTruncates) {
  EXPECT_EQ(MissingMeshesLine({}), "");
  EXPECT_EQ(MissingMeshesLine({{"package://r/meshes/a.dae", false}}), "1 mesh missing: a.dae");
  EXPECT_EQ(
      MissingMeshesLine(
          {{"package://r/a.dae", false}, {"package://r/a.dae", false}, {"model://r/b.stl", true}}),
      "2 meshes missing: a.dae, b.stl (unreadable)");
  std::vector<MissingMesh> fifty;
  for (int i = 0; i < 50; ++i) fifty.push_back({"meshes/link" + std::to_string(i) + ".dae", false});
  EXPECT_EQ(MissingMeshesLine(fifty),
            "50 meshes missing: link0.dae, link1.dae, link2.dae, link3.dae and 46 more");
}

TEST(MeshLook, MissingMeshesAreTintedBoxesNamedOnOneHudLine) {
  const std::string urdf = "<robot name=\"r\">\n" + LinkWithMesh("base", "package://r/m/a.dae") +
                           LinkWithMesh("upper", "package://r/m/b.dae") +
                           LinkWithMesh("fore", "package://r/m/c.dae") +
                           FixedJoint("base", "upper") + FixedJoint("upper", "fore") + "</robot>";
  const SceneDescription description = SceneFromUrdf(urdf, "r.urdf", "/nonexistent");
  ASSERT_EQ(description.visuals.size(), 3u);
  EXPECT_EQ(description.warnings.size(), 3u);  // the log still names each link and file
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, SmallOffscreen());

  const std::vector<vtkTextActor*> texts = TextActors(scene.renderer());
  ASSERT_EQ(texts.size(), 1u);
  EXPECT_STREQ(texts[0]->GetInput(), "3 meshes missing: a.dae, b.dae, c.dae");
  EXPECT_EQ(scene.missing_meshes_line(), "3 meshes missing: a.dae, b.dae, c.dae");
  EXPECT_EQ(PropsOfClass(scene.renderer(), "vtkBillboardTextActor3D"), 0);  // no per-link label
  EXPECT_EQ(PropsOfClass(scene.renderer(), "vtkTextActor3D"), 0);

  ASSERT_EQ(scene.part_actor_count(), 3);
  for (const vtkSmartPointer<vtkActor>& actor : scene.part_actors()) {
    double colour[3];
    actor->GetProperty()->GetColor(colour);
    EXPECT_DOUBLE_EQ(colour[0], kPlaceholderColour.x());
    EXPECT_DOUBLE_EQ(colour[1], kPlaceholderColour.y());
    EXPECT_DOUBLE_EQ(colour[2], kPlaceholderColour.z());
    EXPECT_DOUBLE_EQ(actor->GetProperty()->GetOpacity(), kPlaceholderOpacity);
    EXPECT_LT(kPlaceholderOpacity, 1.0);
  }
  scene.Render();  // draws with the line
  // The page gets the same line for its HUD, and the tint in the parts' colours.
  const std::string json = ExportSceneJson(scene, 1);
  EXPECT_NE(json.find(R"("missing_meshes":"3 meshes missing: a.dae, b.dae, c.dae")"),
            std::string::npos);
  EXPECT_NE(json.find(R"("opacity":0.55)"), std::string::npos);
}

TEST(MeshLook, AModelWithEveryMeshNoPlaceholderHasNoHudLine) {
  const SceneDescription description = SceneFromUrdf(
      "<robot name=\"r\"><link name=\"a\"><visual><geometry><box size=\"0.1 0.1 "
      "0.1\"/></geometry></visual></link></robot>",
      "r.urdf", "/nonexistent");
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, SmallOffscreen());
  EXPECT_TRUE(TextActors(scene.renderer()).empty());
  EXPECT_EQ(scene.missing_meshes_line(), "");
}

// A cube of edge 0.2 m centred at the origin, every face mapped to the whole texture, its
// material black with map_Kd `image` (as published humanoids' OBJ files are).
void WriteTexturedObjCube(const fs::path& obj, const std::string& image) {
  const fs::path mtl = fs::path(obj).replace_extension(".mtl");
  std::ofstream(mtl) << "newmtl skin\nKa 0 0 0\nKd 0 0 0\nKs 0 0 0\nmap_Kd " << image << "\n";
  std::ofstream out(obj);
  out << "mtllib " << mtl.filename().string() << "\nusemtl skin\n";
  const double h = 0.1;
  for (int i = 0; i < 8; ++i) {
    out << "v " << ((i & 1) ? h : -h) << ' ' << ((i & 2) ? h : -h) << ' ' << ((i & 4) ? h : -h)
        << "\n";
  }
  out << "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n";
  // Faces by vertex numbers (1-based), each corner with its texture coordinate.
  const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                           {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
  for (const auto& face : faces) {
    out << "f";
    for (int k = 0; k < 4; ++k) out << ' ' << face[k] << '/' << (k + 1);
    out << "\n";
  }
}

// A uniform 16 x 16 PNG of colour (r, g, b).
void WritePng(const fs::path& path, unsigned char r, unsigned char g, unsigned char b) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(16, 16, 1);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* pixels = static_cast<unsigned char*>(image->GetScalarPointer());
  for (int i = 0; i < 16 * 16; ++i) {
    pixels[3 * i] = r;
    pixels[3 * i + 1] = g;
    pixels[3 * i + 2] = b;
  }
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(path.string().c_str());
  writer->SetInputData(image);
  writer->Write();
}

// The same cube as Collada: a <lambert> whose <diffuse> is a <texture> of `image`.
void WriteTexturedColladaCube(const fs::path& dae, const std::string& image) {
  std::string positions;
  for (int i = 0; i < 8; ++i) {
    for (int axis : {1, 2, 4}) positions += std::string((i & axis) ? "0.1 " : "-0.1 ");
  }
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::string p;  // vertex, texture coordinate; two triangles per face
  for (const auto& face : faces) {
    for (int k : {0, 1, 2, 0, 2, 3}) p += std::to_string(face[k]) + " " + std::to_string(k) + " ";
  }
  std::ofstream(dae) << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Z_UP</up_axis></asset>
  <library_images><image id="skin-image"><init_from>)"
                     << image << R"(</init_from></image></library_images>
  <library_effects><effect id="skin-effect"><profile_COMMON>
    <newparam sid="skin-surface"><surface type="2D"><init_from>skin-image</init_from></surface></newparam>
    <newparam sid="skin-sampler"><sampler2D><source>skin-surface</source></sampler2D></newparam>
    <technique sid="common"><lambert>
      <diffuse><texture texture="skin-sampler" texcoord="UVMap"/></diffuse>
    </lambert></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="skin" name="skin">
    <instance_effect url="#skin-effect"/></material></library_materials>
  <library_geometries><geometry id="cube" name="cube"><mesh>
    <source id="cube-positions"><float_array id="cube-positions-array" count="24">)"
                     << positions << R"(</float_array>
      <technique_common><accessor source="#cube-positions-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <source id="cube-uv"><float_array id="cube-uv-array" count="8">0 0 1 0 1 1 0 1</float_array>
      <technique_common><accessor source="#cube-uv-array" count="4" stride="2">
        <param name="S" type="float"/><param name="T" type="float"/>
      </accessor></technique_common></source>
    <vertices id="cube-vertices"><input semantic="POSITION" source="#cube-positions"/></vertices>
    <triangles material="skin-material" count="12">
      <input semantic="VERTEX" source="#cube-vertices" offset="0"/>
      <input semantic="TEXCOORD" source="#cube-uv" offset="1" set="0"/><p>)"
                     << p << R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="cube-node" name="cube">
    <instance_geometry url="#cube"><bind_material><technique_common>
      <instance_material symbol="skin-material" target="#skin">
        <bind_vertex_input semantic="UVMap" input_semantic="TEXCOORD" input_set="0"/>
      </instance_material>
    </technique_common></bind_material></instance_geometry>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

class TexturedMeshTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A folder per test: the mesh cache keys an OBJ by its bytes and folder (mesh_cache.h).
    dir_ = fs::temp_directory_path() /
           ("mbstream_mesh_look_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    WritePng(dir_ / "skin.png", 200, 60, 40);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Draws `mesh` alone under Xvfb and checks the pixel at its centre has the texture's
  // colour, lit: red well above green and blue, in the texture's proportions (a black
  // material would draw a black silhouette); the page gets the image and the coordinates.
  void ExpectDrawnWithTheTexture(const fs::path& mesh) {
    SceneDescription description;
    description.title = "textured";
    VisualPart part;
    part.name = "cube";
    part.geometry = MeshFile{mesh, true};
    description.visuals.push_back(part);
    ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
    Scene scene(description, SmallOffscreen());

    ASSERT_EQ(scene.part_actor_count(), 1);
    EXPECT_NE(scene.part_actors()[0]->GetTexture(), nullptr);
    const RgbImage image = scene.Capture();
    const std::uint8_t* centre = image.At(image.width / 2, image.height / 2);
    const int r = centre[0], g = centre[1], b = centre[2];
    RecordProperty("centre_rgb",
                   std::to_string(r) + " " + std::to_string(g) + " " + std::to_string(b));
    EXPECT_GT(r, 80) << r << " " << g << " " << b;
    EXPECT_GT(r, 2 * g) << r << " " << g << " " << b;
    EXPECT_GT(r, 2 * b) << r << " " << g << " " << b;
    EXPECT_NEAR(static_cast<double>(g) / r, 60.0 / 200.0, 0.12) << r << " " << g << " " << b;

    const std::string json = ExportSceneJson(scene, 1);
    EXPECT_NE(json.find(R"("texture_png":"iVBORw0KGgo)"), std::string::npos);  // PNG signature
    EXPECT_NE(json.find(R"("uvs":")"), std::string::npos);
  }

  fs::path dir_;
};

TEST_F(TexturedMeshTest, AnObjWhoseColourIsATextureIsDrawnWithIt) {
  WriteTexturedObjCube(dir_ / "cube.obj", "skin.png");
  ExpectDrawnWithTheTexture(dir_ / "cube.obj");
}

TEST_F(TexturedMeshTest, AColladaTextureIsDrawnWithIt) {
  WriteTexturedColladaCube(dir_ / "cube.dae", "skin.png");
  ExpectDrawnWithTheTexture(dir_ / "cube.dae");
}

TEST_F(TexturedMeshTest, AMissingImageLeavesTheMaterialColour) {
  WriteTexturedObjCube(dir_ / "cube.obj", "not_there.png");
  VisualPart part;
  part.geometry = MeshFile{dir_ / "cube.obj", true};
  const VisualActors made = MakeVisualActors(part);
  ASSERT_EQ(made.actors.size(), 1u);
  EXPECT_EQ(made.actors[0]->GetTexture(), nullptr);
  EXPECT_TRUE(made.textured);  // logged once per scene as not drawn
}

}  // namespace
}  // namespace mbstream::viewer
