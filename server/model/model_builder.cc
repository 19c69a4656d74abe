#include "server/model/model_builder.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <utility>

#include "shared/common/check.h"

namespace mbstream {

namespace {

std::string Format(const Vector3d& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) +
         ")";
}

}  // namespace

void ValidateRigidInertia(const RigidInertia& inertia, const std::string& what) {
  if (!std::isfinite(inertia.mass) || inertia.mass <= 0.0) {
    throw InputError(what + ": mass is " + std::to_string(inertia.mass) +
                     " kg; a moving link needs a positive mass (give it an <inertial> with "
                     "<mass value> > 0)");
  }
  if (!inertia.com.allFinite() || !inertia.inertia_com.allFinite()) {
    throw InputError(what + ": inertial data is not finite; give finite numbers");
  }
  const Matrix3d& I = inertia.inertia_com;
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > 1e-12 * (1.0 + I.cwiseAbs().maxCoeff())) {
    throw InputError(what + ": inertia tensor is not symmetric");
  }
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eig(I, Eigen::EigenvaluesOnly);
  const Vector3d d = eig.eigenvalues();  // ascending
  if (d(0) <= 0.0) {
    throw InputError(what + ": inertia tensor is not positive definite (principal moments " +
                     Format(d) + " kg*m^2); check ixx, iyy, izz and the products of inertia");
  }
  const double tol = 1e-9 * d(2);
  if (d(0) + d(1) < d(2) - tol) {
    throw InputError(what + ": inertia tensor breaks the triangle inequality (principal moments " +
                     Format(d) +
                     " kg*m^2: the two smaller must add up to at least the largest); no real "
                     "body has it, check the values and their units");
  }
}

ModelBuilder::ModelBuilder(std::string model_name, std::string base_link) {
  model_.name = std::move(model_name);
  model_.base_name = base_link;
  links_.emplace(base_link, LinkPlace{kBase, Pose::Identity()});
  names_.emplace(base_link, static_cast<int>(model_.frames.size()));
  model_.frames.push_back(Frame{base_link, kBase, Pose::Identity()});
}

void ModelBuilder::CheckNewName(const std::string& link) const {
  if (names_.count(link) != 0) {
    throw InputError("name '" + link +
                     "' is used twice; every link, frame and point needs a "
                     "unique name");
  }
}

const ModelBuilder::LinkPlace& ModelBuilder::PlaceOf(const std::string& link,
                                                     const std::string& context) const {
  const auto it = links_.find(link);
  if (it == links_.end()) {
    throw InputError(context + ": parent link '" + link +
                     "' is not defined (yet); define links from the base outwards");
  }
  return it->second;
}

void ModelBuilder::AddMovingLink(const std::string& link, const std::string& parent_link,
                                 const Joint& joint, const RigidInertia& inertia) {
  if (joint.type != JointType::kRevolute && joint.type != JointType::kPrismatic) {
    throw InputError("joint '" + joint.name + "' (link '" + link + "'): AddMovingLink takes a " +
                     "revolute or prismatic joint, not " + JointTypeName(joint.type) +
                     "; use AddBallLink or AddFreeLink");
  }
  AddBody(link, parent_link, joint, inertia);
}

void ModelBuilder::AddBallLink(const std::string& link, const std::string& parent_link,
                               const std::string& joint_name, const Pose& X_PJ,
                               const RigidInertia& inertia) {
  const double orthogonality = (X_PJ.R.transpose() * X_PJ.R - Matrix3d::Identity()).norm();
  if (!X_PJ.p.allFinite() || !(orthogonality < 1e-9) || !(X_PJ.R.determinant() > 0.0)) {
    throw InputError("ball joint '" + joint_name + "' (link '" + link +
                     "'): its frame is not a finite rigid pose (|R^T R - 1| = " +
                     std::to_string(orthogonality) + ")");
  }
  Joint joint;
  joint.name = joint_name;
  joint.type = JointType::kBall;
  joint.X_PJ = X_PJ;
  AddBody(link, parent_link, joint, inertia);
}

