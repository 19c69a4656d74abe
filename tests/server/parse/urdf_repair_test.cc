// --repair: each defect published URDFs commonly carry is an error naming --repair without
// it, and with it a warning "FILE:LINE: KIND 'NAME': repaired: old -> new" and a model that
// builds and simulates like the nearest physical one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "server/parse/urdf_import.h"
#include "server/parse/urdf_repairs.h"
#include "tests/server/parse/urdf_test_util.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::HasSubstr;
using testing::ImportError;
using testing::InertialXml;
using testing::LinkXml;
using testing::OneJoint;
using testing::Robot;

UrdfImport Repaired(const std::string& text) {
  return ImportUrdf(text, "odd.urdf", {}, UrdfImportOptions{.repair = true});
}

Vector3d Moments(const Matrix3d& I) {
  return Eigen::SelfAdjointEigenSolver<Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
}

TEST(UrdfRepairTest, TriangleInequalityBrokenBy1e4IsMovedToTheNearestTensor) {
  // Published by a CAD export: 0.1 + 0.1 < 0.2001.
  const std::string text =
      OneJoint(testing::kAxisAndLimits, InertialXml("2", "0.1", "0.1", "0.2001"));
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("triangle inequality"), HasSubstr("--repair")));
  const UrdfImport import = Repaired(text);
  EXPECT_THAT(
      import.warnings,
      Contains(AllOf(HasSubstr("odd.urdf:3: link 'link1': repaired: inertia"),
                     HasSubstr("(0.1 0.1 0.2001)"), HasSubstr("(0.10005 0.10005 0.2001)"))));
  const Vector3d d = Moments(import.model.bodies.at(0).inertia.inertia_com);
  EXPECT_NEAR(d(0) + d(1), d(2), 1e-12);
  EXPECT_NEAR(d(2), 0.2001, 1e-12);  // the largest moment is kept
}

TEST(UrdfRepairTest, AZeroPrincipalMomentIsRaisedKeepingTheAxes) {
  // A thin rod along x written with ixx = 0, and a product of inertia: axes not the link's.
  Matrix3d I;
  I << 0.0, 0.0, 0.0,  //
      0.0, 0.5, 0.0,   //
      0.0, 0.0, 0.5;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Vector3d(0, 0, 1)).toRotationMatrix();
  const Matrix3d rotated = R * I * R.transpose();
  const std::optional<Matrix3d> nearest = NearestPhysicalInertia(rotated, 1.0);
  ASSERT_TRUE(nearest.has_value());
  const Vector3d d = Moments(*nearest);
  EXPECT_NEAR(d(0), 0.5e-6, 1e-15);
  EXPECT_NEAR(d(1), 0.5, 1e-12);
  // The rod's axis (R x) is still a principal axis with the smallest moment.
  const Vector3d axis = R * Vector3d::UnitX();
  EXPECT_NEAR((*nearest * axis - d(0) * axis).norm(), 0.0, 1e-12);
}

TEST(UrdfRepairTest, APhysicalTensorNeedsNoRepair) {
  EXPECT_FALSE(NearestPhysicalInertia(Matrix3d(Vector3d(0.1, 0.2, 0.25).asDiagonal()), 1.0));
  EXPECT_THAT(Repaired(OneJoint()).warnings, ::testing::Not(Contains(HasSubstr("repaired"))));
}

TEST(UrdfRepairTest, NegativeLimitsBecomeNoLimit) {
  const std::string text =
      OneJoint(R"(<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="-1" velocity="-1"/>)");
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("is negative"), HasSubstr("--repair")));
  const UrdfImport import = Repaired(text);
  EXPECT_THAT(import.warnings, Contains(AllOf(HasSubstr("odd.urdf:4: joint 'j1': repaired"),
                                              HasSubstr("velocity limit -1 rad/s"))));
  EXPECT_THAT(import.warnings, Contains(HasSubstr("effort limit -1 N*m")));
  EXPECT_TRUE(std::isinf(import.model.bodies.at(0).joint.limits.velocity));
  EXPECT_TRUE(std::isinf(import.model.bodies.at(0).joint.limits.effort));
}

TEST(UrdfRepairTest, AMasslessMovingLinkGetsASmallMassFromItsVisual) {
  const std::string text = Robot(
      LinkXml("link1", InertialXml("0", "0", "0", "0") +
                           R"(<visual><geometry><box size="0.1 0.2 0.3"/></geometry></visual>)") +
      testing::JointXml("j1", "revolute", "base", "link1"));
  EXPECT_THAT(ImportError(text), AllOf(HasSubstr("positive mass"), HasSubstr("--repair")));
  const UrdfImport import = Repaired(text);
  EXPECT_THAT(import.warnings,
              Contains(AllOf(HasSubstr("odd.urdf:3: link 'link1': repaired: mass 0"),
                             HasSubstr("(0.1 0.2 0.3)"))));
  const RigidInertia& inertia = import.model.bodies.at(0).inertia;
  EXPECT_EQ(inertia.mass, 1e-3);
  EXPECT_NEAR(inertia.inertia_com(0, 0), 1e-3 / 12 * (0.04 + 0.09), 1e-15);
}

}  // namespace
}  // namespace mbstream
