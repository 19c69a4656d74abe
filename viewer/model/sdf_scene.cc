#include "viewer/model/sdf_scene.h"

#include <map>

#include <sdf/Joint.hh>

#include "shared/common/check.h"
#include "shared/model_files/sdf_reading.h"
#include "viewer/model/shape_mesh.h"

namespace mbstream::viewer {

namespace {

namespace mf = model_files;

constexpr int kResolution = 32;
constexpr double kPlaceholderEdge = 0.05;  // m

ChainJointKind KindOf(const sdf::Joint& joint) {
  switch (joint.Type()) {
    case sdf::JointType::PRISMATIC:
      return ChainJointKind::kPrismatic;
    case sdf::JointType::FIXED:
      return ChainJointKind::kFixed;
    case sdf::JointType::BALL:
      return ChainJointKind::kBall;
    default:  // revolute, continuous
      return ChainJointKind::kRevolute;
  }
}

// A scoped name's last part: "tool0" of "irb1600::tool0".
std::string LocalName(const std::string& name) {
  const size_t scope = name.rfind(mf::kSdfScope);
  return scope == std::string::npos ? name : name.substr(scope + 2);
}

bool IsTcpName(std::string name) {
  for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name == "tcp" || name == "tool0";
}

// The part that draws `visual` in link frame `frame` (placed at X_LV in it).
VisualPart PartOf(const mf::SdfVisual& visual, int frame, const Eigen::Isometry3d& X_LV,
                  const MeshFinder& find_mesh, std::vector<std::string>* warnings) {
  VisualPart part;
  part.name = visual.link;
  part.frame = frame;
  part.placement = X_LV;
  const std::optional<Eigen::Vector3d> colour = visual.diffuse ? visual.diffuse : visual.ambient;
  if (colour) part.color = *colour;
  if (const auto* box = std::get_if<mf::SdfBox>(&visual.geometry)) {
    part.geometry = CubeMesh({box->size});
    part.placement = part.placement * Eigen::Translation3d(-box->size / 2);
  } else if (const auto* cylinder = std::get_if<mf::SdfCylinder>(&visual.geometry)) {
    part.geometry = CylinderMesh({2 * cylinder->radius, kResolution, cylinder->length});
    part.placement = part.placement * Eigen::Translation3d(0, 0, -cylinder->length / 2);
  } else if (const auto* sphere = std::get_if<mf::SdfSphere>(&visual.geometry)) {
    part.geometry = SphereMesh({sphere->radius, kResolution});
  } else {
    const auto& mesh = std::get<mf::SdfMesh>(visual.geometry);
    part.mesh_filename = mesh.uri;
    VisualPart placeholder = part;
    const Eigen::Vector3d edge = Eigen::Vector3d::Constant(kPlaceholderEdge);
    placeholder.geometry = CubeMesh({edge});
    placeholder.placement = X_LV * Eigen::Translation3d(-edge / 2);
    placeholder.color = kPlaceholderColour;
    placeholder.opacity = kPlaceholderOpacity;
    placeholder.placeholder = true;
    const std::filesystem::path path = find_mesh(mesh.uri);
    if (path.empty()) {
      warnings->push_back(visual.where + ": link '" + visual.link + "': mesh '" + mesh.uri +
                          "' is not found; drawn as a placeholder cube (give --package-path "
                          "DIR, or submit the model with its meshes)");
      return placeholder;
    }
    part.geometry = MeshFile{path, !colour};
    part.scale = mesh.scale;
    part.fallback = std::make_shared<const VisualPart>(std::move(placeholder));
  }
  return part;
}

// The chain joint of a tree joint.
ChainJointKind KindOf(const mf::SdfJointOutline& outline) {
  switch (outline.role) {
    case mf::SdfJointRole::kFree:
      return ChainJointKind::kFree;
    case mf::SdfJointRole::kWeld:
      return ChainJointKind::kFixed;
    default:
      return KindOf(*outline.joint);
  }
}

// A free joint's seven values holding its link at X_WL: x y z, qw qx qy qz.
void AppendFreeValues(const Eigen::Isometry3d& X_WL, std::vector<double>* q) {
  const Eigen::Quaterniond rotation(X_WL.linear());
  const Eigen::Vector3d& p = X_WL.translation();
  q->insert(q->end(),
            {p.x(), p.y(), p.z(), rotation.w(), rotation.x(), rotation.y(), rotation.z()});
}

}  // namespace

SceneDescription SceneFromSdf(const std::string& text, const std::string& source,
                              const MeshFinder& find_mesh,
                              const std::optional<mf::SdfIncludePath>& includes) {
  const mf::SdfFile file(text, source, {.includes = includes});
  const mf::SdfTree tree = mf::ChooseSdfTree(file);
  const std::vector<mf::SdfLinkFrame> frames = mf::SdfLinkFrames(file, tree);

  SceneDescription scene;
  scene.title = file.title();
  scene.joints_named_as_model = true;
  scene.warnings = tree.warnings;
  std::map<std::string, int> frame_of{{mf::kSdfWorld, 0}};
  std::map<std::string, Eigen::Isometry3d> X_WL{{mf::kSdfWorld, Eigen::Isometry3d::Identity()}};
  scene.frame_names.push_back(mf::kSdfWorld);
  std::vector<ChainJoint> joints;
  for (size_t k = 0; k < tree.tree.size(); ++k) {
    const mf::SdfJointOutline& outline = tree.joints[tree.tree[k]];
    const mf::SdfLinkFrame& frame = frames[k];
    ChainJoint joint;
    joint.name = outline.name;
    joint.parent = frame_of.at(outline.parent);
    joint.kind = KindOf(outline);
    // A free joint's values are its link's pose in the world (its parent), as the server's.
    joint.pre = joint.kind == ChainJointKind::kFree
                    ? Eigen::Isometry3d::Identity()
                    : Eigen::Isometry3d(X_WL.at(outline.parent).inverse() * frame.X_WL);
    if (joint.kind == ChainJointKind::kRevolute || joint.kind == ChainJointKind::kPrismatic) {
      joint.axis = mf::SdfJointAxis(file, outline, frame.X_WL);
    }
    if (joint.kind == ChainJointKind::kFree) {
      AppendFreeValues(frame.X_WL, &scene.initial_q);
    } else if (joint.kind == ChainJointKind::kBall) {  // the identity rotation: qw = 1
      scene.initial_q.insert(scene.initial_q.end(), {1.0, 0.0, 0.0, 0.0});
    } else if (joint.kind != ChainJointKind::kFixed) {
      scene.initial_q.push_back(0.0);
    }
    joints.push_back(std::move(joint));
    frame_of[frame.link] = static_cast<int>(joints.size());
    X_WL[frame.link] = frame.X_WL;
    scene.frame_names.push_back(frame.link);
  }
  scene.chain = KinematicChain(Eigen::Isometry3d::Identity(), std::move(joints));
  MBSTREAM_CHECK(static_cast<int>(scene.initial_q.size()) == scene.chain.dof());

  for (const mf::SdfVisual& visual : mf::SdfVisuals(file, &scene.warnings)) {
    const Eigen::Isometry3d X_LV = X_WL.at(visual.link).inverse() * visual.X_WV;
    scene.visuals.push_back(
        PartOf(visual, frame_of.at(visual.link), X_LV, find_mesh, &scene.warnings));
  }
  for (const std::string& name : scene.frame_names) {
    if (!IsTcpName(LocalName(name))) continue;
    ProbePoint probe;
    probe.name = "tcp";
    probe.frame = frame_of.at(name);
    probe.refer = 0;
    probe.refer_name = mf::kSdfWorld;
    scene.probes.push_back(probe);
    break;
  }
  return scene;
}

}  // namespace mbstream::viewer
