// A robot described the way published ones are: a URDF whose visuals are mesh files in
// every format the viewer reads (written by the test), URDF materials by name and inline,
// a missing mesh. Checks the scene's bounds (units applied), colours (URDF material, else
// the file's, else grey), the mesh cache, and a rendered snapshot (under Xvfb) that is
// neither blank nor badly framed.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkProperty.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <set>

#include "bench/viewer/large_model.h"
#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/mesh_lookup.h"
#include "tests/viewer/test_meshes.h"
#include "tests/viewer/xvfb_display.h"
#include "viewer/model/urdf_scene.h"
#include "viewer/scene/mesh_cache.h"
#include "viewer/scene/scene.h"
#include "viewer/scene/visual_pipeline.h"

namespace mbstream::viewer {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;

const Vector3d kBlue(0.2, 0.4, 0.8);
const Vector3d kRed(0.9, 0.1, 0.1);
const Vector3d kGreen(0.1, 0.9, 0.1);
const Vector3d kLeaf(0.1, 0.8, 0.2);
const Vector3d kOrange(1.0, 0.5, 0.0);
const Vector3d kPurple(0.5, 0.0, 0.5);
const Vector3d kGrey = Vector3d::Constant(0.7);

const char* kInertial =
    R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>)";

std::string Revolute(const std::string& name, const std::string& parent, const std::string& child,
                     const std::string& xyz, const std::string& axis) {
  return "<joint name=\"" + name + "\" type=\"revolute\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\"/><axis xyz=\"" + axis +
         "\"/><limit lower=\"-3\" upper=\"3\" effort=\"10\" velocity=\"2\"/></joint>\n";
}

std::string Fixed(const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& xyz) {
  return "<joint name=\"" + name + "\" type=\"fixed\"><parent link=\"" + parent +
         "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\"/></joint>\n";
}

std::string MeshVisual(const std::string& file, const std::string& extra = "") {
  return "<visual><geometry><mesh filename=\"" + file + "\"" + extra + "/></geometry>";
}

// Writes the robot's folder under a fresh directory; returns the URDF's path.
fs::path WriteRobot(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream_mesh_scene_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "meshes" / "visual");
  fs::create_directories(dir / "urdf");
  // 300 x 300 x 200 mm, Z up.
  testing::WriteColladaBox(dir / "meshes/visual/base.dae", Vector3d(-150, -150, 0),
                           Vector3d(150, 150, 200), 0.001, "Z_UP", kBlue);
  testing::WriteObjBoxes(dir / "meshes/visual/upper.obj", Vector3d(-0.05, -0.05, 0),
                         Vector3d(0.05, 0.05, 0.4), kRed, kGreen);
  testing::WriteStlBox(dir / "meshes/visual/fore.stl", Vector3d(-40, -40, 0),
                       Vector3d(40, 40, 300));  // mm, scaled in the URDF
  testing::WriteGltfBox(dir / "meshes/visual/wrist.gltf", Vector3d(-0.03, -0.03, 0),
                        Vector3d(0.03, 0.03, 0.2), kLeaf);
  testing::WritePlyBox(dir / "meshes/visual/flange.ply", Vector3d(-0.04, -0.04, 0),
                       Vector3d(0.04, 0.04, 0.02));
  testing::WriteStlBox(dir / "meshes/visual/tool.stl", Vector3d(-0.01, -0.01, 0.02),
                       Vector3d(0.01, 0.01, 0.1), false);
  const std::string urdf =
      "<robot name=\"meshbot\">\n"
      "<material name=\"orange\"><color rgba=\"1 0.5 0 1\"/></material>\n"
      "<link name=\"base_link\">" +
      MeshVisual("package://meshbot/meshes/visual/base.dae") + "</visual></link>\n" +
      "<link name=\"upper\">" + std::string(kInertial) + MeshVisual("../meshes/visual/upper.obj") +
      "</visual></link>\n" + "<link name=\"fore\">" + kInertial +
      MeshVisual("package://meshbot/meshes/visual/fore.stl", " scale=\"0.001 0.001 0.001\"") +
      "<material name=\"orange\"/></visual></link>\n" + "<link name=\"wrist\">" + kInertial +
      MeshVisual("package://meshbot/meshes/visual/wrist.gltf") + "</visual></link>\n" +
      "<link name=\"flange\">" + MeshVisual("package://meshbot/meshes/visual/flange.ply") +
      "</visual>" + MeshVisual("package://meshbot/meshes/visual/tool.stl") +
      "<material name=\"purple\"><color rgba=\"0.5 0 0.5 1\"/></material></visual></link>\n" +
      "<link name=\"tool0\"/>\n" + "<link name=\"camera\">" +
      R"(<inertial><origin xyz="0.2 0 0.1"/><mass value="2"/><inertia ixx="0.003" iyy="0.003" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial>)" +
      MeshVisual("package://meshbot/meshes/visual/camera.dae") + "</visual></link>\n" +
      Revolute("j1", "base_link", "upper", "0 0 0.2", "0 0 1") +
      Revolute("j2", "upper", "fore", "0 0 0.4", "0 1 0") +
      Revolute("j3", "fore", "wrist", "0 0 0.3", "0 1 0") +
      Fixed("wrist_flange", "wrist", "flange", "0 0 0.2") +
      Fixed("flange_tool0", "flange", "tool0", "0 0 0.1") +
      Fixed("base_camera", "base_link", "camera", "0 0 0") + "</robot>\n";
  std::ofstream(dir / "urdf/meshbot.urdf") << urdf;
  return dir / "urdf/meshbot.urdf";
}

