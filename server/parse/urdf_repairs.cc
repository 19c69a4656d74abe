#include "server/parse/urdf_repairs.h"

#include <urdf_model/link.h>

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace mbstream {

namespace {

constexpr double kSmallestRelativeMoment = 1e-6;  // of the largest principal moment
constexpr double kSphereRadius = 0.01;            // m, for a tensor with no positive moment
constexpr double kStandInMass = 1e-3;             // kg
constexpr double kStandInCube = 0.02;             // m, edge when the visual has no size

// Inertia (kg*m^2) of a solid box of `mass` and edges `size` about its centre.
Matrix3d BoxInertia(double mass, const Vector3d& size) {
  const Vector3d s2 = size.cwiseProduct(size);
  return (mass / 12.0 * Vector3d(s2.y() + s2.z(), s2.x() + s2.z(), s2.x() + s2.y())).asDiagonal();
}

}  // namespace

std::optional<Matrix3d> NearestPhysicalInertia(const Matrix3d& I, double mass) {
  const Matrix3d symmetric = 0.5 * (I + I.transpose());
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eig(symmetric);
  Vector3d d = eig.eigenvalues();  // ascending
  if (!(d(2) > 0.0)) {
    return Matrix3d((0.4 * mass * kSphereRadius * kSphereRadius) * Matrix3d::Identity());
  }
  const Vector3d before = d;
  const double floor = kSmallestRelativeMoment * d(2);
  d(0) = std::max(d(0), floor);
  d(1) = std::max(d(1), floor);
  const double shortfall = d(2) - d(0) - d(1);
  if (shortfall > 0.0) {
    d(0) += 0.5 * shortfall;
    d(1) += 0.5 * shortfall;
  }
  if (d == before) return std::nullopt;
  const Matrix3d& V = eig.eigenvectors();
  const Matrix3d repaired = V * d.asDiagonal() * V.transpose();
  return Matrix3d(0.5 * (repaired + repaired.transpose()));
}

StandInInertia StandInForMasslessLink(const urdf::Link& link) {
  StandInInertia stand_in;
  stand_in.mass = kStandInMass;
  stand_in.size = Vector3d::Constant(kStandInCube);
  const urdf::Geometry* geometry =
      link.visual && link.visual->geometry ? link.visual->geometry.get() : nullptr;
  if (geometry && geometry->type == urdf::Geometry::BOX) {
    const urdf::Vector3& dim = static_cast<const urdf::Box*>(geometry)->dim;
    stand_in.size = Vector3d(dim.x, dim.y, dim.z);
  } else if (geometry && geometry->type == urdf::Geometry::CYLINDER) {
    const auto* cylinder = static_cast<const urdf::Cylinder*>(geometry);
    stand_in.size = Vector3d(2 * cylinder->radius, 2 * cylinder->radius, cylinder->length);
  } else if (geometry && geometry->type == urdf::Geometry::SPHERE) {
    stand_in.size = Vector3d::Constant(2 * static_cast<const urdf::Sphere*>(geometry)->radius);
  }
  if (!(stand_in.size.allFinite() && stand_in.size.minCoeff() > 0.0)) {
    stand_in.size = Vector3d::Constant(kStandInCube);
  }
  stand_in.inertia = BoxInertia(stand_in.mass, stand_in.size);
  return stand_in;
}

}  // namespace mbstream
