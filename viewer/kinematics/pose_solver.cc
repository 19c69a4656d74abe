#include "viewer/kinematics/pose_solver.h"

#include <algorithm>
#include <stdexcept>

#include "shared/common/check.h"

namespace mbstream::viewer {

PoseSolver::PoseSolver(KinematicChain chain, std::vector<ProbePoint> probes)
    : chain_(std::move(chain)), probes_(std::move(probes)) {
  for (const ProbePoint& probe : probes_) {
    for (int frame : {probe.frame, probe.refer}) {
      if (frame < kWorldFrame || frame >= chain_.frame_count()) {
        throw InputError("probe '" + probe.name + "' uses frame " + std::to_string(frame) +
                         ", which the chain does not have");
      }
    }
  }
}

Pose PoseSolver::MakePose() const {
  Pose pose;
  pose.q.assign(chain_.dof(), 0.0);
  pose.frames.assign(chain_.frame_count(), Eigen::Isometry3d::Identity());
  pose.probes.assign(probes_.size(), Eigen::Vector3d::Zero());
  pose.probes_world.assign(probes_.size(), Eigen::Vector3d::Zero());
  Solve(pose.q, &pose);
  return pose;
}

void PoseSolver::Solve(std::span<const double> q, Pose* pose) const {
  if (static_cast<int>(q.size()) != chain_.dof()) {
    throw InputError("the scene has " + std::to_string(chain_.dof()) + " joints but " +
                     std::to_string(q.size()) + " joint values were given");
  }
  if (pose->q.size() != q.size() || pose->frames.size() != size_t(chain_.frame_count()) ||
      pose->probes.size() != probes_.size() || pose->probes_world.size() != probes_.size()) {
    *pose = MakePose();
  }
  std::copy(q.begin(), q.end(), pose->q.begin());
  chain_.Compute(q, pose->frames);
  for (size_t i = 0; i < probes_.size(); ++i) {
    pose->probes_world[i] = ProbeInWorld(probes_[i], pose->frames);
    pose->probes[i] = ProbeInRefer(probes_[i], pose->frames);
  }
}

}  // namespace mbstream::viewer
