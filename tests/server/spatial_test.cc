// Spatial algebra: the blockwise operations agree with the textbook 6x6 matrices.
#include "server/math/spatial.h"

#include <gtest/gtest.h>

#include "server/math/rigid_inertia.h"

namespace mbstream {
namespace {

Pose SomePose() {
  Pose X;
  X.R = Eigen::AngleAxisd(0.8, Vector3d(0.3, -1.0, 0.5).normalized()).toRotationMatrix();
  X.p = {0.4, -0.2, 1.1};
  return X;
}

// Featherstone's motion transform from A coordinates to B coordinates, as a 6x6 matrix.
Matrix6d MotionTransformMatrix(const Pose& X_AB) {
  const Matrix3d E = X_AB.R.transpose();
  Matrix6d X = Matrix6d::Zero();
  X.topLeftCorner<3, 3>() = E;
  X.bottomRightCorner<3, 3>() = E;
  X.bottomLeftCorner<3, 3>() = -E * Skew(X_AB.p);
  return X;
}

TEST(SpatialTest, PoseComposesAndInverts) {
  const Pose X = SomePose();
  const Pose I = X * X.Inverse();
  EXPECT_TRUE(I.R.isApprox(Matrix3d::Identity(), 1e-14));
  EXPECT_LT(I.p.norm(), 1e-14);
  const Vector3d q(0.1, 0.2, 0.3);
  EXPECT_TRUE(X.Inverse().Apply(X.Apply(q)).isApprox(q, 1e-14));
}

TEST(SpatialTest, AxisAngleRotationMatchesEigen) {
  const Vector3d axis = Vector3d(1, -2, 0.5).normalized();
  EXPECT_TRUE(AxisAngleRotation(axis, 1.3).isApprox(Eigen::AngleAxisd(1.3, axis).toRotationMatrix(),
                                                    1e-15));
}

TEST(SpatialTest, MotionToChildMatchesMatrixForm) {
  const Pose X = SomePose();
  Vector6d m;
  m << 0.3, -0.1, 0.7, 1.0, 2.0, -0.5;
  EXPECT_TRUE(MotionToChild(X, m).isApprox(MotionTransformMatrix(X) * m, 1e-14));
}

TEST(SpatialTest, ForceToParentIsTheDualTransform) {
  const Pose X = SomePose();
  Vector6d f;
  f << 0.2, 0.4, -0.3, 5.0, -1.0, 2.0;
  EXPECT_TRUE(ForceToParent(X, f).isApprox(MotionTransformMatrix(X).transpose() * f, 1e-14));
}

TEST(SpatialTest, RigidInertiaApplyMatchesMatrix) {
  RigidInertia I{3.0, {0.1, -0.2, 0.3}, Matrix3d::Zero()};
  I.inertia_com << 0.5, 0.01, 0.02, 0.01, 0.4, 0.03, 0.02, 0.03, 0.3;
  Vector6d v;
  v << 0.3, -0.1, 0.7, 1.0, 2.0, -0.5;
  EXPECT_TRUE(I.Apply(v).isApprox(I.ToMatrix() * v, 1e-14));
}

TEST(SpatialTest, AddInertiaToParentEqualsCongruence) {
  const Pose X = SomePose();
  RigidInertia body{2.0, {0.1, 0.2, -0.1}, Matrix3d::Identity() * 0.3};
  Matrix6d I_B = body.ToMatrix();
  I_B(0, 3) += 0.1;  // make it a general symmetric (articulated) inertia
  I_B(3, 0) += 0.1;
  Matrix6d I_A = Matrix6d::Identity();
  AddInertiaToParent(X, I_B, &I_A);
  const Matrix6d Xm = MotionTransformMatrix(X);
  const Matrix6d expected = Matrix6d::Identity() + Xm.transpose() * I_B * Xm;
  EXPECT_TRUE(I_A.isApprox(expected, 1e-13));
}

TEST(SpatialTest, CombinedInertiaEqualsSumOfMatrices) {
  RigidInertia a{2.0, {0.1, 0.2, -0.1}, Matrix3d::Identity() * 0.3};
  RigidInertia b{1.0, {-0.3, 0.0, 0.4}, Matrix3d::Identity() * 0.1};
  const RigidInertia c = a.CombinedWith(b);
  EXPECT_DOUBLE_EQ(c.mass, 3.0);
  EXPECT_TRUE(c.ToMatrix().isApprox(a.ToMatrix() + b.ToMatrix(), 1e-14));
  // Moving a body to another frame preserves its spatial inertia up to the congruence.
  const Pose X = SomePose();
  Matrix6d in_parent = Matrix6d::Zero();
  AddInertiaToParent(X, a.ToMatrix(), &in_parent);
  EXPECT_TRUE(a.ExpressedIn(X).ToMatrix().isApprox(in_parent, 1e-13));
}

}  // namespace
}  // namespace mbstream
