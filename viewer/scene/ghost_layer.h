// A translucent second copy of a scene's mechanism, posed on its own: the other run of a
// comparison (mbstream-viewer --run A --compare B). Same parts and colours as the scene,
// drawn see-through and slightly tinted, in the same renderer.
//
// Like Scene, two sides: SetJointValues (any thread, no VTK, no allocation) and SyncActors
// (the render thread that built it).
#pragma once

#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include <vtkActor.h>
#include <vtkMatrix4x4.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include "viewer/kinematics/pose_solver.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

class GhostLayer {
 public:
  // Builds the ghost's actors into `renderer` with `opacity` (0..1). A part whose mesh file
  // cannot be read is drawn as its fallback, or left out (the scene already said why).
  GhostLayer(const SceneDescription& description, vtkRenderer* renderer, double opacity);

  // ---- pose side: thread-safe. q in SI, the chain's joint order; throws
  // InputError (shared/common/check.h) on a wrong count.
  void SetJointValues(std::span<const double> q_si);
  // Every frame of the newest pose, in World.
  std::vector<Eigen::Isometry3d> Frames() const;
  std::uint64_t pose_version() const;

  // ---- render side.
  void SyncActors();
  int actor_count() const { return static_cast<int>(actors_.size()); }
  double opacity() const { return opacity_; }

 private:
  PoseSolver solver_;
  const double opacity_;
  mutable std::mutex mutex_;  // guards pose_ and version_
  Pose pose_;
  std::uint64_t version_ = 0;
  // Render side only.
  Pose render_pose_;
  std::uint64_t applied_version_ = ~std::uint64_t{0};
  std::vector<vtkSmartPointer<vtkMatrix4x4>> frame_matrices_;
  std::vector<vtkSmartPointer<vtkActor>> actors_;
};

}  // namespace mbstream::viewer
