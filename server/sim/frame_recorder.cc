#include "server/sim/frame_recorder.h"

#include <algorithm>
#include <cmath>

#include "server/dynamics/energy.h"
#include "server/kinematics/forward_kinematics.h"

namespace mbstream {

FrameRecorder::FrameRecorder(const Model& model, const DriveSet& drives, RunResult& result,
                             size_t frames, bool track_tcp_error, bool latest_only)
    : model_(model),
      drives_(drives),
      result_(result),
      data_(model),
      q_ref_(model.num_dofs()),
      track_tcp_error_(track_tcp_error && drives.all_prescribed() && model.tcp_frame >= 0 &&
                       !model.has_quaternions()),
      latest_only_(latest_only) {
  const size_t n = static_cast<size_t>(model.num_dofs());
  if (latest_only_) frames = 1;
  result_.t.reserve(frames);
  result_.q.reserve(frames * static_cast<size_t>(model.nq()));
  result_.qd.reserve(frames * n);
  result_.tcp.reserve(frames * 3);
  if (result_.has_torques) result_.tau.reserve(frames * n);
  if (result_.has_energy) {
    result_.kinetic.reserve(frames);
    result_.potential.reserve(frames);
  }
  if (drives_.all_prescribed()) result_.stats.tcp_error_max = 0.0;
  if (result_.has_energy) {
    result_.stats.energy_error_max = 0.0;
    result_.stats.energy_work_approximate = drives_.any_work();
    if (drives_.any_work()) result_.stats.energy_quadrature_error_max = 0.0;
    result_.stats.energy_work = drives_.any_work() ? kEnergyWorkTrapezoid : kEnergyWorkNone;
  }
}

void FrameRecorder::UseIntegratedWork() {
  integrated_work_ = true;
  result_.work.reserve(result_.t.capacity());
  result_.stats.energy_work_approximate = false;
  result_.stats.energy_quadrature_error_max = -1.0;
  result_.stats.energy_work = kEnergyWorkIntegrated;
}

void FrameRecorder::AppendLoopForces(const Eigen::VectorXd* forces) {
  loop_forces_ = forces;
  result_.loop_forces.reserve(result_.t.capacity() * static_cast<size_t>(forces->size()));
}

void FrameRecorder::AppendLoopCoordinates(LoopCoordinates* coordinates) {
  loop_coordinates_ = coordinates;
  const Eigen::Index m = coordinates->size();
  loop_value_ = Eigen::VectorXd::Zero(m);
  loop_rate_ = Eigen::VectorXd::Zero(m);
  loop_effort_ = Eigen::VectorXd::Zero(m);
  const size_t frames = result_.t.capacity();
  const size_t width = static_cast<size_t>(model_.num_dofs() + m);
  result_.q.reserve(frames * width);
  result_.qd.reserve(frames * width);
  if (result_.has_torques) result_.tau.reserve(frames * width);
}

bool FrameRecorder::Record(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                           const Eigen::VectorXd* effort, const FrameExtras* extras) {
  if (!q.allFinite() || !qd.allFinite() || (effort && !effort->allFinite())) return false;
  Vector3d tcp = Vector3d::Zero();
  double kinetic = 0.0, potential = 0.0;
  if (extras != nullptr) {
    tcp = extras->tcp;
    kinetic = extras->kinetic;
    potential = extras->potential;
    if (!tcp.allFinite() || !std::isfinite(kinetic) || !std::isfinite(potential)) return false;
  } else {
    // One pass of kinematics (the bodies' poses; the TCP alone of the frames) serves the
    // TCP and both energies.
    BodyKinematics(model_, data_, q);
    if (model_.tcp_frame >= 0) tcp = FramePositionFromBodies(model_, data_, model_.tcp_frame);
    if (result_.has_energy) {
      potential = PotentialEnergy(model_, data_);
      kinetic = KineticEnergyAfterKinematics(model_, data_, qd);
      if (!std::isfinite(kinetic) || !std::isfinite(potential)) return false;
    }
  }
  if (loop_coordinates_ != nullptr) {
    loop_coordinates_->Compute(q, qd, &loop_value_, &loop_rate_);
    if (!loop_value_.allFinite() || !loop_rate_.allFinite()) return false;
  }
  if (loop_forces_ != nullptr && !loop_forces_->allFinite()) return false;
  if (latest_only_ && !result_.t.empty()) {  // drop the previous frame (capacity stays)
    ++result_.first_seq;
    result_.t.clear();
    result_.q.clear();
    result_.qd.clear();
    result_.tcp.clear();
    result_.tau.clear();
    result_.kinetic.clear();
    result_.potential.clear();
    result_.work.clear();
    result_.loop_forces.clear();
  }
  result_.t.push_back(t);
  result_.q.insert(result_.q.end(), q.data(), q.data() + q.size());
  result_.qd.insert(result_.qd.end(), qd.data(), qd.data() + qd.size());
  result_.tcp.insert(result_.tcp.end(), tcp.data(), tcp.data() + 3);
  if (result_.has_torques) {
    result_.tau.insert(result_.tau.end(), effort->data(), effort->data() + effort->size());
  }
  if (loop_coordinates_ != nullptr) {
    const Eigen::Index m = loop_value_.size();
    result_.q.insert(result_.q.end(), loop_value_.data(), loop_value_.data() + m);
    result_.qd.insert(result_.qd.end(), loop_rate_.data(), loop_rate_.data() + m);
    if (result_.has_torques) {
      result_.tau.insert(result_.tau.end(), loop_effort_.data(), loop_effort_.data() + m);
    }
  }
  if (loop_forces_ != nullptr) {
    result_.loop_forces.insert(result_.loop_forces.end(), loop_forces_->data(),
                               loop_forces_->data() + loop_forces_->size());
  }
  if (result_.has_energy) {
    result_.kinetic.push_back(kinetic);
    result_.potential.push_back(potential);
    TrackEnergy(t, kinetic + potential, qd, effort);
    if (integrated_work_) result_.work.push_back(work_);
  }
  if (track_tcp_error_) TrackTcpError(t, tcp);
  result_.stats.t_reached = t;
  return true;
}

// |E(t) - E(0) - W(t)| relative to the energy scale, W = work of drives and damping
// (integrated with the ODE, or the trapezoid rule over the output samples).
void FrameRecorder::TrackEnergy(double t, double energy, const Eigen::VectorXd& qd,
                                const Eigen::VectorXd* effort) {
  double power = constraint_power_;
  for (int i = 0; i < drives_.size(); ++i) {
    const double drive = effort ? (*effort)(i) : 0.0;
    power += (drive - drives_.damping(i) * qd(i)) * qd(i);
  }
  bool compare = false;  // the coarse rule has reached this frame too
  if (result_.first_seq == 0 && result_.t.size() == 1) {
    energy0_ = energy;
    energy_frames_ = 0;
    coarse_work_ = 0.0;
    if (integrated_work_) work_ = 0.0;
  } else if (!integrated_work_) {
    work_ += 0.5 * (power + last_power_) * (t - last_t_);
    ++energy_frames_;
    if (energy_frames_ % 2 == 0) {
      coarse_work_ += 0.5 * (power + power2_) * (t - t2_);
      compare = true;
    }
  }
  if (energy_frames_ % 2 == 0) {  // this frame starts the coarse rule's next interval
    power2_ = power;
    t2_ = t;
  }
  last_power_ = power;
  last_t_ = t;
  scale_ = std::max({scale_, std::abs(energy0_), std::abs(energy)});
  if (compare && result_.stats.energy_quadrature_error_max >= 0.0) {
    const double estimate = std::abs(work_ - coarse_work_) / 3.0 / std::max(scale_, 1e-300);
    result_.stats.energy_quadrature_error_max =
        std::max(result_.stats.energy_quadrature_error_max, estimate);
  }
  const double error = std::abs(energy - energy0_ - work_) / std::max(scale_, 1e-300);
  result_.stats.energy_error_max = std::max(result_.stats.energy_error_max, error);
}

void FrameRecorder::TrackTcpError(double t, const Vector3d& tcp) {
  for (int i = 0; i < drives_.size(); ++i) q_ref_(i) = drives_.Reference(i, t).q;
  BodyKinematics(model_, data_, q_ref_);
  const double error = (tcp - FramePositionFromBodies(model_, data_, model_.tcp_frame)).norm();
  result_.stats.tcp_error_max = std::max(result_.stats.tcp_error_max, error);
}

}  // namespace mbstream
