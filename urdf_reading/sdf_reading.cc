#include "urdf_reading/sdf_reading.h"

#include <algorithm>
#include <deque>
#include <map>

#include <sdf/Box.hh>
#include <sdf/Collision.hh>
#include <sdf/Console.hh>
#include <sdf/Cylinder.hh>
#include <sdf/Geometry.hh>
#include <sdf/JointAxis.hh>
#include <sdf/Link.hh>
#include <sdf/Material.hh>
#include <sdf/Mesh.hh>
#include <sdf/Sphere.hh>
#include <sdf/Visual.hh>
#include <sdf/World.hh>

#include "common/check.h"
#include "urdf_reading/xml_shape.h"

namespace mbstream::urdf_reading {

namespace {

Eigen::Isometry3d ToIsometry(const ignition::math::Pose3d& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const ignition::math::Quaterniond& q = pose.Rot();
  X.linear() = Eigen::Quaterniond(q.W(), q.X(), q.Y(), q.Z()).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

void AddMesh(const sdf::Geometry* geometry, std::vector<std::string>* uris) {
  if (geometry == nullptr || geometry->Type() != sdf::GeometryType::MESH) return;
  const sdf::Mesh* mesh = geometry->MeshShape();
  if (mesh == nullptr || mesh->Uri().empty()) return;
  if (std::find(uris->begin(), uris->end(), mesh->Uri()) == uris->end()) {
    uris->push_back(mesh->Uri());
  }
}

std::optional<Eigen::Vector3d> Colour(const sdf::Material& material, const char* element,
                                      const ignition::math::Color& colour) {
  if (material.Element() == nullptr || !material.Element()->HasElement(element)) {
    return std::nullopt;
  }
  return Eigen::Vector3d(colour.R(), colour.G(), colour.B());
}

}  // namespace

SdfFile::SdfFile(const std::string& text, std::string source, const SdfLoadOptions& options)
    : root_(std::make_unique<sdf::Root>()), source_(std::move(source)) {
  // libsdformat parses with TinyXML2 9 (Debian's libtinyxml2-9): it stops at its own nesting
  // limit (XML_ELEMENT_DEPTH_EXCEEDED) but counts neither attributes nor elements, and its
  // messages for UTF-16 text or entities mislead. The URDF reader's shape check goes first,
  // with the same limits (docs/reliability.md, "Limits").
  XmlShapeLimits limits;
  limits.links_at_any_depth = true;
  if (options.max_links > 0) limits.max_top_links = options.max_links;
  limits.nesting_note =
      "an SDFormat model nests about 8 deep (sdf, world, model, link, visual, geometry, mesh, "
      "uri)";
  limits.refused_element = "include";
  limits.refused_note =
      "it would read another file (a model:// path, a URL, a file of the machine that reads "
      "this one); copy the included model's links and joints into this file";
  if (const auto problem = CheckXmlShape(text, limits)) {
    const std::string message =
        source_ + ":" + std::to_string(problem->line) + ": " + problem->what;
    if (problem->over_caller_limit) throw LimitError(message);
    throw InputError(message);
  }
  // SDFormat's errors come back in `errors` and into our message: keep its console quiet.
  sdf::Console::Instance()->SetQuiet(true);
  const sdf::Errors errors = root_->LoadSdfString(text);
  if (!errors.empty()) ThrowSdfErrors(source_, errors);
  if (root_->WorldCount() > 1) {
    throw InputError(source_ + ": the file has " + std::to_string(root_->WorldCount()) +
                     " worlds; give one world (or a top-level <model>)");
  }
  model_ = root_->Model();
  if (model_ == nullptr && root_->WorldCount() == 1) {
    const sdf::World& world = *root_->WorldByIndex(0);
    if (world.ModelCount() != 1) {
      throw InputError(Where(world.Element()) + ": world '" + world.Name() + "' has " +
                       std::to_string(world.ModelCount()) +
                       " models; mbstream simulates one mechanism: give the world one model");
    }
    model_ = world.ModelByIndex(0);
  }
  if (model_ == nullptr) {
    throw InputError(source_ + ": no <model> in the file; give a <model> with links and joints");
  }
}

std::string SdfFile::Where(const sdf::ElementPtr& element) const {
  if (element != nullptr && element->LineNumber().has_value()) {
    return source_ + ":" + std::to_string(*element->LineNumber());
  }
  return source_;
}

SdfTree ChooseSdfTree(const SdfFile& file) {
  const sdf::Model& model = file.model();
  if (model.ModelCount() > 0) {
    throw InputError(file.Where(model.ModelByIndex(0)->Element()) + ": model '" +
                     model.ModelByIndex(0)->Name() +
                     "': nested models are not supported yet; flatten the model into one "
                     "<model> of links and joints");
  }
  SdfTree tree;
  for (uint64_t k = 0; k < model.JointCount(); ++k) {
    const sdf::Joint* joint = model.JointByIndex(k);
    SdfJointOutline info{joint, joint->ParentLinkName(), joint->ChildLinkName(),
                         file.Where(joint->Element())};
    for (const std::string* link : {&info.parent, &info.child}) {
      if (*link != kSdfWorld && model.LinkByName(*link) == nullptr) {
        throw InputError(info.where + ": joint '" + joint->Name() + "': link '" + *link +
                         "' is not a link of model '" + model.Name() +
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
    tree.joints.push_back(std::move(info));
  }
  std::map<std::string, bool> reached{{kSdfWorld, true}};
  std::deque<std::string> queue{kSdfWorld};
  std::vector<bool> cut(tree.joints.size(), false);
  while (!queue.empty()) {
    const std::string link = queue.front();
    queue.pop_front();
    for (size_t j = 0; j < tree.joints.size(); ++j) {
      const SdfJointOutline& info = tree.joints[j];
      if (info.parent != link) continue;
      if (reached[info.child]) {
        cut[j] = true;
        continue;
      }
      reached[info.child] = true;
      tree.tree.push_back(j);
      queue.push_back(info.child);
    }
  }
  for (uint64_t k = 0; k < model.LinkCount(); ++k) {
    const sdf::Link* link = model.LinkByIndex(k);
    if (!reached[link->Name()]) {
      throw InputError(file.Where(link->Element()) + ": link '" + link->Name() +
                       "' is not reached from the world through parent-to-child joints (a "
                       "floating link); attach it, e.g. with a fixed joint whose parent is "
                       "world");
    }
  }
  for (size_t j = 0; j < tree.joints.size(); ++j) {
    const SdfJointOutline& info = tree.joints[j];
    if (!reached[info.parent]) {
      throw InputError(info.where + ": joint '" + info.joint->Name() + "': its parent link '" +
                       info.parent + "' is not reached from the world; attach it");
    }
    if (cut[j]) tree.cut.push_back(j);
  }
  return tree;
}

std::string SdfBallAxisName(const std::string& joint, int axis) {
  MBSTREAM_CHECK(axis >= 0 && axis < 3);
  static constexpr const char* kSuffix[3] = {".x", ".y", ".z"};
  return joint + kSuffix[axis];
}

Eigen::Isometry3d ModelFramePose(const sdf::SemanticPose& pose, const std::string& what,
                                 const std::string& where) {
  ignition::math::Pose3d resolved;
  const sdf::Errors errors = pose.Resolve(resolved, "__model__");
  if (!errors.empty()) {
    throw InputError(where + ": " + what + ": its pose cannot be resolved: \"" +
                     errors.front().Message() + "\"; check its relative_to frame");
  }
  return ToIsometry(resolved);
}

std::vector<SdfLinkFrame> SdfLinkFrames(const SdfFile& file, const SdfTree& tree) {
  std::vector<SdfLinkFrame> frames;
  for (const size_t j : tree.tree) {
    const SdfJointOutline& info = tree.joints[j];
    SdfLinkFrame frame;
    frame.link = info.child;
    if (info.joint->Type() == sdf::JointType::FIXED) {
      const sdf::Link& link = *file.model().LinkByName(info.child);
      frame.X_ML = ModelFramePose(link.SemanticPose(), "link '" + link.Name() + "'",
                                  file.Where(link.Element()));
    } else {
      frame.X_ML = ModelFramePose(info.joint->SemanticPose(), "joint '" + info.joint->Name() + "'",
                                  info.where);
    }
    frames.push_back(std::move(frame));
  }
  return frames;
}

Eigen::Vector3d SdfJointAxis(const SdfFile& file, const SdfJointOutline& joint,
                             const Eigen::Isometry3d& X_MJ) {
  const sdf::JointAxis* axis = joint.joint->Axis(0);
  if (axis == nullptr) {
    throw InputError(joint.where + ": joint '" + joint.joint->Name() +
                     "': no <axis>; give <axis><xyz>0 0 1</xyz></axis>");
  }
  ignition::math::Vector3d xyz;
  const sdf::Errors errors = axis->ResolveXyz(xyz, "__model__");
  if (!errors.empty()) ThrowSdfErrors(file.source(), errors);
  const Eigen::Vector3d a = X_MJ.linear().transpose() * Eigen::Vector3d(xyz.X(), xyz.Y(), xyz.Z());
  if (!(a.norm() > 1e-12)) {
    throw InputError(joint.where + ": joint '" + joint.joint->Name() +
                     "': the axis is zero; give a unit vector");
  }
  return a.normalized();
}

std::vector<SdfVisual> SdfVisuals(const SdfFile& file, std::vector<std::string>* warnings) {
  std::vector<SdfVisual> visuals;
  const sdf::Model& model = file.model();
  for (uint64_t l = 0; l < model.LinkCount(); ++l) {
    const sdf::Link& link = *model.LinkByIndex(l);
    for (uint64_t v = 0; v < link.VisualCount(); ++v) {
      const sdf::Visual& visual = *link.VisualByIndex(v);
      SdfVisual out;
      out.link = link.Name();
      out.name = visual.Name();
      out.where = file.Where(visual.Element());
      const sdf::Geometry* geometry = visual.Geom();
      const sdf::GeometryType type =
          geometry == nullptr ? sdf::GeometryType::EMPTY : geometry->Type();
      if (type == sdf::GeometryType::BOX && geometry->BoxShape() != nullptr) {
        const ignition::math::Vector3d& size = geometry->BoxShape()->Size();
        out.geometry = SdfBox{Eigen::Vector3d(size.X(), size.Y(), size.Z())};
      } else if (type == sdf::GeometryType::CYLINDER && geometry->CylinderShape() != nullptr) {
        out.geometry =
            SdfCylinder{geometry->CylinderShape()->Radius(), geometry->CylinderShape()->Length()};
      } else if (type == sdf::GeometryType::SPHERE && geometry->SphereShape() != nullptr) {
        out.geometry = SdfSphere{geometry->SphereShape()->Radius()};
      } else if (type == sdf::GeometryType::MESH && geometry->MeshShape() != nullptr) {
        const ignition::math::Vector3d& scale = geometry->MeshShape()->Scale();
        out.geometry =
            SdfMesh{geometry->MeshShape()->Uri(), Eigen::Vector3d(scale.X(), scale.Y(), scale.Z())};
      } else {
        if (warnings != nullptr) {
          warnings->push_back(out.where + ": link '" + link.Name() + "': visual '" + visual.Name() +
                              "': its geometry is not drawn (box, cylinder, sphere and mesh "
                              "are); use one of those");
        }
        continue;
      }
      out.X_MV = ModelFramePose(visual.SemanticPose(), "visual '" + visual.Name() + "'", out.where);
      if (const sdf::Material* material = visual.Material(); material != nullptr) {
        out.diffuse = Colour(*material, "diffuse", material->Diffuse());
        out.ambient = Colour(*material, "ambient", material->Ambient());
      }
      visuals.push_back(std::move(out));
    }
  }
  return visuals;
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

SdfMeshes ReadSdfMeshes(const std::string& text) {
  // Hostile text never reaches libsdformat (a flood of attributes takes it minutes).
  XmlShapeLimits limits;
  limits.links_at_any_depth = true;
  limits.refused_element = "include";
  if (CheckXmlShape(text, limits)) return {};
  sdf::Console::Instance()->SetQuiet(true);
  sdf::Root root;
  if (!root.LoadSdfString(text).empty()) return {};
  const sdf::Model* model = root.Model();
  if (model == nullptr && root.WorldCount() == 1 && root.WorldByIndex(0)->ModelCount() == 1) {
    model = root.WorldByIndex(0)->ModelByIndex(0);
  }
  return model == nullptr ? SdfMeshes{} : MeshesOf(*model);
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

}  // namespace mbstream::urdf_reading
