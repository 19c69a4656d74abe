// The URDF importer on the shipped models and on small mechanisms: structure, frames,
// limits, inertias, the TCP rule and mesh look-up.
#include "server/parse/urdf_import.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include "server/dynamics/aba.h"
#include "server/kinematics/forward_kinematics.h"
#include "tests/server/parse/urdf_test_util.h"

namespace mbstream {
namespace {

using std::numbers::pi;
using testing::InertialXml;
using ::testing::IsEmpty;
using testing::JointXml;
using testing::LinkXml;
using testing::OneJoint;
using testing::Robot;

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string ModelPath(const std::string& relative) {
  return std::string(MBSTREAM_SOURCE_DIR) + "/models/" + relative;
}

double Deg(double degrees) { return degrees * pi / 180.0; }

TEST(UrdfImportTest, Irb1600ImportsItsSixJointsAndTcp) {
  const UrdfImport imported = ImportUrdfFile(ModelPath("irb1600/irb1600.urdf"));
  EXPECT_THAT(imported.warnings, IsEmpty());
  const Model& model = imported.model;
  EXPECT_EQ(model.name, "irb1600");
  EXPECT_EQ(model.base_name, "base_link");
  ASSERT_EQ(model.num_dofs(), 6);

  const Vector3d X = Vector3d::UnitX(), Y = Vector3d::UnitY(), Z = Vector3d::UnitZ();
  const Vector3d axes[6] = {Z, Y, Y, X, Y, X};
  const Vector3d origins[6] = {{0, 0, 0},     {0.150, 0, 0.4865}, {0, 0, 0.475},
                               {0.600, 0, 0}, {0, 0, 0},          {0, 0, 0}};
  const double lower[6] = {-180, -63, -235, -190, -115, -288};
  const double upper[6] = {180, 136, 55, 190, 115, 288};
  for (int i = 0; i < 6; ++i) {
    SCOPED_TRACE(i);
    const Body& body = model.bodies[i];
    EXPECT_EQ(body.name, "link" + std::to_string(i + 1));
    EXPECT_EQ(body.parent, i - 1);
    EXPECT_EQ(body.joint.name, "joint" + std::to_string(i + 1));
    EXPECT_EQ(body.joint.type, JointType::kRevolute);
    EXPECT_EQ(body.joint.axis, axes[i]);
    EXPECT_LT((body.joint.X_PJ.p - origins[i]).norm(), 1e-15);
    EXPECT_EQ(body.joint.X_PJ.R, Matrix3d::Identity());  // exactly: fast paths rely on it
    EXPECT_NEAR(body.joint.limits.lower, Deg(lower[i]), 1e-14);
    EXPECT_NEAR(body.joint.limits.upper, Deg(upper[i]), 1e-14);
    EXPECT_GT(body.joint.limits.velocity, 0.0);
    EXPECT_LT(body.joint.limits.velocity, 10.0);
    EXPECT_GT(body.joint.limits.effort, 0.0);
    EXPECT_LT(body.joint.limits.effort, 2000.0);
    EXPECT_EQ(body.joint.damping, 0.0);
    EXPECT_EQ(body.joint.armature, 0.0);
  }
  EXPECT_NEAR(model.bodies[0].joint.limits.velocity, Deg(150), 1e-14);
  EXPECT_NEAR(model.bodies[5].joint.limits.velocity, Deg(460), 1e-14);

  ASSERT_GE(model.tcp_frame, 0);
  const Frame& tcp = model.frames[model.tcp_frame];
  EXPECT_EQ(tcp.name, "tcp");
  EXPECT_EQ(tcp.body, model.FindBody("link6"));
  EXPECT_LT((tcp.X_BF.p - Vector3d(0.065, 0, 0)).norm(), 1e-15);
  EXPECT_NEAR(model.TotalMass(), 250.0, 1e-9);
}

TEST(UrdfImportTest, Irb1600TcpMatchesTheSeed) {
  const Model model = ImportUrdfFile(ModelPath("irb1600/irb1600.urdf")).model;
  Data data(model);
  ForwardKinematics(model, data, Eigen::VectorXd::Zero(6));
  EXPECT_LT((FramePosition(data, model.tcp_frame) - Vector3d(0.815, 0, 0.9615)).norm(), 1e-12);
  Eigen::VectorXd q(6);
  q << pi, pi / 3, pi / 4, pi, 0.6 * pi, pi;
  ForwardKinematics(model, data, q);
  const Vector3d p = FramePosition(data, model.tcp_frame);
  EXPECT_NEAR(p.x(), -0.470981559, 5e-10);
  EXPECT_NEAR(p.y(), 0.0, 1e-12);
  EXPECT_NEAR(p.z(), 0.147846341, 5e-10);
}

TEST(UrdfImportTest, SinglePendulumFollowsItsClosedForm) {
  const UrdfImport imported = ImportUrdfFile(ModelPath("pendulum/single_pendulum.urdf"));
  EXPECT_THAT(imported.warnings, IsEmpty());
  const Model& model = imported.model;
  ASSERT_EQ(model.num_dofs(), 1);
  const Body& bob = model.bodies[0];
  EXPECT_EQ(bob.joint.axis, Vector3d::UnitY());
  EXPECT_EQ(bob.joint.limits.lower, -kInf);
  EXPECT_EQ(bob.joint.limits.upper, kInf);
  EXPECT_EQ(bob.inertia.mass, 1.0);
  EXPECT_EQ(bob.inertia.com, Vector3d(0, 0, -1));
  ASSERT_GE(model.tcp_frame, 0);
  EXPECT_EQ(model.frames[model.tcp_frame].X_BF.p, Vector3d(0, 0, -1));

  // qdd = -m g l sin q / (I_cm + m l^2), the formula in the file's comment.
  Data data(model);
  for (const double angle : {0.3, 1.0, 2.5}) {
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, angle);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(1);
    EXPECT_NEAR(Aba(model, data, q, zero, zero)(0), -9.81 * std::sin(angle) / (1.0 + 1e-6), 1e-12);
  }
}

TEST(UrdfImportTest, DoublePendulumImportsTwoJointsInOrder) {
  const UrdfImport imported = ImportUrdfFile(ModelPath("pendulum/double_pendulum.urdf"));
  EXPECT_THAT(imported.warnings, IsEmpty());
  const Model& model = imported.model;
  ASSERT_EQ(model.num_dofs(), 2);
  EXPECT_EQ(model.bodies[1].parent, 0);
  EXPECT_EQ(model.bodies[1].joint.X_PJ.p, Vector3d(0, 0, -1));
  EXPECT_EQ(model.bodies[1].joint.axis, Vector3d::UnitY());
  EXPECT_DOUBLE_EQ(model.TotalMass(), 2.0);
  Data data(model);
  ForwardKinematics(model, data, Eigen::Vector2d(pi / 2, 0.0));
  // Rotating +pi/2 about y takes -z to -x.
  EXPECT_LT((FramePosition(data, model.tcp_frame) - Vector3d(-2, 0, 0)).norm(), 1e-12);
}

TEST(UrdfImportTest, FixedLinkMassIsMergedIntoItsBody) {
  const std::string text =
      Robot(LinkXml("link1") + JointXml("j1", "revolute", "base", "link1") + LinkXml("tool") +
            JointXml("fix", "fixed", "link1", "tool", R"(<origin xyz="1 0 0" rpy="0 0 0"/>)"));
  const Model model = ImportUrdf(text, "merge.urdf", {}).model;
  ASSERT_EQ(model.num_dofs(), 1);
  const RigidInertia& merged = model.bodies[0].inertia;
  EXPECT_DOUBLE_EQ(merged.mass, 2.0);
  EXPECT_DOUBLE_EQ(model.TotalMass(), 2.0);
  EXPECT_LT((merged.com - Vector3d(0.5, 0, 0)).norm(), 1e-15);
  // 0.1 each about its own centre, plus 1 kg * (0.5 m)^2 each about y and z.
  EXPECT_LT((merged.inertia_com - Vector3d(0.2, 0.7, 0.7).asDiagonal().toDenseMatrix())
                .cwiseAbs()
                .maxCoeff(),
            1e-15);
  const int tool = model.FindFrame("tool");
  ASSERT_GE(tool, 0);
  EXPECT_EQ(model.frames[tool].body, 0);
  EXPECT_EQ(model.frames[tool].X_BF.p, Vector3d(1, 0, 0));
  EXPECT_EQ(model.tcp_frame, tool);  // the fixed leaf on the last moving body
}

TEST(UrdfImportTest, RpyIsRzRyRx) {
  const double roll = 0.1, pitch = -0.7, yaw = 2.3;
  const std::string rpy =
      std::to_string(roll) + " " + std::to_string(pitch) + " " + std::to_string(yaw);
  const std::string origin = "<origin xyz=\"0.1 0.2 0.3\" rpy=\"" + rpy + "\"/>";
  const Model model = ImportUrdf(OneJoint(origin + testing::kAxisAndLimits), "rpy.urdf", {}).model;
  const Matrix3d expected =
      (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Vector3d::UnitX()))
          .toRotationMatrix();
  EXPECT_LT((model.bodies[0].joint.X_PJ.R - expected).norm(), 1e-14);
  EXPECT_LT((model.bodies[0].joint.X_PJ.p - Vector3d(0.1, 0.2, 0.3)).norm(), 1e-15);
}

