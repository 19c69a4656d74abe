// The viewer draws every model of a world from its mesh files (issue 43, docs/worlds.md,
// "Meshes of included models"): tests/data/worlds/mesh_world/ includes post/ (welded, an arm
// on a hinge; STL named relative to its model.sdf and as model://post/...), crate/ (a free
// body; OBJ, relative) and shelf/ (static; Collada in its own colour). Each model's actors
// stand where its pose says, follow its joints, and show in the snapshot in its colour; a
// mesh that is missing or unreadable is named. Under a private Xvfb.
#include <gtest/gtest.h>
#include <unistd.h>

#include <vtkActor.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include "tests/viewer/xvfb_display.h"
#include "viewer/model/model_scene.h"
#include "viewer/scene/scene.h"

namespace mbstream::viewer {
namespace {

namespace fs = std::filesystem;
using Eigen::AlignedBox3d;
using Eigen::Vector3d;

const char kWorld[] = MBSTREAM_SOURCE_DIR "/tests/data/worlds/mesh_world/world.sdf";

// The model part of a scoped name: "crate" of "crate::body".
std::string ModelOf(const std::string& name) { return name.substr(0, name.find("::")); }

SceneOptions Offscreen() {
  SceneOptions options;
  options.width = 640;
  options.height = 480;
  options.offscreen = true;
  return options;
}

// The world bounds of every actor of each model (its actors' frames named MODEL::...).
std::map<std::string, AlignedBox3d> ModelBounds(const Scene& scene,
                                                const SceneDescription& description) {
  std::map<std::string, AlignedBox3d> bounds;
  for (int k = 0; k < scene.part_actor_count(); ++k) {
    double b[6];
    scene.part_actors()[k]->GetBounds(b);
    const std::string model = ModelOf(description.frame_names.at(scene.part_frames()[k]));
    auto [it, added] = bounds.try_emplace(model, Vector3d(b[0], b[2], b[4]));
    it->second.extend(Vector3d(b[0], b[2], b[4]));
    it->second.extend(Vector3d(b[1], b[3], b[5]));
  }
  return bounds;
}

void ExpectBox(const AlignedBox3d& box, const Vector3d& low, const Vector3d& high,
               const std::string& what) {
  EXPECT_LT((box.min() - low).norm(), 1e-6) << what << " min " << box.min().transpose();
  EXPECT_LT((box.max() - high).norm(), 1e-6) << what << " max " << box.max().transpose();
}

TEST(MeshWorld, EveryIncludedModelsMeshIsFoundRelativeToItsFolderOrByModelUri) {
  const SceneDescription scene = SceneFromModelFile(kWorld);
  EXPECT_EQ(scene.title, "mesh_world");
  EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  std::map<std::string, std::string> meshes;  // link -> mesh URI
  for (const VisualPart& part : scene.visuals) {
    EXPECT_FALSE(part.placeholder) << part.name;
    EXPECT_TRUE(std::holds_alternative<MeshFile>(part.geometry)) << part.name;
    meshes[part.name] = part.mesh_filename;
  }
  // A path relative to the included model's file is named as model://NAME/... (found as its
  // <include> was); a model:// URI stays as written.
  EXPECT_EQ(meshes, (std::map<std::string, std::string>{
                        {"post::base", "model://post/meshes/unit_cube.stl"},
                        {"post::arm", "model://post/meshes/unit_cube.stl"},
                        {"crate::body", "model://crate/meshes/two_cubes.obj"},
                        {"shelf::block", "model://shelf/meshes/shelf.dae"}}));
}

TEST(MeshWorld, EachModelsMeshStandsWhereItsPoseSaysAndTheSnapshotShowsItsColour) {
  const SceneDescription description = SceneFromModelFile(kWorld);
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, Offscreen());
  EXPECT_EQ(scene.missing_meshes_line(), "");
  ASSERT_EQ(description.chain.dof(), 1 + 7);  // the hinge, then the crate's free joint
  std::vector<double> q = description.initial_q;
  scene.SetJointValues(q);
  scene.SyncActors();
  std::map<std::string, AlignedBox3d> bounds = ModelBounds(scene, description);
  ASSERT_EQ(bounds.size(), 3u);
  // The post: a 0.2 x 0.2 x 0.6 column (the unit cube scaled) and a 0.4 m arm along x at
  // 0.65 m. The shelf: its 0.3 x 0.4 x 0.5 block at (-0.6, 0.3, 0).
  ExpectBox(bounds.at("post"), Vector3d(-0.1, -0.1, 0), Vector3d(0.4, 0.1, 0.69), "post");
  ExpectBox(bounds.at("shelf"), Vector3d(-0.75, 0.1, 0), Vector3d(-0.45, 0.5, 0.5), "shelf");
  // The crate: two cubes spanning 0.3 x 0.1 x 0.1, turned 0.5 rad about z at (0.6, 0, 0.5).
  const double c = std::cos(0.5), s = std::sin(0.5);
  const Vector3d half(0.15 * c + 0.05 * s, 0.15 * s + 0.05 * c, 0.05);
  ExpectBox(bounds.at("crate"), Vector3d(0.6, 0, 0.5) - half, Vector3d(0.6, 0, 0.5) + half,
            "crate");

