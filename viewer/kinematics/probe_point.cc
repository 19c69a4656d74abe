#include "viewer/kinematics/probe_point.h"

namespace mbstream::viewer {

Eigen::Vector3d ProbeInWorld(const ProbePoint& probe, std::span<const Eigen::Isometry3d> frames) {
  return probe.frame == kWorldFrame ? probe.point : frames[probe.frame] * probe.point;
}

Eigen::Vector3d ProbeInRefer(const ProbePoint& probe, std::span<const Eigen::Isometry3d> frames) {
  const Eigen::Vector3d world = ProbeInWorld(probe, frames);
  if (probe.refer == kWorldFrame) return world;
  const Eigen::Isometry3d& refer = frames[probe.refer];
  // Rigid inverse: R^T (p - t).
  return refer.linear().transpose() * (world - refer.translation());
}

}  // namespace mbstream::viewer
