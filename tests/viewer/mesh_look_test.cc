// How meshes look (issue 30, "Looking like itself"): a link whose mesh is missing is a
// tinted box named on one HUD line, not a text label per link; a mesh whose colour comes from
// a texture (an OBJ .mtl with map_Kd and a black Kd) is drawn with it. Under Xvfb.
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

TEST(MeshLook, AnObjWhoseColourIsATextureIsDrawnWithIt) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream_mesh_look_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  WritePng(dir / "skin.png", 200, 60, 40);
  WriteTexturedObjCube(dir / "cube.obj", "skin.png");

  SceneDescription description;
  description.title = "textured";
  VisualPart part;
  part.name = "cube";
  part.geometry = MeshFile{dir / "cube.obj", true};
  description.visuals.push_back(part);
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, SmallOffscreen());

  ASSERT_EQ(scene.part_actor_count(), 1);
  EXPECT_NE(scene.part_actors()[0]->GetTexture(), nullptr);
  const RgbImage image = scene.Capture();
  const std::uint8_t* centre = image.At(image.width / 2, image.height / 2);
  const int r = centre[0], g = centre[1], b = centre[2];
  // The texture's colour, lit: red well above green and blue, in the texture's proportions
  // (a black material would draw a black silhouette).
  EXPECT_GT(r, 80) << r << " " << g << " " << b;
  EXPECT_GT(r, 2 * g) << r << " " << g << " " << b;
  EXPECT_GT(r, 2 * b) << r << " " << g << " " << b;
  EXPECT_NEAR(static_cast<double>(g) / r, 60.0 / 200.0, 0.12) << r << " " << g << " " << b;
  // The page gets the image and the texture coordinates with the part.
  const std::string json = ExportSceneJson(scene, 1);
  EXPECT_NE(json.find(R"("texture_png":"iVBORw0KGgo)"), std::string::npos);  // PNG signature
  EXPECT_NE(json.find(R"("uvs":")"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::viewer