TEST(UrdfImportTest, InertialOriginRotatesAndShiftsTheInertia) {
  // diag(1, 2, 3) about the centre of mass, turned by yaw = pi/2: x and y swap.
  const std::string inertial = InertialXml(
      "2", "1", "2", "3", "0", R"(<origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/>)");
  const Model model = ImportUrdf(OneJoint(testing::kAxisAndLimits, inertial), "i.urdf", {}).model;
  const RigidInertia& inertia = model.bodies[0].inertia;
  EXPECT_EQ(inertia.mass, 2.0);
  EXPECT_LT((inertia.com - Vector3d(0.1, 0.2, 0.3)).norm(), 1e-15);
  EXPECT_LT(
      (inertia.inertia_com - Vector3d(2, 1, 3).asDiagonal().toDenseMatrix()).cwiseAbs().maxCoeff(),
      1e-14);
}

TEST(UrdfImportTest, JointKindsDampingAndRotorInertia) {
  const std::string text = Robot(
      LinkXml("a") +
      JointXml(
          "spin", "continuous", "base", "a",
          R"(<axis xyz="0 1 0"/><dynamics damping="0.25"/><mbstream:rotor_inertia value="0.02"/>)") +
      LinkXml("b") +
      JointXml(
          "slide", "prismatic", "a", "b",
          R"(<axis xyz="1 0 0"/><limit lower="-0.1" upper="0.4" effort="300" velocity="0.5"/>)"));
  const UrdfImport imported = ImportUrdf(text, "kinds.urdf", {});
  EXPECT_THAT(imported.warnings, ::testing::Contains(::testing::HasSubstr("no TCP")));
  const Model& model = imported.model;
  ASSERT_EQ(model.num_dofs(), 2);
  const Joint& spin = model.bodies[0].joint;
  EXPECT_EQ(spin.type, JointType::kRevolute);
  EXPECT_EQ(spin.limits.lower, -kInf);
  EXPECT_EQ(spin.limits.upper, kInf);
  EXPECT_EQ(spin.limits.effort, kInf);
  EXPECT_EQ(spin.damping, 0.25);
  EXPECT_EQ(spin.armature, 0.02);
  const Joint& slide = model.bodies[1].joint;
  EXPECT_EQ(slide.type, JointType::kPrismatic);
  EXPECT_EQ(slide.axis, Vector3d::UnitX());
  EXPECT_EQ(slide.limits.lower, -0.1);
  EXPECT_EQ(slide.limits.upper, 0.4);
  EXPECT_EQ(slide.limits.effort, 300.0);
  EXPECT_EQ(slide.limits.velocity, 0.5);
  EXPECT_EQ(slide.damping, 0.0);
  EXPECT_EQ(slide.armature, 0.0);
}

