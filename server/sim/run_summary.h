// What a run reports about all of its frames whatever it keeps (RunSpec.keep): computed as
// the frames come, so that a sweep of many runs needs none of their frames afterwards.
#pragma once

#include <string>
#include <vector>

namespace mbstream {

// One joint over the run's output frames.
struct JointSummary {
  // N*m or N: the largest |effort| and its root mean square over the output frames (< 0:
  // the run reports no efforts).
  double effort_peak = -1.0;
  double effort_rms = -1.0;
  // rad or m: the largest |q_ref(t) - q| over the output frames of a joint whose drive has
  // a reference motion (pd_servo, prescribed); < 0 for other joints.
  double tracking_error_max = -1.0;
  bool operator==(const JointSummary&) const = default;
};

struct RunSummary {
  std::string keep = "all";  // which frames the run kept (FrameKeepName)
  long frames_computed = 0;  // good output frames the run computed
  long frames_kept = 0;      // of those, the ones kept (stored, sent, written)
  // The last good frame: s, and each joint's position (rad or m) and rate (rad/s or m/s) in
  // the results' joint order (a closed loop's cut joints after the tree's).
  double t_final = 0.0;
  std::vector<double> q_final, qd_final;
  std::vector<JointSummary> joints;  // in the same order
  bool operator==(const RunSummary&) const = default;
};

}  // namespace mbstream
