#include "server/parse/sdf_import.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <sdf/Collision.hh>
#include <sdf/Geometry.hh>
#include <sdf/Joint.hh>
#include <sdf/JointAxis.hh>
#include <sdf/Link.hh>
#include <sdf/Mesh.hh>
#include <sdf/Model.hh>
#include <sdf/Root.hh>
#include <sdf/Visual.hh>
#include <sdf/World.hh>

#include "common/check.h"
#include "server/model/model_builder.h"
#include "urdf_reading/sdf_reading.h"

namespace mbstream {

namespace {

constexpr const char* kWorld = urdf_reading::kSdfWorld;
using urdf_reading::MeshesOf;
using urdf_reading::ThrowSdfErrors;

Pose ToPose(const ignition::math::Pose3d& pose) {
  const ignition::math::Matrix3d r(pose.Rot());
  Pose X;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) X.R(i, j) = r(i, j);
  }
  X.p = Vector3d(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

using JointInfo = urdf_reading::SdfJointOutline;

class SdfReader {
 public:
  explicit SdfReader(const urdf_reading::SdfFile& file)
      : file_(file), sdf_(file.model()), source_(file.source()) {}

  SdfImport Read() {
    const urdf_reading::SdfTree tree = urdf_reading::ChooseSdfTree(file_);
    ModelBuilder builder(sdf_.Name(), kWorld);
    frame_of_[kWorld] = Pose::Identity();
    for (const size_t j : tree.tree) AddTreeJoint(builder, tree.joints[j]);
    SetTcpIfNamed(builder);
    result_.model = builder.Build();
    for (const size_t j : tree.cut) result_.loops.push_back(LoopOf(tree.joints[j]));
    return std::move(result_);
  }

 private:
  Pose ModelPoseOf(const sdf::SemanticPose& pose, const std::string& what,
                   const std::string& where) const {
    ignition::math::Pose3d resolved;
    const sdf::Errors errors = pose.Resolve(resolved, "__model__");
    if (!errors.empty()) {
      throw InputError(where + ": " + what + ": its pose cannot be resolved: \"" +
                       errors.front().Message() + "\"; check its relative_to frame");
    }
    return ToPose(resolved);
  }

  // X_MJ, the joint frame in the model frame.
  Pose JointFrame(const JointInfo& info) const {
    return ModelPoseOf(info.joint->SemanticPose(), "joint '" + info.joint->Name() + "'",
                       info.where);
  }

  // The joint's unit axis in its own frame J.
  Vector3d AxisInJoint(const JointInfo& info, const Pose& X_MJ) const {
    const sdf::JointAxis* axis = info.joint->Axis(0);
    if (axis == nullptr) {
      throw InputError(info.where + ": joint '" + info.joint->Name() +
                       "': no <axis>; give <axis><xyz>0 0 1</xyz></axis>");
    }
    ignition::math::Vector3d xyz;
    const sdf::Errors errors = axis->ResolveXyz(xyz, "__model__");
    if (!errors.empty()) ThrowSdfErrors(source_, errors);
    const Vector3d a = X_MJ.R.transpose() * Vector3d(xyz.X(), xyz.Y(), xyz.Z());
    if (!(a.norm() > 1e-12)) {
      throw InputError(info.where + ": joint '" + info.joint->Name() +
                       "': the axis is zero; give a unit vector");
    }
    return a.normalized();
  }

  RigidInertia InertiaIn(const sdf::Link& link, const Pose& F_L) const {
    const ignition::math::Inertiald& inertial = link.Inertial();
    const Pose X_ML =
        ModelPoseOf(link.SemanticPose(), "link '" + link.Name() + "'", file_.Where(link.Element()));
    const Pose X_FI = F_L.Inverse() * X_ML * ToPose(inertial.Pose());
    const ignition::math::Matrix3d moi = inertial.MassMatrix().Moi();
    Matrix3d I;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) I(i, j) = moi(i, j);
    }
    return RigidInertia{inertial.MassMatrix().Mass(), X_FI.p, X_FI.R * I * X_FI.R.transpose()};
  }

  static double LimitOrInfinity(double value, bool upper) {
    const double inf = std::numeric_limits<double>::infinity();
    if (std::abs(value) >= 1e16) return upper ? inf : -inf;
    return value;
  }