TEST(UrdfImportTest, LinksAreAddedParentsFirstInDocumentOrder) {
  // A branching tree whose file lists a grandchild's joint before its parent's.
  const std::string text =
      Robot(LinkXml("a") + LinkXml("b") + LinkXml("c") + LinkXml("d") +
            JointXml("jc", "revolute", "a", "c") + JointXml("ja", "revolute", "base", "a") +
            JointXml("jb", "revolute", "base", "b") + JointXml("jd", "revolute", "b", "d"));
  const Model model = ImportUrdf(text, "tree.urdf", {}).model;
  ASSERT_EQ(model.num_dofs(), 4);
  EXPECT_EQ(model.bodies[0].joint.name, "ja");
  EXPECT_EQ(model.bodies[1].joint.name, "jc");
  EXPECT_EQ(model.bodies[2].joint.name, "jb");
  EXPECT_EQ(model.bodies[3].joint.name, "jd");
  EXPECT_EQ(model.bodies[1].parent, 0);
  EXPECT_EQ(model.bodies[3].parent, 2);
}

TEST(UrdfImportTest, TcpPrefersALinkNamedTcpThenTool0) {
  const std::string chain = LinkXml("link1") + JointXml("j1", "revolute", "base", "link1") +
                            LinkXml("flange", "") + JointXml("f", "fixed", "link1", "flange", "");
  const std::string tool0 = LinkXml("tool0", "") + JointXml("t0", "fixed", "link1", "tool0", "");
  const std::string tcp = LinkXml("TCP", "") + JointXml("t", "fixed", "base", "TCP", "");
  const Model fixed_leaf = ImportUrdf(Robot(chain), "t.urdf", {}).model;
  EXPECT_EQ(fixed_leaf.frames[fixed_leaf.tcp_frame].name, "flange");
  const Model with_tool0 = ImportUrdf(Robot(chain + tool0), "t.urdf", {}).model;
  EXPECT_EQ(with_tool0.frames[with_tool0.tcp_frame].name, "tool0");
  const Model with_tcp = ImportUrdf(Robot(chain + tool0 + tcp), "t.urdf", {}).model;
  EXPECT_EQ(with_tcp.frames[with_tcp.tcp_frame].name, "TCP");
}

