// The shape-specialised transforms across a joint (joint_spatial_transform.h,
// joint_inertia_transform.h) against the general ones, for every shape.
#include <gtest/gtest.h>

#include <utility>

#include "server/kinematics/joint_inertia_transform.h"
#include "server/kinematics/joint_spatial_transform.h"
#include "server/kinematics/joint_transform.h"

namespace mbstream {
namespace {

struct ShapeCase {
  const char* name;
  JointType type;
  Vector3d axis;
  bool rotated_origin;
  int expected_shape;
};

Joint MakeJoint(const ShapeCase& c) {
  Joint joint;
  joint.type = c.type;
  joint.axis = c.axis.normalized();
  joint.X_PJ.p = Vector3d(0.3, -0.2, 0.7);
  if (c.rotated_origin) {
    joint.X_PJ.R = Eigen::AngleAxisd(0.4, Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  }
  DeriveJointShape(joint);
  return joint;
}

class JointShapeTest : public ::testing::TestWithParam<ShapeCase> {};

TEST_P(JointShapeTest, SpecialisedTransformsMatchTheGeneralOnes) {
  const Joint joint = MakeJoint(GetParam());
  ASSERT_EQ(JointShape(joint), GetParam().expected_shape);
  Pose X;
  JointTransform(joint, 0.83, &X);
  Vector6d m, f, U;
  m << 0.3, -0.1, 0.7, 1.0, 2.0, -0.5;
  f << -1.2, 0.4, 0.9, 3.0, -0.7, 0.2;
  U << 0.5, 0.1, -0.3, 0.2, 0.4, 0.6;
  const Matrix6d L = Matrix6d::Random();
  const Matrix6d I_B = L * L.transpose() + 4.0 * Matrix6d::Identity();  // symmetric, like IA
  const double inv_D = 1.0 / 3.0;
  const Matrix6d projected = I_B - U * U.transpose() * inv_D;

  DispatchJointShape(joint, [&](auto shape) {
    Pose X_shape;
    JointTransformOfShape<shape()>(joint, 0.83, &X_shape);
    EXPECT_EQ(X_shape.R, X.R);  // bit for bit
    EXPECT_EQ(X_shape.p, X.p);
    EXPECT_LT((MotionToChildAcross<shape()>(X, m) - MotionToChild(X, m)).norm(), 1e-14);
    EXPECT_LT((ForceToParentAcross<shape()>(X, f) - ForceToParent(X, f)).norm(), 1e-14);

    Matrix6d expected = Matrix6d::Identity(), added = Matrix6d::Identity();
    AddInertiaToParent(X, I_B, &expected);
    AddInertiaAcross<shape()>(X, I_B, &added);
    EXPECT_LT((added - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.norm());

    Matrix6d expected_projected = Matrix6d::Identity(), added_projected = Matrix6d::Identity();
    AddInertiaToParent(X, projected, &expected_projected);
    Matrix6d I_B_copy = I_B;
    AddProjectedInertiaAcross<shape()>(X, I_B_copy, U, inv_D, &added_projected);
    EXPECT_LT((added_projected - expected_projected).cwiseAbs().maxCoeff(),
              1e-12 * expected_projected.norm());
  });
}

TEST(JointOffsetShapeTest, OffsetAxisAndAxisKernelAreDerived) {
  Joint joint;
  joint.axis = Vector3d::UnitY();
  const std::pair<Vector3d, int> cases[] = {{Vector3d(0.3, 0, 0), 0},
                                            {Vector3d(0, -0.2, 0), 1},
                                            {Vector3d(0, 0, 0.7), 2},
                                            {Vector3d::Zero(), kNoOffset},
                                            {Vector3d(0.15, 0, 0.4865), kAnyOffset}};
  for (const auto& [p, offset_axis] : cases) {
    joint.X_PJ.p = p;
    DeriveJointShape(joint);
    EXPECT_EQ(joint.offset_axis, offset_axis) << p.transpose();
    EXPECT_EQ(joint.axis_kernel, 5 + (offset_axis == kAnyOffset ? 4 : offset_axis));
  }
  joint.type = JointType::kPrismatic;  // no axis kernel: prismatic, or a rotated origin
  DeriveJointShape(joint);
  EXPECT_EQ(joint.axis_kernel, -1);
  joint.type = JointType::kRevolute;
  joint.X_PJ.R = AxisAngleRotation(Vector3d::UnitX(), 0.3);
  DeriveJointShape(joint);
  EXPECT_EQ(joint.axis_kernel, -1);
}

INSTANTIATE_TEST_SUITE_P(
    Shapes, JointShapeTest,
    ::testing::Values(ShapeCase{"RevoluteX", JointType::kRevolute, Vector3d::UnitX(), false, 0},
                      ShapeCase{"RevoluteY", JointType::kRevolute, Vector3d::UnitY(), false, 1},
                      ShapeCase{"RevoluteZ", JointType::kRevolute, Vector3d::UnitZ(), false, 2},
                      ShapeCase{"Prismatic", JointType::kPrismatic, Vector3d(0.6, 0.0, 0.8), false,
                                kTranslatingJoint},
                      ShapeCase{"RevoluteOblique", JointType::kRevolute, Vector3d(1, 2, 3), false,
                                kGeneralJoint},
                      ShapeCase{"RevoluteRotatedOrigin", JointType::kRevolute, Vector3d::UnitZ(),
                                true, kGeneralJoint},
                      ShapeCase{"PrismaticRotatedOrigin", JointType::kPrismatic, Vector3d::UnitX(),
                                true, kGeneralJoint}),
    [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace mbstream
