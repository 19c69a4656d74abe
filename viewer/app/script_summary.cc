#include "viewer/app/script_summary.h"

#include <map>
#include <sstream>

#include "viewer/model/script_scene.h"
#include "viewer/script/device_frames.h"
#include "viewer/script/diagnostics.h"

namespace mbstream::viewer {

namespace {

namespace ss = scene_script;

std::string Vector(const Eigen::Vector3d& v) {
  return "(" + ss::FormatNumber(v.x()) + ", " + ss::FormatNumber(v.y()) + ", " +
         ss::FormatNumber(v.z()) + ")";
}

}  // namespace

std::string ScriptSummary(const std::string& file, const ss::Script& script) {
  std::ostringstream out;
  const SceneDescription scene = SceneFromScript(script);
  out << file << ": ok\n";
  if (script.device) {
    const ss::DeviceCommand& device = *script.device;
    int revolute = 0;
    for (const auto& joint : device.joints) revolute += joint.type == ss::JointType::kRevolute;
    out << "device " << device.name << ": " << device.joints.size() << " joints (" << revolute
        << " revolute, " << device.joints.size() - revolute << " prismatic)";
    if (device.lbox_mm) out << ", LBox " << ss::FormatNumber(*device.lbox_mm) << " mm";
    if (device.tcp) {
      out << ", TCP on " << ss::DeviceFrameName(device, device.tcp_frame) << " at "
          << Vector(device.tcp->shift_mm) << " mm";
    }
    out << "\n";
  } else {
    out << "device: none (a static scene)\n";
  }
  std::map<int, int> per_frame;
  for (const VisualPart& visual : scene.visuals) ++per_frame[visual.frame];
  out << "links:";
  for (int k = 0; k < static_cast<int>(scene.frame_names.size()); ++k) {
    out << (k ? ", " : " ") << scene.frame_names[k] << " " << per_frame[k] << " parts";
  }
  if (per_frame.contains(kWorldFrame)) out << ", World " << per_frame[kWorldFrame] << " parts";
  out << "\n";
  std::map<std::string, int> kinds;
  for (const ss::PartCommand& part : script.parts) ++kinds[part.keyword];
  out << "parts: " << script.parts.size() << " defined (";
  bool first = true;
  for (const auto& [kind, count] : kinds) {
    out << (first ? "" : ", ") << kind << " " << count;
    first = false;
  }
  out << "), " << scene.visuals.size() << " shown, " << script.sets.size() << " sets\n";
  out << "probes:";
  if (script.probes.empty()) out << " none";
  for (size_t i = 0; i < script.probes.size(); ++i) {
    const ss::ProbeCommand& probe = script.probes[i];
    out << (i ? ", " : " ") << probe.name << " on " << probe.frame_in << " at "
        << Vector(probe.offset.shift_mm) << " mm, reported in " << probe.refer;
  }
  out << "\n";
  return out.str();
}

}  // namespace mbstream::viewer