Eigen::AlignedBox3d Bounds(const VisualPart& part) {
  double b[6];
  VisualSurface(part)->GetBounds(b);
  return Eigen::AlignedBox3d(Vector3d(b[0], b[2], b[4]), Vector3d(b[1], b[3], b[5]));
}

// The actors' colours, sorted, to 3 decimals (files store floats).
std::vector<std::array<int, 3>> Colours(const VisualPart& part) {
  std::vector<std::array<int, 3>> colours;
  for (const auto& actor : MakeVisualActors(part).actors) {
    const double* c = actor->GetProperty()->GetColor();
    colours.push_back({int(std::lround(c[0] * 1000)), int(std::lround(c[1] * 1000)),
                       int(std::lround(c[2] * 1000))});
  }
  std::sort(colours.begin(), colours.end());
  return colours;
}

std::vector<std::array<int, 3>> Expected(std::vector<Vector3d> colours) {
  std::vector<std::array<int, 3>> out;
  for (const Vector3d& c : colours) {
    out.push_back({int(std::lround(c[0] * 1000)), int(std::lround(c[1] * 1000)),
                   int(std::lround(c[2] * 1000))});
  }
  std::sort(out.begin(), out.end());
  return out;
}

bool Near(const Eigen::AlignedBox3d& box, const Vector3d& low, const Vector3d& high) {
  return (box.min() - low).norm() < 1e-6 && (box.max() - high).norm() < 1e-6;
}

class MeshSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    urdf_ = WriteRobot(::testing::UnitTest::GetInstance()->current_test_info()->name());
    scene_ = SceneFromUrdfFile(urdf_);
  }
  void TearDown() override { fs::remove_all(urdf_.parent_path().parent_path()); }

  const VisualPart& Visual(const std::string& link, int index = 0) {
    for (const VisualPart& part : scene_.visuals) {
      if (part.name == link && index-- == 0) return part;
    }
    ADD_FAILURE() << "no visual " << index << " of link " << link;
    return scene_.visuals.front();
  }

  fs::path urdf_;
  SceneDescription scene_;
};

