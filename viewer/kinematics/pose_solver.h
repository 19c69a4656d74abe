// Joint values -> every frame and every probe, into storage allocated once.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "viewer/kinematics/kinematic_chain.h"
#include "viewer/kinematics/probe_point.h"

namespace mbstream::viewer {

// One evaluated pose.
struct Pose {
  std::vector<double> q;                      // joint values, SI
  std::vector<Eigen::Isometry3d> frames;      // every frame in World
  std::vector<Eigen::Vector3d> probes;        // each probe in its refer frame, m
  std::vector<Eigen::Vector3d> probes_world;  // each probe in World, m
};

class PoseSolver {
 public:
  PoseSolver(KinematicChain chain, std::vector<ProbePoint> probes);

  const KinematicChain& chain() const { return chain_; }
  const std::vector<ProbePoint>& probes() const { return probes_; }
  int dof() const { return chain_.dof(); }

  // A Pose with its storage sized for this chain (all frames at q = 0).
  Pose MakePose() const;
  // Fills `pose` for `q` (size dof()); allocates nothing when `pose` came from MakePose.
  // Throws InputError naming both counts when q has the wrong size.
  void Solve(std::span<const double> q, Pose* pose) const;

 private:
  KinematicChain chain_;
  std::vector<ProbePoint> probes_;
};

}  // namespace mbstream::viewer
