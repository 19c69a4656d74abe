// The VTK scene under an X display (a private Xvfb when none is set): it renders, moves
// only actor matrices, answers probes from any thread, and snapshots.
#include <gtest/gtest.h>

#include <vtkActorCollection.h>
#include <vtkMapper.h>
#include <vtkMassProperties.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkTriangleFilter.h>

#include <atomic>
#include <numbers>
#include <thread>

#include "shared/common/check.h"
#include "tests/viewer/script_test_util.h"
#include "tests/viewer/xvfb_display.h"
#include "viewer/model/script_scene.h"
#include "viewer/model/urdf_scene.h"
#include "viewer/scene/scene.h"
#include "viewer/scene/scene_error.h"
#include "viewer/scene/visual_pipeline.h"

namespace mbstream::viewer {
namespace {

namespace ss = scene_script;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

SceneDescription Irb1600() {
  const ss::Translation translation =
      ss::TranslateScriptFile(ss::testing::SourcePath("models/irb1600/irb1600.scene"));
  EXPECT_TRUE(translation.ok());
  return SceneFromScript(translation.script);
}

std::unique_ptr<Scene> MakeScene(SceneDescription description) {
  if (!testing::EnsureDisplay()) return nullptr;
  SceneOptions options;
  options.width = 640;
  options.height = 480;
  options.offscreen = true;
  return std::make_unique<Scene>(std::move(description), options);
}

// Where a World point lands in a captured image (x right, y down).
Eigen::Vector2i Pixel(Scene& scene, const Vector3d& world) {
  vtkRenderer* renderer = scene.renderer();
  renderer->SetWorldPoint(world.x(), world.y(), world.z(), 1.0);
  renderer->WorldToDisplay();
  double display[3];
  renderer->GetDisplayPoint(display);
  const int height = scene.render_window()->GetSize()[1];
  return {static_cast<int>(std::lround(display[0])),
          height - 1 - static_cast<int>(std::lround(display[1]))};
}

int Difference(const RgbImage& a, const RgbImage& b, int x, int y) {
  int d = 0;
  for (int c = 0; c < 3; ++c) d = std::max(d, std::abs(int(a.At(x, y)[c]) - int(b.At(x, y)[c])));
  return d;
}

// Pixels where `image` differs from the empty background.
std::vector<bool> RobotMask(const RgbImage& image, const RgbImage& background) {
  std::vector<bool> mask(size_t(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      mask[size_t(y) * image.width + x] = Difference(image, background, x, y) > 12;
    }
  }
  return mask;
}

RgbImage Background(Scene& scene) {
  vtkActorCollection* actors = scene.renderer()->GetActors();
  actors->InitTraversal();
  std::vector<vtkActor*> all;
  while (vtkActor* actor = actors->GetNextActor()) all.push_back(actor);
  for (vtkActor* actor : all) actor->VisibilityOff();
  RgbImage background = scene.Capture();
  for (vtkActor* actor : all) actor->VisibilityOn();
  return background;
}

TEST(VtkScene, RendersTheRobotInsideTheFrameAndMovesItBetweenPoses) {
  std::unique_ptr<Scene> scene = MakeScene(Irb1600());
  ASSERT_TRUE(scene) << "no X display and Xvfb could not be started";
  EXPECT_EQ(scene->part_actor_count(), static_cast<int>(scene->description().visuals.size()));
  const RgbImage background = Background(*scene);
  ASSERT_EQ(background.width, 640);
  ASSERT_EQ(background.height, 480);

  const std::vector<double> pose_a(6, 0.0);
  const std::vector<double> pose_b{kPi, -0.5, 0.4, 0.5, 1.0, 0.3};  // turned round
  std::vector<RgbImage> images;
  std::vector<Eigen::Vector2i> tcp_pixels;
  for (const auto& q : {pose_a, pose_b}) {
    scene->SetJointValues(q);
    images.push_back(scene->Capture());
    const Vector3d tcp_world =
        scene->description().chain.base_in_world() * scene->ProbeReports()[0].position_m;
    tcp_pixels.push_back(Pixel(*scene, tcp_world));
  }
  for (int i = 0; i < 2; ++i) {
    const std::vector<bool> mask = RobotMask(images[i], background);
    int robot = 0;
    int on_border = 0;
    for (int y = 0; y < 480; ++y) {
      for (int x = 0; x < 640; ++x) {
        if (!mask[size_t(y) * 640 + x]) continue;
        ++robot;
        if (x < 2 || y < 2 || x >= 638 || y >= 478) ++on_border;
      }
    }
    EXPECT_GT(robot, 640 * 480 / 40) << "pose " << i << ": the robot is too small or missing";
    EXPECT_EQ(on_border, 0) << "pose " << i << ": the robot leaves the frame";
    const Eigen::Vector2i p = tcp_pixels[i];
    ASSERT_TRUE(p.x() > 0 && p.y() > 0 && p.x() < 640 && p.y() < 480);
    EXPECT_TRUE(mask[size_t(p.y()) * 640 + p.x()]) << "pose " << i << ": no robot at the TCP";
  }
  // Where the flange was at pose A there is background at pose B, and the reverse.
  EXPECT_GT(Difference(images[0], images[1], tcp_pixels[0].x(), tcp_pixels[0].y()), 12);
  EXPECT_GT(Difference(images[0], images[1], tcp_pixels[1].x(), tcp_pixels[1].y()), 12);
  // The base does not move.
  const Vector3d foot = scene->description().chain.base_in_world() * Vector3d(0.17, 0.17, 0.015);
  const Eigen::Vector2i f = Pixel(*scene, foot);
  EXPECT_LE(Difference(images[0], images[1], f.x(), f.y()), 2);
  int changed = 0;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) changed += Difference(images[0], images[1], x, y) > 12;
  }
  EXPECT_GT(changed, 640 * 480 / 50);
}

