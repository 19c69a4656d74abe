// ReadModelBundle on small robot description folders written by the tests: package://
// meshes found through package.xml, folder names, the URDF's ancestors and the package
// path; assets named by the path the URDF writes; collision meshes on request; .xacro.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "server/wire/model_bundle_files.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;
using ::testing::Pair;
using ::testing::UnorderedElementsAre;

// Two moving links; base_link's visual and collision meshes share the base name link0.stl;
// link1's visual is written twice (stored once) and as a path relative to the URDF.
std::string DemoUrdf(const std::string& package) {
  const std::string p = "package://" + package + "/meshes/";
  return R"(<?xml version="1.0"?>
<robot name="demo">
  <link name="base_link">
    <visual><geometry><mesh filename=")" +
         p + R"(visual/link0.stl"/></geometry></visual>
    <collision><geometry><mesh filename=")" +
         p + R"(collision/link0.stl"/></geometry></collision>
  </link>
  <link name="link1"><inertial><mass value="1"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="../meshes/visual/link1.stl"/></geometry></visual>
    <visual><geometry><mesh filename="../meshes/visual/link1.stl"/></geometry></visual>
  </link>
  <joint name="j1" type="revolute"><parent link="base_link"/><child link="link1"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>
)";
}

class ModelBundleFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream_bundle_files_" +
            std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    unsetenv("MBSTREAM_PACKAGE_PATH");
  }
  void TearDown() override {
    unsetenv("MBSTREAM_PACKAGE_PATH");
    fs::remove_all(dir_);
  }
  fs::path Write(const fs::path& relative, const std::string& text) {
    const fs::path path = dir_ / relative;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  // A description folder `folder` (package.xml naming `package` unless empty) with the
  // demo URDF in urdf/ and its three meshes, each holding its own path as its bytes.
  fs::path WriteDescription(const std::string& folder, const std::string& package) {
    if (!package.empty()) {
      Write(folder + "/package.xml", "<?xml version=\"1.0\"?>\n<package format=\"3\">\n  <name>" +
                                         package +
                                         "</name>\n  <version>0.0.1</version>\n</package>\n");
    }
    for (const char* mesh :
         {"meshes/visual/link0.stl", "meshes/collision/link0.stl", "meshes/visual/link1.stl"}) {
      Write(folder + "/" + mesh, std::string("solid ") + mesh + "\nendsolid\n");
    }
    return Write(folder + "/urdf/demo.urdf", DemoUrdf("demo_description"));
  }
  static std::map<std::string, std::string> Assets(const v1::ModelBundle& bundle) {
    std::map<std::string, std::string> assets;
    for (const v1::Asset& asset : bundle.assets()) assets[asset.name()] = asset.data();
    return assets;
  }

  fs::path dir_;
};

TEST_F(ModelBundleFilesTest, DescriptionFolderAttachesItsVisualMeshesUnderTheirUrdfPaths) {
  WriteDescription("demo_description", "demo_description");
  BundleFiles files;
  files.model_path = (dir_ / "demo_description").string();  // the URDF is in urdf/
  const BundleRead read = ReadModelBundle(files);
  EXPECT_THAT(read.warnings, IsEmpty());
  EXPECT_EQ(read.bundle.urdf_file_name(), (dir_ / "demo_description/urdf/demo.urdf").string());
  EXPECT_THAT(Assets(read.bundle),
              UnorderedElementsAre(
                  Pair("demo_description/meshes/visual/link0.stl",
                       HasSubstr("solid meshes/visual/link0.stl")),
                  Pair("meshes/visual/link1.stl", HasSubstr("solid meshes/visual/link1.stl"))));

  files.with_collision = true;
  EXPECT_THAT(Assets(ReadModelBundle(files).bundle),
              UnorderedElementsAre(
                  Pair("demo_description/meshes/visual/link0.stl",
                       HasSubstr("solid meshes/visual/link0.stl")),
                  Pair("demo_description/meshes/collision/link0.stl",
                       HasSubstr("solid meshes/collision/link0.stl")),
                  Pair("meshes/visual/link1.stl", HasSubstr("solid meshes/visual/link1.stl"))));
}

TEST_F(ModelBundleFilesTest, RenamedPackageFolderIsFoundFromTheUrdfsAncestors) {
  const fs::path urdf = WriteDescription("ws/src/my_robot_v2", "");
  BundleFiles files;
  files.model_path = urdf.string();
  const BundleRead read = ReadModelBundle(files);
  EXPECT_THAT(read.warnings, IsEmpty());
  EXPECT_EQ(read.bundle.assets_size(), 2);
  EXPECT_EQ(Assets(read.bundle).count("demo_description/meshes/visual/link0.stl"), 1u);
}