TEST(UrdfImportTest, MeshesMatchByFileNameOrBaseName) {
  const std::string text = OneJoint(
      testing::kAxisAndLimits,
      testing::kInertial +
          R"(<visual><geometry><mesh filename="package://irb/meshes/link1.stl"/></geometry></visual>)" +
          R"(<collision><geometry><mesh filename="meshes/link1_c.stl"/></geometry></collision>)");
  EXPECT_NO_THROW(ImportUrdf(text, "m.urdf", {"link1.stl", "meshes/link1_c.stl"}));
  EXPECT_NO_THROW(ImportUrdf(text, "m.urdf", {"package://irb/meshes/link1.stl", "link1_c.stl"}));
}

TEST(UrdfImportTest, MissingMeshesAreWarningsCollisionOnesCountedOnce) {
  const std::string visual =
      R"(<visual><geometry><mesh filename="package://irb/meshes/link1.stl"/></geometry></visual>)";
  const std::string collision =
      R"(<collision><geometry><mesh filename="c/link1.dae"/></geometry></collision>)" +
      std::string(R"(<collision><geometry><mesh filename="c/link2.dae"/></geometry></collision>)");
  const UrdfImport import = ImportUrdf(
      OneJoint(testing::kAxisAndLimits, testing::kInertial + visual + collision), "m.urdf", {});
  EXPECT_EQ(import.model.num_dofs(), 1);
  EXPECT_THAT(import.warnings,
              ::testing::Contains(::testing::AllOf(
                  ::testing::HasSubstr("m.urdf:3: link 'link1'"),
                  ::testing::HasSubstr("visual mesh 'package://irb/meshes/link1.stl' is not "
                                       "supplied"),
                  ::testing::HasSubstr("placeholder"))));
  EXPECT_THAT(import.warnings, ::testing::Contains(::testing::AllOf(
                                   ::testing::HasSubstr("m.urdf: 2 collision mesh(es) not "
                                                        "supplied"),
                                   ::testing::HasSubstr("--with-collision"))));
  // Supplied under the name mbstream submit stores it (the path the URDF writes).
  const UrdfImport supplied =
      ImportUrdf(OneJoint(testing::kAxisAndLimits, testing::kInertial + visual), "m.urdf",
                 {"irb/meshes/link1.stl"});
  EXPECT_THAT(supplied.warnings,
              ::testing::Not(::testing::Contains(::testing::HasSubstr("not supplied"))));
}

TEST(UrdfImportTest, FileImportFindsMeshesBesideTheUrdf) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("mbstream_urdf_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  std::filesystem::create_directories(dir / "meshes");
  const std::string text = OneJoint(
      testing::kAxisAndLimits,
      testing::kInertial +
          R"(<visual><geometry><mesh filename="package://irb/meshes/link1.stl"/></geometry></visual>)");
  std::ofstream(dir / "robot.urdf") << text;
  const std::string path = (dir / "robot.urdf").string();
  // Missing: the model imports (simulate never needs meshes), with a warning naming it.
  EXPECT_THAT(ImportUrdfFile(path).warnings,
              ::testing::Contains(::testing::AllOf(
                  ::testing::HasSubstr(path + ":3: link 'link1'"),
                  ::testing::HasSubstr("visual mesh 'package://irb/meshes/link1.stl' is not "
                                       "supplied"),
                  ::testing::HasSubstr("--asset link1.stl"))));
  std::ofstream(dir / "meshes" / "link1.stl") << "solid empty\nendsolid empty\n";
  EXPECT_EQ(ImportUrdfFile(path).model.num_dofs(), 1);
  EXPECT_THAT(ImportUrdfFile(path).warnings,
              ::testing::Not(::testing::Contains(::testing::HasSubstr("not supplied"))));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mbstream
