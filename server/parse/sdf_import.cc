#include "server/parse/sdf_import.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <sdf/Collision.hh>
#include <sdf/Console.hh>
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
#include "urdf_reading/xml_shape.h"

namespace mbstream {

namespace {

constexpr char kWorld[] = "world";

Pose ToPose(const ignition::math::Pose3d& pose) {
  const ignition::math::Matrix3d r(pose.Rot());
  Pose X;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) X.R(i, j) = r(i, j);
  }
  X.p = Vector3d(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

// "FILE:LINE" of an element (FILE alone when the line is unknown).
std::string Where(const std::string& source, const sdf::ElementPtr& element) {
  if (element != nullptr && element->LineNumber().has_value()) {
    return source + ":" + std::to_string(*element->LineNumber());
  }
  return source;
}

void AddMesh(const sdf::Geometry* geometry, std::vector<std::string>* uris) {
  if (geometry == nullptr || geometry->Type() != sdf::GeometryType::MESH) return;
  const sdf::Mesh* mesh = geometry->MeshShape();
  if (mesh == nullptr || mesh->Uri().empty()) return;
  if (std::find(uris->begin(), uris->end(), mesh->Uri()) == uris->end()) {
    uris->push_back(mesh->Uri());
  }
}

SdfMeshes MeshesOf(const sdf::Model& model) {
  SdfMeshes meshes;
  for (uint64_t l = 0; l < model.LinkCount(); ++l) {
    const sdf::Link& link = *model.LinkByIndex(l);
    for (uint64_t v = 0; v < link.VisualCount(); ++v) {
      AddMesh(link.VisualByIndex(v)->Geom(), &meshes.visual);
    }
    for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
      AddMesh(link.CollisionByIndex(c)->Geom(), &meshes.collision);
    }
  }
  return meshes;
}

[[noreturn]] void ThrowSdfErrors(const std::string& source, const sdf::Errors& errors) {
  std::string message;
  for (const sdf::Error& error : errors) {
    if (!message.empty()) message += "\n";
    message += source;
    if (error.LineNumber().has_value()) message += ":" + std::to_string(*error.LineNumber());
    message += ": SDFormat: \"" + error.Message() + "\"";
  }
  throw InputError(message + "\nfix the model file (SDFormat 1.6 or later, one model)");
}

// What the tree needs of one joint of the file.
struct JointInfo {
  const sdf::Joint* joint;
  std::string parent, child;  // link names, "world" for the world
  std::string where;
};

class SdfReader {
 public:
  SdfReader(const sdf::Model& model, std::string source)
      : sdf_(model), source_(std::move(source)) {}

  SdfImport Read() {
    if (sdf_.ModelCount() > 0) {
      throw InputError(Where(source_, sdf_.ModelByIndex(0)->Element()) + ": model '" +
                       sdf_.ModelByIndex(0)->Name() +
                       "': nested models are not supported yet; flatten the model into one "
                       "<model> of links and joints");
    }
    ReadJoints();
    ChooseTree();
    ModelBuilder builder(sdf_.Name(), kWorld);
    frame_of_[kWorld] = Pose::Identity();
    for (const JointInfo* info : tree_) AddTreeJoint(builder, *info);
    SetTcpIfNamed(builder);
    result_.model = builder.Build();
    for (const JointInfo& info : joints_) {
      if (cut_.count(info.joint->Name()) != 0) result_.loops.push_back(LoopOf(info));
    }
    return std::move(result_);
  }

 private:
  void ReadJoints() {
    for (uint64_t k = 0; k < sdf_.JointCount(); ++k) {
      const sdf::Joint* joint = sdf_.JointByIndex(k);
      JointInfo info{joint, joint->ParentLinkName(), joint->ChildLinkName(),
                     Where(source_, joint->Element())};
      for (const std::string* link : {&info.parent, &info.child}) {
        if (*link != kWorld && sdf_.LinkByName(*link) == nullptr) {
          throw InputError(info.where + ": joint '" + joint->Name() + "': link '" + *link +
                           "' is not a link of model '" + sdf_.Name() +
                           "'; name a link of this model (or world)");
        }
      }
      switch (joint->Type()) {
        case sdf::JointType::REVOLUTE:
        case sdf::JointType::CONTINUOUS:
        case sdf::JointType::PRISMATIC:
        case sdf::JointType::FIXED:
        case sdf::JointType::BALL:
          break;
        default:
          throw InputError(info.where + ": joint '" + joint->Name() +
                           "': this joint type is not simulated by mbstream; use revolute, "
                           "continuous, prismatic, fixed or ball joints");
      }
      joints_.push_back(info);
    }
  }