  // The hinge a quarter turn: the arm along y. The crate's free joint: 0.3 m lower, unturned
  // (x y z qw qx qy qz).
  q[0] = M_PI / 2;
  const std::vector<double> crate = {0.6, 0, 0.2, 1, 0, 0, 0};
  std::copy(crate.begin(), crate.end(), q.begin() + 1);
  scene.SetJointValues(q);
  scene.SyncActors();
  bounds = ModelBounds(scene, description);
  ExpectBox(bounds.at("post"), Vector3d(-0.1, -0.1, 0), Vector3d(0.1, 0.4, 0.69), "post turned");
  ExpectBox(bounds.at("crate"), Vector3d(0.45, -0.05, 0.15), Vector3d(0.75, 0.05, 0.25),
            "crate moved");
  ExpectBox(bounds.at("shelf"), Vector3d(-0.75, 0.1, 0), Vector3d(-0.45, 0.5, 0.5), "shelf");

  // The snapshot: the post's red, the crate's green and the shelf's blue (its Collada
  // file's own), each over the background.
  std::vector<vtkActor*> actors;
  vtkActorCollection* collection = scene.renderer()->GetActors();
  collection->InitTraversal();
  while (vtkActor* actor = collection->GetNextActor()) actors.push_back(actor);
  for (vtkActor* actor : actors) actor->VisibilityOff();
  const RgbImage background = scene.Capture();
  for (vtkActor* actor : actors) actor->VisibilityOn();
  const RgbImage image = scene.Capture();
  int red = 0, green = 0, blue = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      int d = 0;
      for (int k = 0; k < 3; ++k) {
        d = std::max(d, std::abs(int(image.At(x, y)[k]) - int(background.At(x, y)[k])));
      }
      if (d <= 12) continue;
      const int r = image.At(x, y)[0], g = image.At(x, y)[1], b = image.At(x, y)[2];
      if (r > g + 60 && r > b + 60) ++red;
      if (g > r + 60 && g > b + 60) ++green;
      if (b > r + 60 && b > g + 30) ++blue;
    }
  }
  EXPECT_GT(red, 200) << "no post in the picture";
  EXPECT_GT(green, 50) << "no crate in the picture";
  EXPECT_GT(blue, 200) << "no shelf in the picture";
}

// A copy of the world whose crate mesh is gone and whose shelf mesh is not a mesh: the crate
// is a placeholder with a warning naming its model file and line and the mesh; the shelf's
// unreadable file (its path and reader's error logged) falls back to a placeholder; both are
// named on the HUD line.
TEST(MeshWorld, AMissingOrUnreadableMeshIsNamed) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream_mesh_world_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::copy(fs::path(kWorld).parent_path(), dir, fs::copy_options::recursive);
  fs::remove(dir / "crate/meshes/two_cubes.obj");
  std::ofstream(dir / "shelf/meshes/shelf.dae", std::ios::trunc) << "not Collada\n";
  const SceneDescription description = SceneFromModelFile((dir / "world.sdf").string());
  ASSERT_EQ(description.warnings.size(), 1u);
  const std::string& warning = description.warnings[0];
  EXPECT_EQ(warning.rfind((dir / "crate/model.sdf").string() +
                              ":11: link 'crate::body': mesh "
                              "'model://crate/meshes/two_cubes.obj' is not found",
                          0),
            0u)
      << warning;
  ASSERT_TRUE(testing::EnsureDisplay()) << "no X display and Xvfb could not be started";
  Scene scene(description, Offscreen());
  EXPECT_EQ(scene.missing_meshes_line(), "2 meshes missing: two_cubes.obj, shelf.dae (unreadable)");
  EXPECT_EQ(scene.part_actor_count(), 4);  // the placeholders stand in for the two meshes
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::viewer
