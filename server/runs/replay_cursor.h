// Reads a stored run's frames for a replay, one stored chunk (kFramesPerChunk frames) at a
// time, in any order (a seek loads the chunk that holds the frame). A run is never in
// memory at once: every cursor of the process together holds replay_frames_held() frames.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"

namespace mbstream {

class Store;

// Frames held by every ReplayCursor of the process now, and the most held at once since
// the last ResetReplayFramesPeak (the memory bound a test asserts).
int64_t replay_frames_held();
int64_t replay_frames_peak();
void ResetReplayFramesPeak();

class ReplayCursor {
 public:
  // `store` must outlive the cursor; `frame_count` is the run's stored frames (RunInfo.frames).
  ReplayCursor(const Store* store, std::string run_id, int64_t frame_count);
  ~ReplayCursor();
  ReplayCursor(const ReplayCursor&) = delete;
  ReplayCursor& operator=(const ReplayCursor&) = delete;

  const std::string& run_id() const { return run_id_; }
  int64_t frame_count() const { return frame_count_; }

  // Frame `seq` (0 <= seq < frame_count()), valid until the next call. Loads its chunk when
  // it is not the one held. Throws InternalError when the store does not hold the frame.
  const v1::Frame& At(int64_t seq);

 private:
  void Hold(std::size_t frames);

  const Store* store_;
  const std::string run_id_;
  const int64_t frame_count_;
  std::vector<v1::Frame> chunk_;  // the chunk held, frames chunk_first_ ... in seq order
  int64_t chunk_first_ = -1;
  std::size_t held_ = 0;
};

}  // namespace mbstream