  // Breadth-first from the world, each link's joints in file order.
  void ChooseTree() {
    std::map<std::string, bool> reached{{kWorld, true}};
    std::deque<std::string> queue{kWorld};
    while (!queue.empty()) {
      const std::string link = queue.front();
      queue.pop_front();
      for (const JointInfo& info : joints_) {
        if (info.parent != link) continue;
        if (reached[info.child]) {
          cut_[info.joint->Name()] = true;
          continue;
        }
        if (info.joint->Type() == sdf::JointType::BALL) {
          throw InputError(info.where + ": joint '" + info.joint->Name() +
                           "': a ball joint inside the tree is not supported yet (only as the "
                           "joint that closes a loop); reorder the joints so that another "
                           "joint reaches link '" +
                           info.child + "' first, or use revolute joints");
        }
        reached[info.child] = true;
        tree_.push_back(&info);
        queue.push_back(info.child);
      }
    }
    for (uint64_t k = 0; k < sdf_.LinkCount(); ++k) {
      const sdf::Link* link = sdf_.LinkByIndex(k);
      if (!reached[link->Name()]) {
        throw InputError(Where(source_, link->Element()) + ": link '" + link->Name() +
                         "' is not reached from the world through parent-to-child joints (a "
                         "floating link); attach it, e.g. with a fixed joint whose parent is "
                         "world");
      }
    }
    for (const JointInfo& info : joints_) {
      if (!reached[info.parent]) {
        throw InputError(info.where + ": joint '" + info.joint->Name() + "': its parent link '" +
                         info.parent + "' is not reached from the world; attach it");
      }
    }
  }

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
    const Pose X_ML = ModelPoseOf(link.SemanticPose(), "link '" + link.Name() + "'",
                                  Where(source_, link.Element()));
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
                                     Where(source_, link.Element()));
        frame_of_[info.child] = F_L;
        builder.AddFixedLink(info.child, info.parent, F_P.Inverse() * F_L, InertiaIn(link, F_L));
        return;
      }
      const Pose X_MJ = JointFrame(info);
      frame_of_[info.child] = X_MJ;
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

  const sdf::Model& sdf_;
  const std::string source_;
  std::vector<JointInfo> joints_;
  std::vector<const JointInfo*> tree_;
  std::map<std::string, bool> cut_;
  std::map<std::string, Pose> frame_of_;  // F_L: each link's frame in the Model, in the model frame
  SdfImport result_;
};

}  // namespace

SdfImport ImportSdf(const std::string& text, const std::string& source,
                    const SdfImportOptions& options) {
  // libsdformat parses with TinyXML2 9 (Debian's libtinyxml2-9): it stops at its own nesting
  // limit (XML_ELEMENT_DEPTH_EXCEEDED) but counts neither attributes nor elements, and its
  // messages for UTF-16 text or entities mislead. The URDF reader's shape check goes first,
  // with the same limits (docs/reliability.md, "Limits").
  urdf_reading::XmlShapeLimits limits;
  limits.links_at_any_depth = true;
  if (options.max_links > 0) limits.max_top_links = options.max_links;
  limits.nesting_note =
      "an SDFormat model nests about 8 deep (sdf, world, model, link, visual, geometry, mesh, "
      "uri)";
  if (const auto problem = urdf_reading::CheckXmlShape(text, limits)) {
    const std::string message = source + ":" + std::to_string(problem->line) + ": " + problem->what;
    if (problem->over_caller_limit) throw LimitError(message);
    throw InputError(message);
  }
  // SDFormat's errors come back in `errors` and into our message: keep its console quiet.
  sdf::Console::Instance()->SetQuiet(true);
  sdf::Root root;
  const sdf::Errors errors = root.LoadSdfString(text);
  if (!errors.empty()) ThrowSdfErrors(source, errors);
  if (root.WorldCount() > 1) {
    throw InputError(source + ": the file has " + std::to_string(root.WorldCount()) +
                     " worlds; give one world (or a top-level <model>)");
  }
  const sdf::Model* model = root.Model();
  if (model == nullptr && root.WorldCount() == 1) {
    const sdf::World& world = *root.WorldByIndex(0);
    if (world.ModelCount() != 1) {
      throw InputError(Where(source, world.Element()) + ": world '" + world.Name() + "' has " +
                       std::to_string(world.ModelCount()) +
                       " models; mbstream simulates one mechanism: give the world one model");
    }
    model = world.ModelByIndex(0);
  }
  if (model == nullptr) {
    throw InputError(source + ": no <model> in the file; give a <model> with links and joints");
  }
  SdfImport result = SdfReader(*model, source).Read();
  SdfMeshes meshes = MeshesOf(*model);
  result.mesh_files = std::move(meshes.visual);
  for (std::string& uri : meshes.collision) {
    if (std::find(result.mesh_files.begin(), result.mesh_files.end(), uri) ==
        result.mesh_files.end()) {
      result.mesh_files.push_back(std::move(uri));
    }
  }
  return result;
}

SdfMeshes ReadSdfMeshes(const std::string& text) {
  // Hostile text never reaches libsdformat (a flood of attributes takes it minutes).
  urdf_reading::XmlShapeLimits limits;
  limits.links_at_any_depth = true;
  if (urdf_reading::CheckXmlShape(text, limits)) return {};
  sdf::Console::Instance()->SetQuiet(true);
  sdf::Root root;
  if (!root.LoadSdfString(text).empty()) return {};
  const sdf::Model* model = root.Model();
  if (model == nullptr && root.WorldCount() == 1 && root.WorldByIndex(0)->ModelCount() == 1) {
    model = root.WorldByIndex(0)->ModelByIndex(0);
  }
  return model == nullptr ? SdfMeshes{} : MeshesOf(*model);
}

SdfImport ImportSdfFile(const std::string& path, const SdfImportOptions& options) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the file; check the path");
  std::ostringstream text;
  text << in.rdbuf();
  return ImportSdf(text.str(), path, options);
}

}  // namespace mbstream
