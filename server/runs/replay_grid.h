// The common time grid of a replay and its ghost (a comparison of two stored runs): both
// runs' output frames lie at k * interval from t = 0, so they can be shown side by side at
// the times both have when one interval is a whole multiple of the other.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mbstream {

struct ReplayGridRun {
  std::string id;
  int64_t frames = 0;       // stored frames
  double interval_s = 0.0;  // s between frames (frame 1's time; 0 with fewer than 2 frames)
  std::vector<std::string> joint_names;
};

struct ReplayGrid {
  int64_t stride = 1;        // frames of the replayed run per grid step
  int64_t ghost_stride = 0;  // frames of the ghost per grid step; 0 = no ghost
  int64_t frames = 0;        // grid steps: grid step k shows frame k * stride (and the
                             // ghost's k * ghost_stride)
  double interval_s = 0.0;   // s between grid steps
};

// The grid of `run` alone (stride 1).
ReplayGrid SingleRunGrid(const ReplayGridRun& run);

// The common grid of `run` and `ghost`: the coarser interval, over the shorter of the two.
// Throws InputError naming both runs and what to do when their joint names differ or when
// neither interval is a whole multiple of the other (within 1e-9 relative).
ReplayGrid AlignReplayGrids(const ReplayGridRun& run, const ReplayGridRun& ghost);

}  // namespace mbstream
