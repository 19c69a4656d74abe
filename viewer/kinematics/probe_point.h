// A probe: a point fixed in one frame, reported in another (seed's `Probe` command).
#pragma once

#include <span>
#include <string>

#include <Eigen/Geometry>

namespace mbstream::viewer {

inline constexpr int kWorldFrame = -1;

struct ProbePoint {
  std::string name;
  int frame = 0;                                    // frame number, or kWorldFrame
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // in `frame`, metres
  int refer = kWorldFrame;                          // frame to report in
  std::string refer_name = "World";                 // as reported
};

// The probe in World and in its refer frame, given every frame in World.
Eigen::Vector3d ProbeInWorld(const ProbePoint& probe, std::span<const Eigen::Isometry3d> frames);
Eigen::Vector3d ProbeInRefer(const ProbePoint& probe, std::span<const Eigen::Isometry3d> frames);

}  // namespace mbstream::viewer
