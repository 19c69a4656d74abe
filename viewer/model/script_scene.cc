#include "viewer/model/script_scene.h"

#include <set>

#include "viewer/model/shape_mesh.h"
#include "viewer/script/device_frames.h"
#include "viewer/script/token_stream.h"

namespace mbstream::viewer {

namespace {

namespace ss = scene_script;

constexpr double kMetresPerMm = 0.001;

Mesh MeshOf(const ss::Shape& shape) {
  struct Visitor {
    Mesh operator()(const ss::CylinderShape& s) const { return CylinderMesh(s); }
    Mesh operator()(const ss::ConeShape& s) const { return ConeMesh(s); }
    Mesh operator()(const ss::CubeShape& s) const { return CubeMesh(s); }
    Mesh operator()(const ss::SphereShape& s) const { return SphereMesh(s); }
    Mesh operator()(const ss::PolyprismShape& s) const { return PolyprismMesh(s); }
    Mesh operator()(const ss::ModuleShape& s) const { return ModuleMesh(s); }
    Mesh operator()(const ss::StlShape&) const { return {}; }
  };
  return std::visit(Visitor{}, shape);
}

class VisualCollector {
 public:
  VisualCollector(const ss::Script& script, std::vector<VisualPart>* out)
      : script_(script), out_(out) {}

  // Adds component `name` (a part or an assembly) placed by `placement` in `frame`.
  void Add(const std::string& name, const Eigen::Isometry3d& placement, int frame,
           std::vector<const ss::RenderCommand*> renders) {
    renders.push_back(script_.FindRender(name));
    if (const ss::PartCommand* part = script_.FindPart(name)) {
      VisualPart visual;
      visual.name = name;
      if (const auto* stl = std::get_if<ss::StlShape>(&part->shape)) {
        visual.geometry = MeshFile{stl->resolved_path};
      } else {
        visual.geometry = MeshOf(part->shape);
      }
      visual.scale = Eigen::Vector3d::Constant(kMetresPerMm);
      visual.placement = placement;
      visual.frame = frame;
      for (auto it = renders.rbegin(); it != renders.rend(); ++it) {
        if (*it) {
          visual.color = (*it)->color;
          break;
        }
      }
      out_->push_back(std::move(visual));
      return;
    }
    if (const ss::SetCommand* set = script_.FindSet(name)) {
      for (const ss::Component& component : set->components) {
        Add(component.name, placement * component.placement.ToIsometry(kMetresPerMm), frame,
            renders);
      }
    }
  }

 private:
  const ss::Script& script_;
  std::vector<VisualPart>* out_;
};

int FrameOf(const ss::Script& script, const std::string& name) {
  if (ss::EqualsIgnoreCase(name, "World") || !script.device) return kWorldFrame;
  return ss::DeviceFrameNumber(*script.device, name).value_or(kWorldFrame);
}

}  // namespace

KinematicChain ChainFromDevice(const ss::DeviceCommand& device) {
  std::vector<ChainJoint> joints;
  for (const ss::JointDeclaration& declaration : device.joints) {
    ChainJoint joint;
    joint.name = ss::DeviceFrameName(device, declaration.number);
    joint.parent = declaration.parent;
    joint.pre = declaration.pre.ToIsometry(kMetresPerMm);
    joint.kind = declaration.type == ss::JointType::kRevolute ? ChainJointKind::kRevolute
                                                              : ChainJointKind::kPrismatic;
    joint.axis = Eigen::Vector3d::Unit(declaration.axis);
    joint.post = declaration.post.ToIsometry(kMetresPerMm);
    joints.push_back(std::move(joint));
  }
  return KinematicChain(device.placement.ToIsometry(kMetresPerMm), std::move(joints));
}

SceneDescription SceneFromScript(const ss::Script& script) {
  SceneDescription scene;
  if (script.device) {
    const ss::DeviceCommand& device = *script.device;
    scene.title = device.name;
    scene.chain = ChainFromDevice(device);
    scene.frame_names = ss::DeviceFrameNames(device);
    if (device.lbox_mm) scene.scene_box_m = *device.lbox_mm * kMetresPerMm;
    if (device.tcp) {
      scene.tcp = device.tcp->ToIsometry(kMetresPerMm);
      scene.tcp_frame = device.tcp_frame;
    }
    const std::vector<double> zeros(device.joints.size(), 0.0);
    scene.initial_q = ScriptUnitsToSi(
        scene.chain, device.initial && device.initial->size() == device.joints.size()
                         ? std::span<const double>(*device.initial)
                         : std::span<const double>(zeros));
  } else {
    scene.title = "scene";
    scene.frame_names = {"base"};
  }

  VisualCollector collector(script, &scene.visuals);
  std::set<std::string> components;
  for (const ss::SetCommand& set : script.sets) {
    for (const ss::Component& component : set.components) components.insert(component.name);
  }
  for (const ss::SetCommand& set : script.sets) {
    const int frame = FrameOf(script, set.name);
    if (frame != kWorldFrame) {
      collector.Add(set.name, Eigen::Isometry3d::Identity(), frame, {});
    }
  }
  std::set<std::string> shown;
  for (const ss::RenderCommand& render : script.renders) {
    const bool link = FrameOf(script, render.target) != kWorldFrame;
    if (link || components.contains(render.target) || !shown.insert(render.target).second) {
      continue;
    }
    collector.Add(render.target, Eigen::Isometry3d::Identity(), kWorldFrame, {});
  }

  for (const ss::ProbeCommand& command : script.probes) {
    ProbePoint probe;
    probe.name = command.name;
    probe.frame = FrameOf(script, command.frame_in);
    probe.point = command.offset.ToIsometry(kMetresPerMm).translation();
    probe.refer = FrameOf(script, command.refer);
    probe.refer_name = probe.refer == kWorldFrame ? "World" : scene.frame_names[probe.refer];
    scene.probes.push_back(std::move(probe));
  }
  return scene;
}

}  // namespace mbstream::viewer
