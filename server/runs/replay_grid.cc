#include "server/runs/replay_grid.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "shared/common/check.h"

namespace mbstream {

namespace {

std::string Joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

std::string Seconds(double s) {
  std::ostringstream out;
  out.precision(9);
  out << s << " s";
  return out.str();
}

// The whole number n with fine = coarse / n, or 0 when there is none.
int64_t WholeRatio(double coarse, double fine) {
  if (!(fine > 0.0) || !(coarse >= fine)) return 0;
  const double ratio = coarse / fine;
  const double n = std::round(ratio);
  return std::abs(ratio - n) <= 1e-9 * ratio ? static_cast<int64_t>(n) : 0;
}

}  // namespace

ReplayGrid SingleRunGrid(const ReplayGridRun& run) {
  ReplayGrid grid;
  grid.frames = run.frames;
  grid.interval_s = run.interval_s;
  return grid;
}

ReplayGrid AlignReplayGrids(const ReplayGridRun& run, const ReplayGridRun& ghost) {
  const std::string both = "cannot compare run " + run.id + " with run " + ghost.id + ": ";
  if (run.joint_names != ghost.joint_names) {
    throw InputError(both + "their models' joints differ (" + Joined(run.joint_names) +
                     " against " + Joined(ghost.joint_names) +
                     "); compare two runs of the same model");
  }
  if (run.frames < 1 || ghost.frames < 1) {
    throw InputError(both + "run " + (run.frames < 1 ? run.id : ghost.id) +
                     " has no stored frames");
  }
  ReplayGrid grid;
  grid.stride = 1;
  grid.ghost_stride = 1;
  if (run.frames > 1 && ghost.frames > 1) {
    const bool run_finer = run.interval_s <= ghost.interval_s;
    const double coarse = run_finer ? ghost.interval_s : run.interval_s;
    const double fine = run_finer ? run.interval_s : ghost.interval_s;
    const int64_t n = WholeRatio(coarse, fine);
    if (n == 0) {
      throw InputError(both + "their time grids cannot be aligned (a frame every " +
                       Seconds(run.interval_s) + " against every " + Seconds(ghost.interval_s) +
                       "); run " + ghost.id + "'s model again with --output-interval " +
                       Seconds(run.interval_s).substr(0, Seconds(run.interval_s).size() - 2) +
                       " or a whole fraction of it");
    }
    (run_finer ? grid.stride : grid.ghost_stride) = n;
    grid.interval_s = coarse;
  }
  grid.frames =
      std::min((run.frames - 1) / grid.stride, (ghost.frames - 1) / grid.ghost_stride) + 1;
  return grid;
}

}  // namespace mbstream