void ModelBuilder::AddBody(const std::string& link, const std::string& parent_link,
                           const Joint& joint, const RigidInertia& inertia) {
  const std::string what = "joint '" + joint.name + "' (link '" + link + "')";
  CheckNewName(link);
  const LinkPlace& parent = PlaceOf(parent_link, what);
  const double norm = joint.axis.norm();
  if (!(std::abs(norm - 1.0) < 1e-9)) {
    throw InputError(what + ": axis " + Format(joint.axis) + " is not a unit vector");
  }
  if (!(joint.limits.lower <= joint.limits.upper)) {
    throw InputError(what + ": lower limit is above upper limit");
  }
  if (!(joint.damping >= 0.0) || !(joint.armature >= 0.0)) {
    throw InputError(what + ": damping and armature must be finite and >= 0");
  }
  ValidateRigidInertia(inertia, "link '" + link + "'");

  Body body;
  body.name = link;
  body.parent = parent.body;
  body.joint = joint;
  body.joint.X_PJ = parent.X_BL * joint.X_PJ;  // re-expressed in the moving parent body
  DeriveJointShape(body.joint);
  body.inertia = inertia;
  const int index = static_cast<int>(model_.bodies.size());
  model_.bodies.push_back(std::move(body));

  links_.emplace(link, LinkPlace{index, Pose::Identity()});
  names_.emplace(link, static_cast<int>(model_.frames.size()));
  model_.frames.push_back(Frame{link, index, Pose::Identity()});
}

void ModelBuilder::AddFreeLink(const std::string& link, const std::string& joint_name,
                               const Pose& X_WL, const RigidInertia& inertia) {
  const std::string what = "free joint '" + joint_name + "' (link '" + link + "')";
  CheckNewName(link);
  if (!X_WL.p.allFinite() || !X_WL.R.allFinite()) {
    throw InputError(what + ": its pose is not finite; give finite numbers");
  }
  const double orthogonality = (X_WL.R.transpose() * X_WL.R - Matrix3d::Identity()).norm();
  if (!(orthogonality < 1e-9) || !(X_WL.R.determinant() > 0.0)) {
    throw InputError(what + ": its pose's rotation is not a rotation (|R^T R - 1| = " +
                     std::to_string(orthogonality) +
                     ", det R = " + std::to_string(X_WL.R.determinant()) + ")");
  }
  ValidateRigidInertia(inertia, "link '" + link + "'");
  Body body;
  body.name = link;
  body.parent = kBase;
  body.joint.name = joint_name;
  body.joint.type = JointType::kFree;
  DeriveJointShape(body.joint);
  body.inertia = inertia;
  body.X_W0 = X_WL;
  const int index = static_cast<int>(model_.bodies.size());
  model_.bodies.push_back(std::move(body));
  links_.emplace(link, LinkPlace{index, Pose::Identity()});
  names_.emplace(link, static_cast<int>(model_.frames.size()));
  model_.frames.push_back(Frame{link, index, Pose::Identity()});
}

void ModelBuilder::AddFixedLink(const std::string& link, const std::string& parent_link,
                                const Pose& X_PL, const RigidInertia& inertia) {
  CheckNewName(link);
  const LinkPlace& parent = PlaceOf(parent_link, "fixed link '" + link + "'");
  const LinkPlace place{parent.body, parent.X_BL * X_PL};
  if (place.body != kBase && inertia.mass > 0.0) {
    Body& body = model_.bodies[place.body];
    body.inertia = body.inertia.CombinedWith(inertia.ExpressedIn(place.X_BL));
  }
  links_.emplace(link, place);
  names_.emplace(link, static_cast<int>(model_.frames.size()));
  model_.frames.push_back(Frame{link, place.body, place.X_BL});
}

void ModelBuilder::AddPoint(const std::string& name, const std::string& link,
                            const Vector3d& p_LP) {
  CheckNewName(name);
  const LinkPlace& place = PlaceOf(link, "point '" + name + "'");
  Pose X_LP;
  X_LP.p = p_LP;
  names_.emplace(name, static_cast<int>(model_.frames.size()));
  model_.frames.push_back(Frame{name, place.body, place.X_BL * X_LP});
}

void ModelBuilder::SetTcp(const std::string& frame_name) {
  const auto it = names_.find(frame_name);
  if (it == names_.end()) {
    throw InputError("TCP frame '" + frame_name + "' is not a link or point of the model");
  }
  model_.tcp_frame = it->second;
}

Model ModelBuilder::Build() {
  for (size_t i = 0; i < model_.bodies.size(); ++i) {
    MBSTREAM_CHECK(model_.bodies[i].parent < static_cast<int>(i));
  }
  IndexCoordinates(&model_);
  return std::move(model_);
}

}  // namespace mbstream
