// What the viewer answers for each probe: its coordinates in its Refer frame, metres.
#pragma once

#include <string>

#include <Eigen/Core>

namespace mbstream::viewer {

struct ProbeReport {
  std::string name;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  std::string frame;  // the Refer frame: "World", the device base or "Device#k"
};

}  // namespace mbstream::viewer