TEST(VtkScene, PosesChangeOnlyActorMatricesNeverThePipelines) {
  std::unique_ptr<Scene> scene = MakeScene(Irb1600());
  ASSERT_TRUE(scene);
  scene->Render();
  std::vector<vtkMTimeType> before;
  vtkActorCollection* actors = scene->renderer()->GetActors();
  actors->InitTraversal();
  while (vtkActor* actor = actors->GetNextActor()) {
    before.push_back(actor->GetMapper()->GetInputAsDataSet()->GetMTime());
  }
  for (int i = 0; i < 5; ++i) {
    scene->SetJointValues(std::vector<double>(6, 0.3 * i));
    scene->Render();
  }
  actors->InitTraversal();
  size_t i = 0;
  while (vtkActor* actor = actors->GetNextActor()) {
    EXPECT_EQ(actor->GetMapper()->GetInputAsDataSet()->GetMTime(), before[i++]);
  }
}

TEST(VtkScene, ProbesFromAnotherThreadWhileRendering) {
  std::unique_ptr<Scene> scene = MakeScene(Irb1600());
  ASSERT_TRUE(scene);
  std::atomic<bool> done{false};
  std::atomic<int> bad{0};
  std::thread network([&] {
    std::vector<ProbeReport> reports;
    for (int i = 0; i < 20000; ++i) {
      const double t = i * 1e-3;
      const std::vector<double> q{std::sin(t), 0.5 * std::sin(t), 0.2, 0.1, 0.3, t};
      scene->SetJointValues(q);
      scene->ProbeReports(&reports);
      if (reports.size() != 1 || reports[0].frame != "IRB1600" || reports[0].name != "Tcp" ||
          !reports[0].position_m.allFinite()) {
        ++bad;
      }
    }
    done = true;
  });
  int frames = 0;
  while (!done) {
    scene->Render();
    ++frames;
  }
  network.join();
  EXPECT_EQ(bad, 0);
  EXPECT_GT(frames, 0);
  EXPECT_EQ(scene->pose_version(), 20001u);
  EXPECT_THROW(scene->SetJointValues(std::vector<double>(5, 0.0)), InputError);
}

TEST(VtkScene, SnapshotsArePngFilesAndBytes) {
  std::unique_ptr<Scene> scene = MakeScene(Irb1600());
  ASSERT_TRUE(scene);
  const std::string bytes = scene->SnapshotPngBytes();
  ASSERT_GT(bytes.size(), 1000u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "mbstream_vtk_scene_test.png";
  scene->SnapshotPng(path);
  EXPECT_GT(std::filesystem::file_size(path), 1000u);
  std::filesystem::remove(path);
  EXPECT_THROW(scene->SnapshotPng("/nonexistent/dir/x.png"), SceneError);
}

TEST(VtkScene, UrdfVisualsRender) {
  std::unique_ptr<Scene> scene =
      MakeScene(SceneFromUrdfFile(ss::testing::SourcePath("models/irb1600/irb1600.urdf")));
  ASSERT_TRUE(scene);
  const RgbImage background = Background(*scene);
  const std::vector<bool> mask = RobotMask(scene->Capture(), background);
  EXPECT_GT(std::count(mask.begin(), mask.end(), true), 640 * 480 / 50);
  ASSERT_EQ(scene->ProbeReports().size(), 1u);
  EXPECT_LT((scene->ProbeReports()[0].position_m - Vector3d(0.815, 0, 0.9615)).norm(), 1e-12);
}

TEST(VtkScene, WedgeModuleIsAClosedSolidOfTheRightVolume) {
  const ss::Translation translation = ss::TranslateScript(R"(Module Wedge Points
    0 0.0 0.0 0.0  1 50.0 15.0 0.0  2 50.0 75.0 0.0  3 0.0 75.0 0.0
    4 50.0 15.0 15.0  5 50.0 75.0 15.0  6 0.0 75.0 20.0  7 0.0 0.0 20.0
    Polygons (0 1 2 3) (1 2 5 4)(2 3 6 5) (3 6 7 0) (7, 4, 1, 0)(4 5 6 7);
    Render Wedge color 1 1 1;)");
  ASSERT_TRUE(translation.ok());
  const SceneDescription scene = SceneFromScript(translation.script);
  ASSERT_EQ(scene.visuals.size(), 1u);
  vtkNew<vtkMassProperties> mass;
  mass->SetInputData(VisualSurface(scene.visuals[0]));
  mass->Update();
  // Base area 3375 mm^2 under the plane z = 20 - x/10: 59375 mm^3.
  EXPECT_NEAR(mass->GetVolume(), 59375e-9, 1e-12);
}

TEST(VtkScene, AnUnreadableStlFileIsASceneError) {
  VisualPart part;
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "mbstream_empty.stl";
  { std::ofstream(path) << "solid nothing\nendsolid nothing\n"; }
  part.geometry = MeshFile{path};
  EXPECT_THROW(MakeVisualActors(part), SceneError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace mbstream::viewer
