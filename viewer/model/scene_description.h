// What a scene shows, independent of VTK: the kinematic chain, the visual parts attached to
// its frames, the probes and the camera box. Built from a translated scene script or from
// a URDF's visual elements; the VTK scene is built from it.
#pragma once

#include <filesystem>
#include <memory>
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

// A mesh file (STL, Collada, OBJ, glTF/GLB, PLY, ...), read by the VTK scene with Assimp.
struct MeshFile {
  std::filesystem::path path;
  // The file's own material colours (per sub-mesh) win over VisualPart::color, which then
  // colours only sub-meshes without one.
  bool file_colours = false;
};

struct VisualPart {
  std::string name;
  std::variant<Mesh, MeshFile> geometry;
  // geometry coordinates * scale, then placed by `placement` in `frame` (metres).
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  int frame = kWorldFrame;  // frame number, or kWorldFrame for a static part
  Eigen::Vector3d color = Eigen::Vector3d::Constant(0.7);
  double opacity = 1.0;
  std::string mesh_filename;  // a URDF mesh's filename as written (also for its placeholder)
  // A box standing for a mesh that is missing or unreadable (mesh_filename names it): drawn
  // tinted (kPlaceholderColour, kPlaceholderOpacity) and counted on one HUD line.
  bool placeholder = false;
  // Drawn instead when the mesh file cannot be read (a URDF link's placeholder box).
  std::shared_ptr<const VisualPart> fallback;
};

// How a placeholder looks: a muted orange, see-through, so that the robot stays readable.
inline const Eigen::Vector3d kPlaceholderColour(0.85, 0.55, 0.3);
inline constexpr double kPlaceholderOpacity = 0.55;

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
  // True when the chain's joint names are the model's (a URDF scene): the joint values
  // are then ordered by the names the server sends (KinematicChain::OrderJointValuesBy).
  bool joints_named_as_model = false;
  std::vector<std::string> warnings;  // what the scene draws differently from the model
};

// Joint values in script units (degrees for revolute, mm for prismatic joints) to SI.
// Throws InputError when the count differs from chain.dof().
std::vector<double> ScriptUnitsToSi(const KinematicChain& chain, std::span<const double> values);

}  // namespace mbstream::viewer
