#include "server/parse/sdf_import.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <sdf/Joint.hh>
#include <sdf/JointAxis.hh>
#include <sdf/Link.hh>

#include "server/model/model_builder.h"
#include "server/parse/collision_reading.h"
#include "server/parse/import_cancel.h"
#include "shared/common/check.h"
#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/sdf_reading.h"

namespace mbstream {

namespace {

namespace mf = model_files;
constexpr const char* kWorld = mf::kSdfWorld;

Pose ToPose(const Eigen::Isometry3d& X) { return Pose{X.linear(), X.translation()}; }

Eigen::Isometry3d ToIsometry(const Pose& X) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = X.R;
  out.translation() = X.p;
  return out;
}

Pose ToPose(const ignition::math::Pose3d& pose) {
  const ignition::math::Matrix3d r(pose.Rot());
  Pose X;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) X.R(i, j) = r(i, j);
  }
  X.p = Vector3d(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

using JointInfo = mf::SdfJointOutline;

class SdfReader {
 public:
  SdfReader(const mf::SdfFile& file, const MeshSource& meshes)
      : file_(file), meshes_(meshes), source_(file.source()) {}

  SdfImport Read() {
    const mf::SdfTree tree = mf::ChooseSdfTree(file_);
    result_.warnings = tree.warnings;
    const std::vector<mf::SdfLinkFrame> frames = mf::SdfLinkFrames(file_, tree);
    ModelBuilder builder(file_.title(), kWorld);
    frame_of_[kWorld] = Pose::Identity();
    for (size_t k = 0; k < tree.tree.size(); ++k) {
      AddTreeJoint(builder, tree.joints[tree.tree[k]], ToPose(frames[k].X_WL));
    }
    SetTcpIfNamed(builder);
    result_.model = builder.Build();
    if (file_.gravity()) result_.model.gravity = *file_.gravity();  // a run spec's gravity wins
    ReadSdfCollisions(file_, frame_of_, meshes_, &result_.model, &result_.warnings);
    for (const size_t j : tree.cut) result_.loops.push_back(LoopOf(tree.joints[j]));
    return std::move(result_);
  }

 private:
  // X_WJ, a file joint's frame in the world.
  Pose JointFrame(const JointInfo& info) const {
    return ToPose(mf::WorldPose(file_.models()[info.model], info.joint->SemanticPose(),
                                "joint '" + info.name + "'", info.where));
  }

  // The link's inertia in frame F_L (in the world).
  RigidInertia InertiaIn(const std::string& scoped_link, const Pose& F_L) const {
    const mf::SdfLinkRef ref = mf::FindSdfLink(file_, scoped_link);
    const ignition::math::Inertiald& inertial = ref.link->Inertial();
    const Pose X_WL = ToPose(mf::SdfLinkPose(file_, scoped_link));
    const Pose X_FI = F_L.Inverse() * X_WL * ToPose(inertial.Pose());
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

  void AddTreeJoint(ModelBuilder& builder, const JointInfo& info, const Pose& F_L) {
    const std::string what = info.where + ": joint '" + info.name + "'";
    const Pose& F_P = frame_of_.at(info.parent);
    frame_of_[info.child] = F_L;
    try {
      if (info.role == mf::SdfJointRole::kFree) {
        AddFreeBody(builder, info, F_L);
        return;
      }
      if (info.role == mf::SdfJointRole::kWeld || info.joint->Type() == sdf::JointType::FIXED) {
        builder.AddFixedLink(info.child, info.parent, F_P.Inverse() * F_L,
                             InertiaIn(info.child, F_L));
        return;
      }
      if (info.joint->Type() == sdf::JointType::BALL) {  // its frame's origin, the centre
        builder.AddBallLink(info.child, info.parent, info.name, F_P.Inverse() * F_L,
                            InertiaIn(info.child, F_L));
        return;
      }
      Joint joint;
      joint.name = info.name;
      joint.type = info.joint->Type() == sdf::JointType::PRISMATIC ? JointType::kPrismatic
                                                                   : JointType::kRevolute;
      joint.X_PJ = F_P.Inverse() * F_L;
      joint.axis = mf::SdfJointAxis(file_, info, ToIsometry(F_L));
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
      builder.AddMovingLink(info.child, info.parent, joint, InertiaIn(info.child, F_L));
    } catch (const InputError& error) {
      const std::string message = error.what();
      if (message.rfind(source_, 0) == 0) throw;  // already placed
      throw InputError(what + ": " + message);
    }
  }

  // A model's canonical link with no joint to the world: a free body at its pose, its free
  // joint named after the link.
  void AddFreeBody(ModelBuilder& builder, const JointInfo& info, const Pose& X_WL) {
    builder.AddFreeLink(info.child, info.name, X_WL, InertiaIn(info.child, X_WL));
  }

  void SetTcpIfNamed(ModelBuilder& builder) const {
    for (const mf::SdfModelEntry& entry : file_.models()) {
      for (uint64_t k = 0; k < entry.model->LinkCount(); ++k) {
        const std::string& name = entry.model->LinkByIndex(k)->Name();
        std::string lower = name;
        for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (lower == "tcp" || lower == "tool0") {
          builder.SetTcp(entry.prefix + name);
          return;
        }
      }
    }
  }

  LoopClosure LoopOf(const JointInfo& info) const {
    const Model& model = result_.model;
    LoopClosure loop;
    loop.name = info.name;
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
    const Pose X_WJ = JointFrame(info);
    if (loop.type == LoopJointType::kRevolute || loop.type == LoopJointType::kPrismatic) {
      loop.axis = mf::SdfJointAxis(file_, info, ToIsometry(X_WJ));
    }
    // The joint frame in the body that carries each side's link.
    auto side = [&](const std::string& link, int* body, Pose* X_BJ) {
      const Frame& frame = model.frames[model.FindFrame(link)];
      *body = frame.body;
      *X_BJ = frame.X_BF * frame_of_.at(link).Inverse() * X_WJ;
    };
    side(info.parent, &loop.body_a, &loop.X_AJ);
    side(info.child, &loop.body_b, &loop.X_BJ);
    return loop;
  }

  const mf::SdfFile& file_;
  const MeshSource& meshes_;
  const std::string source_;
  std::map<std::string, Pose> frame_of_;  // F_L: each link's frame in the Model, in the world
  SdfImport result_;
};

}  // namespace

SdfImport ImportSdf(const std::string& text, const std::string& source,
                    const SdfImportOptions& options) {
  const mf::SdfFile file(text, source,
                         {.max_links = options.max_links, .includes = options.includes});
  ThrowIfImportCancelled();  // libsdformat's parse cannot be stopped inside (import_cancel.h)
  SdfImport result = SdfReader(file, options.collision_meshes).Read();
  SdfMeshes meshes = mf::MeshesOf(file);
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
  SdfImportOptions local = options;
  if (!local.includes) {
    local.includes =
        mf::SdfIncludePath{std::filesystem::path(path).parent_path(), mf::PackagePath({})};
  }
  if (!local.collision_meshes) {
    local.collision_meshes = DiskMeshSource(std::filesystem::path(path).parent_path());
  }
  return ImportSdf(text.str(), path, local);
}

}  // namespace mbstream