TEST_F(MeshSceneTest, ChainTcpAndMissingMesh) {
  EXPECT_EQ(scene_.title, "meshbot");
  ASSERT_EQ(scene_.chain.dof(), 3);
  EXPECT_EQ(scene_.chain.dof_joint(2).name, "j3");
  ASSERT_EQ(scene_.probes.size(), 1u);
  EXPECT_EQ(scene_.frame_names[scene_.probes[0].frame], "tool0");
  EXPECT_EQ(scene_.visuals.size(), 7u);
  ASSERT_EQ(scene_.warnings.size(), 1u);
  EXPECT_NE(scene_.warnings[0].find("link 'camera': mesh "
                                    "'package://meshbot/meshes/visual/camera.dae' is not in the "
                                    "model's files"),
            std::string::npos)
      << scene_.warnings[0];
  const VisualPart& camera = Visual("camera");
  EXPECT_TRUE(camera.placeholder);
  EXPECT_EQ(camera.mesh_filename, "package://meshbot/meshes/visual/camera.dae");
  // 2 kg, 0.003 kg*m^2 about each axis: a cube of edge sqrt(6 * 0.003 / 2) = 0.0949 m
  // around the centre of mass.
  const double edge = std::sqrt(6 * 0.003 / 2);
  EXPECT_TRUE(Near(Bounds(camera), Vector3d(0.2 - edge / 2, -edge / 2, 0.1 - edge / 2),
                   Vector3d(0.2 + edge / 2, edge / 2, 0.1 + edge / 2)));
}

TEST_F(MeshSceneTest, UnitsAndScalesAreApplied) {
  // Collada in mm (<unit meter="0.001">), Z up: metres, axes kept.
  EXPECT_TRUE(
      Near(Bounds(Visual("base_link")), Vector3d(-0.15, -0.15, 0), Vector3d(0.15, 0.15, 0.2)));
  // OBJ (two boxes side by side), metres.
  EXPECT_TRUE(Near(Bounds(Visual("upper")), Vector3d(-0.05, -0.05, 0), Vector3d(0.15, 0.05, 0.4)));
  // Binary STL in mm with the URDF's scale 0.001.
  EXPECT_TRUE(Near(Bounds(Visual("fore")), Vector3d(-0.04, -0.04, 0), Vector3d(0.04, 0.04, 0.3)));
  EXPECT_TRUE(Near(Bounds(Visual("wrist")), Vector3d(-0.03, -0.03, 0), Vector3d(0.03, 0.03, 0.2)));
  EXPECT_TRUE(
      Near(Bounds(Visual("flange")), Vector3d(-0.04, -0.04, 0), Vector3d(0.04, 0.04, 0.02)));
  EXPECT_TRUE(
      Near(Bounds(Visual("flange", 1)), Vector3d(-0.01, -0.01, 0.02), Vector3d(0.01, 0.01, 0.1)));
}

TEST_F(MeshSceneTest, ColladaUpAxisIsNotAppliedButItsUnitIs) {
  // A Y_UP file is drawn in its own axes, as rviz draws it (published robots are checked
  // there); its unit still applies.
  const fs::path y_up = urdf_.parent_path() / "y_up.dae";
  testing::WriteColladaBox(y_up, Vector3d(0, 0, 0), Vector3d(10, 20, 30), 0.01, "Y_UP", kBlue);
  VisualPart part;
  part.geometry = MeshFile{y_up, true};
  EXPECT_TRUE(Near(Bounds(part), Vector3d::Zero(), Vector3d(0.1, 0.2, 0.3)));
}

TEST_F(MeshSceneTest, UrdfMaterialWinsThenFileColoursThenGrey) {
  EXPECT_EQ(Colours(Visual("base_link")), Expected({kBlue}));     // the Collada's
  EXPECT_EQ(Colours(Visual("upper")), Expected({kRed, kGreen}));  // the .mtl's, per material
  EXPECT_EQ(Colours(Visual("fore")), Expected({kOrange}));        // URDF, by name
  EXPECT_EQ(Colours(Visual("wrist")), Expected({kLeaf}));         // glTF base colour
  EXPECT_EQ(Colours(Visual("flange")), Expected({kGrey}));        // PLY: none
  EXPECT_EQ(Colours(Visual("flange", 1)), Expected({kPurple}));   // URDF, inline
  // A URDF colour wins over the file's.
  VisualPart base = Visual("base_link");
  std::get<MeshFile>(base.geometry).file_colours = false;
  base.color = kOrange;
  EXPECT_EQ(Colours(base), Expected({kOrange}));
}

