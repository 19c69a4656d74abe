// The scene of a run follows the model the server sends: a URDF scene's joint values are
// ordered by the model's joint names, and a scene whose names differ is refused.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "shared/common/check.h"
#include "tests/viewer/script_test_util.h"
#include "viewer/link/run_scene.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream::viewer {
namespace {

std::string TreeUrdf() {
  std::ifstream in(
      scene_script::testing::SourcePath("tests/model_files/data/tree_child_first.urdf"));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

v1::ModelInfo ModelWithJoints(const std::vector<std::string>& names) {
  v1::ModelInfo model;
  model.set_id("m-test");
  model.set_name("tree");
  model.set_dofs(static_cast<int>(names.size()));
  for (const std::string& name : names) model.add_joints()->set_name(name);
  return model;
}

// The frame of link `link` for joint values `q`.
Eigen::Isometry3d Frame(const SceneDescription& scene, const std::vector<double>& q,
                        const std::string& link) {
  std::vector<Eigen::Isometry3d> frames(scene.chain.frame_count());
  scene.chain.Compute(q, frames);
  const auto it = std::find(scene.frame_names.begin(), scene.frame_names.end(), link);
  return frames.at(it - scene.frame_names.begin());
}

TEST(RunScene, UrdfJointValuesFollowTheModelsJointNames) {
  v1::ModelBundle bundle;
  bundle.set_urdf(TreeUrdf());
  RunSceneSource source;
  source.asset_root = std::filesystem::temp_directory_path() / "mbstream_run_scene_test";
  // The server's order for this tree.
  const SceneDescription same =
      SceneForModel(ModelWithJoints({"ja", "jc", "jb", "jd"}), bundle, source);
  // Another order: q[k] still moves the joint the model names k-th.
  const SceneDescription other =
      SceneForModel(ModelWithJoints({"jd", "jc", "jb", "ja"}), bundle, source);
  const std::vector<double> q_same = {0.1, 0.2, 0.3, 0.04};
  const std::vector<double> q_other = {0.04, 0.2, 0.3, 0.1};
  for (const char* link : {"a", "b", "c", "d"}) {
    EXPECT_TRUE(Frame(same, q_same, link).isApprox(Frame(other, q_other, link), 1e-12)) << link;
  }
  // jd is prismatic along z from b's frame: 0.04 m.
  EXPECT_NEAR(
      (Frame(other, q_other, "d").translation() - Frame(other, q_other, "b").translation()).z(),
      0.34, 1e-12);
}

TEST(RunScene, AUrdfSceneWhoseJointNamesDifferIsRefused) {
  v1::ModelBundle bundle;
  bundle.set_urdf(TreeUrdf());
  RunSceneSource source;
  source.asset_root = std::filesystem::temp_directory_path() / "mbstream_run_scene_test";
  try {
    SceneForModel(ModelWithJoints({"ja", "jc", "jb", "j4"}), bundle, source);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "scene 'tree' does not fit model 'tree' (m-test): the joint names differ: the "
                 "model's 'j4' not in the scene; the scene's 'jd' not in the model; use the "
                 "model's own URDF or a scene with its joints");
  }
  EXPECT_THROW(SceneForModel(ModelWithJoints({"ja", "jc", "jb"}), bundle, source),
               InputError);  // the count differs
}

}  // namespace
}  // namespace mbstream::viewer