  void AddTreeJoint(ModelBuilder& builder, const JointInfo& info) {
    const sdf::Link& link = *sdf_.LinkByName(info.child);
    const std::string what = info.where + ": joint '" + info.joint->Name() + "'";
    const Pose& F_P = frame_of_.at(info.parent);
    try {
      if (info.joint->Type() == sdf::JointType::FIXED) {
        const Pose F_L = ModelPoseOf(link.SemanticPose(), "link '" + link.Name() + "'",
                                     file_.Where(link.Element()));
        frame_of_[info.child] = F_L;
        builder.AddFixedLink(info.child, info.parent, F_P.Inverse() * F_L, InertiaIn(link, F_L));
        return;
      }
      const Pose X_MJ = JointFrame(info);
      frame_of_[info.child] = X_MJ;
      if (info.joint->Type() == sdf::JointType::BALL) {
        const std::string axes[3] = {urdf_reading::SdfBallAxisName(info.joint->Name(), 0),
                                     urdf_reading::SdfBallAxisName(info.joint->Name(), 1),
                                     urdf_reading::SdfBallAxisName(info.joint->Name(), 2)};
        builder.AddBallLink(info.child, info.parent, info.joint->Name(), info.where,
                            F_P.Inverse() * X_MJ, axes, InertiaIn(link, X_MJ));
        return;
      }
      Joint joint;
      joint.name = info.joint->Name();
      joint.type = info.joint->Type() == sdf::JointType::PRISMATIC ? JointType::kPrismatic
                                                                   : JointType::kRevolute;
      joint.X_PJ = F_P.Inverse() * X_MJ;
      joint.axis = AxisInJoint(info, X_MJ);
      const sdf::JointAxis& axis = *info.joint->Axis(0);
      if (info.joint->Type() != sdf::JointType::CONTINUOUS) {
        joint.limits.lower = LimitOrInfinity(axis.Lower(), false);
        joint.limits.upper = LimitOrInfinity(axis.Upper(), true);
      }
      if (axis.Effort() > 0.0) joint.limits.effort = axis.Effort();
      if (axis.MaxVelocity() > 0.0) joint.limits.velocity = axis.MaxVelocity();
      if (axis.Damping() < 0.0) {
        throw InputError("the damping is negative; give a damping >= 0");
      }
      joint.damping = axis.Damping();
      builder.AddMovingLink(info.child, info.parent, joint, InertiaIn(link, X_MJ));
    } catch (const InputError& error) {
      const std::string message = error.what();
      if (message.rfind(source_, 0) == 0) throw;  // already placed
      throw InputError(what + ": " + message);
    }
  }

  void SetTcpIfNamed(ModelBuilder& builder) const {
    for (uint64_t k = 0; k < sdf_.LinkCount(); ++k) {
      const std::string& name = sdf_.LinkByIndex(k)->Name();
      std::string lower = name;
      for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (lower == "tcp" || lower == "tool0") {
        builder.SetTcp(name);
        return;
      }
    }
  }

  LoopClosure LoopOf(const JointInfo& info) const {
    const Model& model = result_.model;
    LoopClosure loop;
    loop.name = info.joint->Name();
    loop.where = info.where;
    switch (info.joint->Type()) {
      case sdf::JointType::PRISMATIC:
        loop.type = LoopJointType::kPrismatic;
        break;
      case sdf::JointType::BALL:
        loop.type = LoopJointType::kBall;
        break;
      case sdf::JointType::FIXED:
        loop.type = LoopJointType::kFixed;
        break;
      default:
        loop.type = LoopJointType::kRevolute;
    }
    const Pose X_MJ = JointFrame(info);
    if (loop.type == LoopJointType::kRevolute || loop.type == LoopJointType::kPrismatic) {
      loop.axis = AxisInJoint(info, X_MJ);
    }
    // The joint frame in the body that carries each side's link.
    auto side = [&](const std::string& link, int* body, Pose* X_BJ) {
      const Frame& frame = model.frames[model.FindFrame(link)];
      *body = frame.body;
      *X_BJ = frame.X_BF * frame_of_.at(link).Inverse() * X_MJ;
    };
    side(info.parent, &loop.body_a, &loop.X_AJ);
    side(info.child, &loop.body_b, &loop.X_BJ);
    return loop;
  }

  const urdf_reading::SdfFile& file_;
  const sdf::Model& sdf_;
  const std::string source_;
  std::map<std::string, Pose> frame_of_;  // F_L: each link's frame in the Model, in the model frame
  SdfImport result_;
};

}  // namespace

SdfImport ImportSdf(const std::string& text, const std::string& source,
                    const SdfImportOptions& options) {
  const urdf_reading::SdfFile file(text, source, {.max_links = options.max_links});
  SdfImport result = SdfReader(file).Read();
  SdfMeshes meshes = MeshesOf(file.model());
  result.mesh_files = std::move(meshes.visual);
  for (std::string& uri : meshes.collision) {
    if (std::find(result.mesh_files.begin(), result.mesh_files.end(), uri) ==
        result.mesh_files.end()) {
      result.mesh_files.push_back(std::move(uri));
    }
  }
  return result;
}

SdfImport ImportSdfFile(const std::string& path, const SdfImportOptions& options) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the file; check the path");
  std::ostringstream text;
  text << in.rdbuf();
  return ImportSdf(text.str(), path, options);
}

}  // namespace mbstream
