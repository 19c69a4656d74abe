// The server's importer and the viewer read every URDF in the repository the same way:
// the same moving joints in the same order (the order of q on the wire), the same TCP link,
// and the same answer to "is this mesh there" (a file beside the URDF, or a bundle asset).
// This test links both sides: server/parse and viewer/model.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "server/parse/urdf_import.h"
#include "server/parse/urdf_meshes.h"
#include "server/parse/urdf_xml_scan.h"
#include "shared/model_files/joint_order.h"
#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/mesh_lookup.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> RepositoryUrdfs() {
  std::vector<fs::path> files;
  for (const char* top : {"models", "tests"}) {
    for (const auto& entry :
         fs::recursive_directory_iterator(fs::path(MBSTREAM_SOURCE_DIR) / top)) {
      if (entry.is_regular_file() && entry.path().extension() == ".urdf") {
        files.push_back(entry.path());
      }
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(UrdfAgreement, TheRepositoryHasTheTestUrdfs) {
  const std::vector<fs::path> files = RepositoryUrdfs();
  std::set<std::string> names;
  for (const fs::path& file : files) names.insert(file.filename().string());
  for (const char* expected :
       {"irb1600.urdf", "tree_child_first.urdf", "tcp_fixed_leaf.urdf", "demo.urdf"}) {
    EXPECT_EQ(names.count(expected), 1u) << expected;
  }
}

TEST(UrdfAgreement, JointOrderTcpAndMeshesOfEveryUrdf) {
  for (const fs::path& path : RepositoryUrdfs()) {
    SCOPED_TRACE(path.string());
    const std::string text = Read(path);
    std::vector<std::string> ignored;
    const UrdfXmlFacts facts = ScanUrdfXml(text, path.string(), &ignored);
    // The server: every mesh counts as supplied here (its lookup is compared below).
    const std::set<std::string> all(facts.mesh_files.begin(), facts.mesh_files.end());
    const Model model = ImportUrdf(text, path.string(), all).model;
    const viewer::SceneDescription scene = viewer::SceneFromUrdfFile(path);

    std::vector<std::string> server_joints, viewer_joints;
    for (const auto& body : model.bodies) server_joints.push_back(body.joint.name);
    for (int i = 0; i < scene.chain.dof(); ++i)
      viewer_joints.push_back(scene.chain.dof_joint(i).name);
    EXPECT_EQ(viewer_joints, server_joints);

    const std::string server_tcp =
        model.tcp_frame >= 0 && model.tcp_frame < int(model.frames.size())
            ? model.frames[model.tcp_frame].name
            : "";
    const std::string viewer_tcp =
        scene.probes.empty() ? "" : scene.frame_names.at(scene.probes[0].frame);
    EXPECT_EQ(viewer_tcp, server_tcp);

    // Mesh files on disk: the server's "exists" is the viewer's "drawn from a file", both
    // found as `mbstream submit` finds them.
    const std::set<std::string> server_found =
        ExistingMeshFiles(facts.mesh_files, path.parent_path());
    for (const viewer::VisualPart& part : scene.visuals) {
      if (part.mesh_filename.empty()) continue;
      const bool drawn = std::holds_alternative<viewer::MeshFile>(part.geometry);
      EXPECT_EQ(drawn, server_found.count(part.mesh_filename) == 1) << part.mesh_filename;
      if (drawn) {  // the file `mbstream submit` attaches
        EXPECT_EQ(
            std::get<viewer::MeshFile>(part.geometry).path,
            model_files::MeshFileSearch(path.parent_path(), {}).Find(part.mesh_filename).found);
      }
    }
  }
}

TEST(UrdfAgreement, TreeListingAChildJointFirst) {
  const viewer::SceneDescription scene = viewer::SceneFromUrdfFile(
      fs::path(MBSTREAM_SOURCE_DIR) / "tests/model_files/data/tree_child_first.urdf");
  std::vector<std::string> names;
  for (int i = 0; i < scene.chain.dof(); ++i) names.push_back(scene.chain.dof_joint(i).name);
  EXPECT_EQ(names, (std::vector<std::string>{"ja", "jc", "jb", "jd"}));
}

TEST(UrdfAgreement, BundleAssetsUnderEveryNameTheServerAccepts) {
  // For each name an asset may carry, the server says "supplied" exactly when the viewer,
  // having written the bundle's assets under their names, finds the file.
  const std::string filename = "package://demo_description/meshes/visual/link0.stl";
  const std::vector<std::string> asset_names = {filename,
                                                "demo_description/meshes/visual/link0.stl",
                                                "meshes/visual/link0.stl",
                                                "link0.stl",
                                                "meshes/link0.stl",
                                                "other/link0.stl",
                                                "visual/link0.stl"};
  for (const std::string& name : asset_names) {
    SCOPED_TRACE(name);
    if (name.find("://") != std::string::npos)
      continue;  // not a relative path: the viewer refuses it
    const fs::path dir =
        fs::temp_directory_path() / ("mbstream_agreement_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories((dir / name).parent_path());
    std::ofstream(dir / name) << "solid x\nendsolid x\n";
    const bool server = MeshSupplied(filename, {name});
    const bool viewer = !model_files::FindMeshFile(filename, dir).empty();
    EXPECT_EQ(viewer, server);
    fs::remove_all(dir);
  }
  EXPECT_TRUE(MeshSupplied(filename, {"meshes/visual/link0.stl"}));
  EXPECT_FALSE(MeshSupplied(filename, {"meshes/collision/link0.stl"}));
}

}  // namespace
}  // namespace mbstream