TEST_F(MeshSceneTest, SameBytesAreReadOnce) {
  const fs::path copy = urdf_.parent_path() / "fore_copy.stl";
  fs::copy_file(urdf_.parent_path().parent_path() / "meshes/visual/fore.stl", copy);
  VisualPart a = Visual("fore");
  VisualPart b = a;
  std::get<MeshFile>(b.geometry).path = copy;
  MakeVisualActors(a);
  const long long reads = MeshCacheStatistics().reads;
  MakeVisualActors(b);
  MakeVisualActors(a);
  EXPECT_EQ(MeshCacheStatistics().reads, reads);
}

TEST_F(MeshSceneTest, AnUnreadableMeshIsDrawnAsItsPlaceholder) {
  std::ofstream(urdf_.parent_path().parent_path() / "meshes/visual/wrist.gltf") << "not glTF";
  const SceneDescription scene = SceneFromUrdfFile(urdf_);
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  SceneOptions options;
  options.width = 320;
  options.height = 240;
  options.offscreen = true;
  Scene built(scene, options);
  EXPECT_EQ(built.missing_meshes_line(), "2 meshes missing: wrist.gltf (unreadable), camera.dae");
}

TEST_F(MeshSceneTest, SnapshotShowsTheWholeRobotFramed) {
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  SceneOptions options;
  options.width = 640;
  options.height = 480;
  options.offscreen = true;
  Scene scene(scene_, options);
  // The background alone: every actor hidden.
  std::vector<vtkActor*> actors;
  vtkActorCollection* collection = scene.renderer()->GetActors();
  collection->InitTraversal();
  while (vtkActor* actor = collection->GetNextActor()) actors.push_back(actor);
  for (vtkActor* actor : actors) actor->VisibilityOff();
  const RgbImage background = scene.Capture();
  for (vtkActor* actor : actors) actor->VisibilityOn();
  const RgbImage image = scene.Capture();

  int count = 0, min_x = 640, max_x = -1, min_y = 480, max_y = -1;
  bool blue = false;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(int(image.At(x, y)[c]) - int(background.At(x, y)[c])));
      }
      if (d <= 12) continue;
      ++count;
      min_x = std::min(min_x, x), max_x = std::max(max_x, x);
      min_y = std::min(min_y, y), max_y = std::max(max_y, y);
      const auto* p = image.At(x, y);
      blue = blue || (p[2] > p[0] + 40 && p[2] > p[1] + 20);  // the Collada base's colour
    }
  }
  ASSERT_GT(count, 640 * 480 / 100) << "the snapshot is blank";
  const double width = (max_x - min_x + 1) / 640.0, height = (max_y - min_y + 1) / 480.0;
  EXPECT_GE(std::max(width, height), 0.4) << "the model covers " << width << " x " << height;
  EXPECT_GT(min_x, 0);  // inside the picture
  EXPECT_LT(max_x, 639);
  EXPECT_GT(min_y, 0);
  EXPECT_LT(max_y, 479);
  EXPECT_TRUE(blue) << "the base's Collada colour is not in the picture";
}

}  // namespace
}  // namespace mbstream::viewer

namespace mbstream::viewer {
namespace {

// Pixels that differ from the background.
std::vector<bool> Mask(Scene& scene) {
  std::vector<vtkActor*> actors;
  vtkActorCollection* collection = scene.renderer()->GetActors();
  collection->InitTraversal();
  while (vtkActor* actor = collection->GetNextActor()) actors.push_back(actor);
  for (vtkActor* actor : actors) actor->VisibilityOff();
  const RgbImage background = scene.Capture();
  for (vtkActor* actor : actors) actor->VisibilityOn();
  const RgbImage image = scene.Capture();
  std::vector<bool> mask(size_t(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(int(image.At(x, y)[c]) - int(background.At(x, y)[c])));
      }
      mask[size_t(y) * image.width + x] = d > 12;
    }
  }
  return mask;
}

