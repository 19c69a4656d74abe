// Which output frames a run keeps (RunSpec.keep): every frame, every Nth, the final one or
// none. The run computes every frame either way, and its summary (run_summary.h) sees them
// all; the store, the wire and the results files get only the kept ones.
#pragma once

#include <string>
#include <string_view>

namespace mbstream {

struct FrameKeep {
  enum class Mode {
    kAll,      // every frame (the default)
    kEvery,    // frames 0, N, 2N, ... and the last
    kFinal,    // the last good frame only
    kSummary,  // no frame: the summary in the run's stats only
  };
  Mode mode = Mode::kAll;
  long every = 1;  // N of kEvery, >= 2

  // Whether frame `k` (0-based, of those computed) is kept as it comes; the last frame of
  // kEvery and kFinal is kept at the run's end (KeepsLast) if it was not kept already.
  bool Keeps(long k) const {
    return mode == Mode::kAll || (mode == Mode::kEvery && k % every == 0);
  }
  bool KeepsLast() const { return mode == Mode::kEvery || mode == Mode::kFinal; }
  bool operator==(const FrameKeep&) const = default;
};

// How many of `computed` frames (a whole run's) `keep` keeps.
long KeptFrameCount(const FrameKeep& keep, long computed);

// "all", "every:N", "final" or "summary".
std::string FrameKeepName(const FrameKeep& keep);

// Parses one of those names ("every:1" is "all"); returns false, with what is wrong and
// what to give in *why, for anything else.
bool ParseFrameKeep(std::string_view text, FrameKeep* keep, std::string* why);

}  // namespace mbstream
