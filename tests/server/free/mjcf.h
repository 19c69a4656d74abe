// A Model with free bodies written as MuJoCo's MJCF, for comparisons with MuJoCo (tests and
// bench/free_body_bench.cc): free roots as <freejoint>, revolute, prismatic and ball joints as
// hinge, slide and ball joints at their body's origin, inertias as <inertial> on their principal
// axes; contacts, constraints and passive forces disabled. Armature, damping and limits are not
// written.
#pragma once

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <sstream>
#include <string>
#include <vector>

#include "server/model/model.h"

namespace mbstream::testing {

inline std::string Numbers(const Vector3d& v) {
  std::ostringstream out;
  out.precision(17);
  out << v.x() << ' ' << v.y() << ' ' << v.z();
  return out.str();
}

// The principal axes in double precision here (MuJoCo's own diagonalisation of a full inertia
// is accurate to about 1e-8).
inline std::string Inertial(const RigidInertia& inertia) {
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eig(inertia.inertia_com);
  Matrix3d axes = eig.eigenvectors();
  if (axes.determinant() < 0.0) axes.col(2) = -axes.col(2);
  const Eigen::Quaterniond quat(axes);
  std::ostringstream out;
  out.precision(17);
  out << "<inertial pos=\"" << Numbers(inertia.com) << "\" quat=\"" << quat.w() << ' ' << quat.x()
      << ' ' << quat.y() << ' ' << quat.z() << "\" mass=\"" << inertia.mass << "\" diaginertia=\""
      << Numbers(eig.eigenvalues()) << "\"/>";
  return out.str();
}

// Body i and its subtree, depth first (MJCF nests a body's children inside it; the model's
// topological order need not be depth first).
inline void MjcfBody(const Model& model, int i, const std::vector<std::vector<int>>& children,
                     std::ostringstream& out) {
  const Body& body = model.bodies[i];
  if (body.free()) {
    out << "<body name=\"" << body.name << "\"><freejoint name=\"" << body.joint.name << "\"/>";
  } else {
    const Eigen::Quaterniond quat(body.joint.X_PJ.R);
    out << "<body name=\"" << body.name << "\" pos=\"" << Numbers(body.joint.X_PJ.p) << "\" quat=\""
        << quat.w() << ' ' << quat.x() << ' ' << quat.y() << ' ' << quat.z() << "\"><joint name=\""
        << body.joint.name << "\" type=\"";
    if (body.ball()) {
      out << "ball\"/>";
    } else {
      out << (body.joint.type == JointType::kRevolute ? "hinge" : "slide") << "\" axis=\""
          << Numbers(body.joint.axis) << "\"/>";
    }
  }
  out << Inertial(body.inertia);
  for (const int child : children[static_cast<size_t>(i)]) MjcfBody(model, child, children, out);
  out << "</body>";
}

// `model` (free roots, ball and one-coordinate joints, no armature) as MJCF.
inline std::string Mjcf(const Model& model) {
  std::ostringstream out;
  out.precision(17);
  out << "<mujoco><option gravity=\"" << Numbers(model.gravity)
      << "\"><flag contact=\"disable\" constraint=\"disable\" passive=\"disable\"/></option>"
      << "<worldbody>";
  std::vector<std::vector<int>> children(static_cast<size_t>(model.num_bodies()));
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (model.bodies[i].parent != kBase)
      children[static_cast<size_t>(model.bodies[i].parent)].push_back(i);
  }
  for (int i = 0; i < model.num_bodies(); ++i) {
    if (model.bodies[i].parent == kBase) MjcfBody(model, i, children, out);
  }
  out << "</worldbody></mujoco>";
  return out.str();
}

}  // namespace mbstream::testing
