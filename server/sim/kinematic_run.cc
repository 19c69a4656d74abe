#include "server/sim/kinematic_run.h"

#include <string>

#include "server/dynamics/rnea.h"
#include "server/sim/frame_loop.h"

namespace mbstream {

namespace {

// The prescribed motion at each output time: nothing to advance.
class KinematicSource : public FrameSource {
 public:
  KinematicSource(const Model& model, const DriveSet& drives, bool want_torques)
      : model_(model),
        drives_(drives),
        want_torques_(want_torques),
        data_(model),
        q_(model.num_dofs()),
        qd_(model.num_dofs()),
        qdd_(model.num_dofs()),
        effort_(model.num_dofs()) {}

  bool Advance(const std::vector<double>& /*times*/, size_t /*k*/, RunStats* /*stats*/) override {
    return true;
  }

  bool Record(double t, FrameRecorder& recorder) override {
    const int n = model_.num_dofs();
    for (int i = 0; i < n; ++i) {
      const TrajectoryPoint ref = drives_.Reference(i, t);
      q_(i) = ref.q;
      qd_(i) = ref.qd;
      qdd_(i) = ref.qdd;
    }
    if (want_torques_) {
      effort_ = Rnea(model_, data_, q_, qd_, qdd_);
      for (int i = 0; i < n; ++i) effort_(i) += drives_.damping(i) * qd_(i);
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
};

}  // namespace

void RunKinematic(const Model& model, const RunConfig& config, const DriveSet& drives,
                  const std::vector<double>& times, FrameRecorder& recorder, RunResult& result,
                  FrameSink* sink, const std::atomic<bool>* cancel) {
  KinematicSource source(model, drives, config.want_torques);
  RunFrames(times, source, recorder, result, sink, cancel);
}

}  // namespace mbstream