TEST_F(ModelBundleFilesTest, PackagePathFindsAPackageByItsPackageXmlOrByItsFolderName) {
  WriteDescription("ws/src/renamed", "demo_description");
  // The URDF elsewhere (a generated one), so only the package path can find the meshes.
  const fs::path urdf = Write("elsewhere/demo.urdf", DemoUrdf("demo_description"));
  BundleFiles files;
  files.model_path = urdf.string();
  BundleRead read = ReadModelBundle(files);
  EXPECT_EQ(Assets(read.bundle).count("demo_description/meshes/visual/link0.stl"), 0u);
  ASSERT_EQ(read.warnings.size(), 2u);  // link0 not found, link1 not found
  EXPECT_THAT(
      read.warnings[0],
      AllOf(HasSubstr("visual mesh 'package://demo_description/meshes/visual/link0.stl' "
                      "was not found; tried "),
            HasSubstr((dir_ / "elsewhere/meshes/visual/link0.stl").string()),
            HasSubstr((dir_ / "meshes/visual/link0.stl").string()), HasSubstr("--package-path")));

  files.package_paths = {(dir_ / "ws").string()};  // found by its package.xml
  read = ReadModelBundle(files);
  EXPECT_THAT(Assets(read.bundle),
              ::testing::Contains(Pair("demo_description/meshes/visual/link0.stl",
                                       HasSubstr("solid meshes/visual/link0.stl"))));

  // By folder name, through MBSTREAM_PACKAGE_PATH (colon separated, empty entries skipped).
  WriteDescription("pkgs/demo_description", "");
  files.package_paths.clear();
  setenv("MBSTREAM_PACKAGE_PATH", ("::/nonexistent:" + (dir_ / "pkgs").string()).c_str(), 1);
  read = ReadModelBundle(files);
  EXPECT_EQ(Assets(read.bundle).count("demo_description/meshes/visual/link0.stl"), 1u);
}

TEST_F(ModelBundleFilesTest, NotFoundMeshNamesEveryPlaceTried) {
  const fs::path urdf = Write("robot/urdf/demo.urdf", DemoUrdf("nowhere"));
  BundleFiles files;
  files.model_path = urdf.string();
  files.package_paths = {(dir_ / "robot").string()};
  const BundleRead read = ReadModelBundle(files);
  ASSERT_FALSE(read.warnings.empty());
  EXPECT_THAT(read.warnings[0],
              AllOf(HasSubstr("'package://nowhere/meshes/visual/link0.stl' was not found"),
                    HasSubstr((dir_ / "robot/urdf/meshes/visual/link0.stl").string()),
                    HasSubstr((dir_ / "robot/meshes/visual/link0.stl").string()),
                    HasSubstr("no package 'nowhere' (a package.xml naming it, or a folder of "
                              "that name) below " +
                              (dir_ / "robot").string()),
                    HasSubstr("(the model is sent without it)")));
}

TEST_F(ModelBundleFilesTest, XacroIsRefusedWithTheCommandThatExpandsIt) {
  const fs::path xacro = Write("robot/urdf/model.urdf.xacro", "<robot/>");
  BundleFiles files;
  files.model_path = xacro.string();
  try {
    ReadModelBundle(files);
    ADD_FAILURE() << "a .xacro was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("xacro " + xacro.string() + " > model.urdf"));
  }
  files.model_path = (dir_ / "robot").string();  // a folder with no URDF but the xacro
  try {
    ReadModelBundle(files);
    ADD_FAILURE() << "a folder holding only a .xacro was read";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("> model.urdf"));
  }
}

TEST_F(ModelBundleFilesTest, AMeshCarriesItsMaterialsAndImagesBesideIt) {
  Write("r/meshes/cube.obj", "mtllib cube.mtl\nusemtl skin\nv 0 0 0\n");
  Write("r/meshes/cube.mtl",
        "newmtl skin\nmap_Kd ../textures/skin.png\nmap_Ks C:\\Users\\me\\shine.png\n"
        "map_bump gone.png\nmap_d ../../../outside.png\n");
  Write("r/textures/skin.png", "skin");
  Write("r/meshes/shine.png", "shine");  // named by a path of the author's machine
  Write("outside.png", "outside");       // would leave the bundle
  Write("r/meshes/part.dae",
        "<COLLADA><library_images><image><init_from>../textures/skin.png</init_from></image>"
        "</library_images></COLLADA>");
  Write("r/spare.png", "not named by any mesh");
  const fs::path urdf = Write("r/robot.urdf", R"(<robot name="r"><link name="a">
    <visual><geometry><mesh filename="meshes/cube.obj"/></geometry></visual>
    <visual><geometry><mesh filename="package://r/meshes/part.dae"/></geometry></visual>
  </link></robot>)");
  BundleFiles files;
  files.model_path = urdf.string();
  const BundleRead read = ReadModelBundle(files);
  EXPECT_THAT(
      Assets(read.bundle),
      UnorderedElementsAre(Pair("meshes/cube.obj", HasSubstr("mtllib")),
                           Pair("meshes/cube.mtl", HasSubstr("newmtl")),
                           Pair("textures/skin.png", "skin"), Pair("meshes/shine.png", "shine"),
                           Pair("r/meshes/part.dae", HasSubstr("COLLADA")),
                           Pair("r/textures/skin.png", "skin")));
  EXPECT_THAT(read.warnings,
              ElementsAre(HasSubstr("names 'gone.png', which is not in"),
                          HasSubstr("names '../../../outside.png', which is not in")));
}

}  // namespace
}  // namespace mbstream
