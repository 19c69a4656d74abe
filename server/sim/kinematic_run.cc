#include "server/sim/kinematic_run.h"

#include <string>

#include "server/drives/pose_motion.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/quaternion.h"
#include "server/sim/frame_loop.h"
#include "server/sim/initial_state.h"

namespace mbstream {

namespace {

// The prescribed motion at each output time: nothing to advance. A free or ball joint takes
// its prescribed pose (pose_motion.h), the components without a drive held at their initial
// values.
class KinematicSource : public FrameSource {
 public:
  KinematicSource(const Model& model, const RunConfig& config, const DriveSet& drives)
      : model_(model),
        drives_(drives),
        want_torques_(config.want_torques),
        data_(model),
        q_(model.nq()),
        qd_(model.nv()),
        qdd_(model.nv()),
        effort_(model.nv()),
        held_(model.nv()) {
    held_.setZero();
    const Eigen::VectorXd y0 = InitialJointState(config, drives, model);
    for (const int b : drives.posed_bodies()) {
      const Body& body = model.bodies[static_cast<size_t>(b)];
      const double* q0 = y0.data() + body.q_index;
      double* held = held_.data() + body.v_index;
      if (body.free()) {
        for (int k = 0; k < 3; ++k) held[k] = q0[k];
        held_.segment<3>(body.v_index + 3) = pose_motion::Angles(quaternion::Rotation(q0 + 3));
      } else {
        held_.segment<3>(body.v_index) = pose_motion::Angles(quaternion::Rotation(q0));
      }
    }
  }

  bool Advance(const std::vector<double>& /*times*/, size_t /*k*/, RunStats* /*stats*/) override {
    return true;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    for (const Body& body : model_.bodies) {
      const int i = body.v_index;
      if (body.nv() == 1) {
        const TrajectoryPoint ref = drives_.Reference(i, t);
        q_(body.q_index) = ref.q;
        qd_(i) = ref.qd;
        qdd_(i) = ref.qdd;
        continue;
      }
      TrajectoryPoint c[kFreeNv];
      for (int k = 0; k < body.nv(); ++k) {
        c[k] = drives_.pose_hold(i + k) ? TrajectoryPoint{held_(i + k), 0.0, 0.0}
                                        : drives_.Reference(i + k, t);
      }
      double* q = q_.data() + body.q_index;
      if (body.free()) {
        pose_motion::FreeCoordinates(c, q, qd_.data() + i, qdd_.data() + i);
      } else {
        pose_motion::BallCoordinates(c, q, qd_.data() + i, qdd_.data() + i);
      }
    }
    if (want_torques_) {
      effort_ = Rnea(model_, data_, q_, qd_, qdd_);
      for (int i = 0; i < model_.nv(); ++i) effort_(i) += drives_.damping(i) * qd_(i);
    }
    return recorder.Record(t, q_, qd_, want_torques_ ? &effort_ : nullptr);
  }

  std::string NonFiniteMessage(double t) const override {
    return "a prescribed trajectory gave a non-finite value at t = " + std::to_string(t) +
           " s; check the drives' parameters";
  }

 private:
  const Model& model_;
  const DriveSet& drives_;
  const bool want_torques_;
  Data data_;
  Eigen::VectorXd q_, qd_, qdd_, effort_;
  // Per velocity coordinate of a prescribed pose: the held value of its component (m or rad).
  Eigen::VectorXd held_;
};

}  // namespace

void RunKinematic(const Model& model, const RunConfig& config, const DriveSet& drives,
                  const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                  FrameSink* sink, const std::atomic<bool>* cancel) {
  KinematicSource source(model, config, drives);
  RunFrames(times, source, recorder, result, sink, cancel);
}

}  // namespace mbstream