TEST(MeshDecimation, ATriangleBudgetKeepsTheSilhouette) {
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream_decimation_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const bench::LargeModel model = bench::WriteLargeModel(dir, 2, 3, 140'000);
  const SceneDescription description = SceneFromUrdfFile(model.urdf);
  SceneOptions options;
  options.width = 480;
  options.height = 360;
  options.offscreen = true;
  options.triangle_budget = 0;
  Scene full(description, options);
  options.triangle_budget = 14'000;
  Scene decimated(description, options);
  EXPECT_GT(full.triangle_count(), 130'000);
  EXPECT_LT(decimated.triangle_count(), 14'000 * 1.3);
  EXPECT_GT(decimated.triangle_count(), 14'000 * 0.5);
  const std::vector<bool> a = Mask(full), b = Mask(decimated);
  long long both = 0, either = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    both += a[i] && b[i];
    either += a[i] || b[i];
  }
  ASSERT_GT(either, 480 * 360 / 50);
  EXPECT_GT(double(both) / double(either), 0.97)
      << "silhouettes overlap " << both << " / " << either;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::viewer

namespace mbstream::viewer {
namespace {

// Issue 32: a published robot's URDF names package://val_description/model/meshes/..., and
// its folders were renamed, so the mesh is only found under one of the URDF's ancestors, as
// `mbstream submit` looks (model_files::MeshFileSearch). The viewer's local mode finds it
// the same way and draws the mesh, not a placeholder box.
TEST(LocalMeshLookup, MeshesFoundOnlyUnderTheUrdfsAncestorsAreDrawnAsSubmitFindsThem) {
  ASSERT_EQ(unsetenv("MBSTREAM_PACKAGE_PATH"), 0);
  const fs::path root =
      fs::temp_directory_path() / ("mbstream_ancestor_meshes_" + std::to_string(::getpid()));
  fs::remove_all(root);
  const fs::path urdf_dir = root / "robots" / "valkyrie" / "urdf";
  fs::create_directories(urdf_dir);
  const std::vector<std::string> parts = {"pelvis", "torso"};
  std::string links, joints;
  for (const std::string& part : parts) {
    const fs::path mesh = root / "robots" / "model" / "meshes" / part / (part + ".stl");
    fs::create_directories(mesh.parent_path());
    testing::WriteStlBox(mesh, Vector3d(-0.1, -0.1, 0), Vector3d(0.1, 0.1, 0.3));
    links += "<link name=\"" + part + "\">" + std::string(kInertial) +
             MeshVisual("package://val_description/model/meshes/" + part + "/" + part + ".stl") +
             "</visual></link>\n";
  }
  joints = Revolute("j1", "pelvis", "torso", "0 0 0.3", "0 0 1");
  const fs::path urdf = urdf_dir / "valkyrie.urdf";
  std::ofstream(urdf) << "<robot name=\"valkyrie\">\n" + links + joints + "</robot>\n";

  const model_files::MeshFileSearch submit_search(urdf_dir, {});
  const SceneDescription scene = SceneFromUrdfFile(urdf);
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  ASSERT_EQ(scene.visuals.size(), parts.size());
  for (const VisualPart& part : scene.visuals) {
    const auto* file = std::get_if<MeshFile>(&part.geometry);
    ASSERT_NE(file, nullptr) << part.name << " is a placeholder";
    const fs::path expected =
        root / "robots" / "model" / "meshes" / part.name / (part.name + ".stl");
    EXPECT_EQ(fs::weakly_canonical(file->path), fs::weakly_canonical(expected));
    // The file submit attaches, and one the lookup inside a bundle (beside the URDF, or in
    // its parent) does not find.
    EXPECT_EQ(file->path, submit_search.Find(part.mesh_filename).found);
    EXPECT_TRUE(model_files::FindMeshFile(part.mesh_filename, urdf_dir).empty());
    // The STL's box, not the inertia's (an edge of 0.245 m).
    EXPECT_TRUE(Near(Bounds(part), Vector3d(-0.1, -0.1, 0), Vector3d(0.1, 0.1, 0.3)));
  }
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  SceneOptions options;
  options.width = 320;
  options.height = 240;
  options.offscreen = true;
  Scene drawn(scene, options);
  EXPECT_TRUE(drawn.missing_meshes().empty());  // no placeholder box
  EXPECT_EQ(drawn.part_actor_count(), 2);
  fs::remove_all(root);
}

}  // namespace
}  // namespace mbstream::viewer
