// What a scene shows, independent of VTK: the kinematic chain, the visual parts attached to
// its frames, the probes and the camera box. Built from a translated scene script or from
// a URDF's visual elements; the VTK scene is built from it.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Geometry>

#include "viewer/kinematics/kinematic_chain.h"
#include "viewer/kinematics/probe_point.h"
#include "viewer/model/mesh.h"

namespace mbstream::viewer {

struct StlGeometry {
  std::filesystem::path path;
};

struct VisualPart {
  std::string name;
  std::variant<Mesh, StlGeometry> geometry;
  // geometry coordinates * scale, then placed by `placement` in `frame` (metres).
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  int frame = kWorldFrame;  // frame number, or kWorldFrame for a static part
  Eigen::Vector3d color = Eigen::Vector3d::Constant(0.7);
};

struct SceneDescription {
  std::string title;  // the device or robot name
  KinematicChain chain;
  std::vector<std::string> frame_names;  // frame_count() names: "IRB1600", "IRB1600#1", ...
  std::vector<ProbePoint> probes;
  std::vector<VisualPart> visuals;
  std::vector<double> initial_q;         // SI, dof() values
  std::optional<double> scene_box_m;     // the script's LBox: fixes the camera
  std::optional<Eigen::Isometry3d> tcp;  // in frame tcp_frame
  int tcp_frame = 0;
};

// Joint values in script units (degrees for revolute, mm for prismatic joints) to SI.
// Throws std::invalid_argument when the count differs from chain.dof().
std::vector<double> ScriptUnitsToSi(const KinematicChain& chain, std::span<const double> values);

}  // namespace mbstream::viewer
