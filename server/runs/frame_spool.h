// A run's frames on their way to the store: the frames since the last stored chunk are kept
// encoded (frame_chunks.h) and written as one chunk every `frames_per_chunk` frames, so a
// run's memory is one chunk whatever its length. Finish writes the rest together with the
// run's final info. Used by the run's worker thread only (not thread-safe).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/store/frame_chunks.h"

namespace mbstream {

class Store;

class FrameSpool {
 public:
  // `expected_frames` (0: unknown) sizes each chunk's buffer once, from its first frame.
  explicit FrameSpool(std::string run_id, int64_t expected_frames = 0,
                      std::size_t frames_per_chunk = kFramesPerChunk);

  // Adds the next frame (in seq order); stores the chunk when it is full. A store failure
  // does not throw: it is kept in error() and later frames are dropped (the run should stop).
  void Add(const v1::Frame& frame, Store& store);
  // Stores `info` and the frames not yet stored in one transaction (Store::FinishRun), with
  // a `holder` only while it holds the run's lease: false (nothing stored) otherwise.
  // Throws what the store throws.
  bool Finish(const v1::RunInfo& info, Store& store, const std::string& holder = {});

  // After a Finish that stored every frame of the run in one chunk: that chunk's blob
  // (moved out; RecentResults keeps it). Empty otherwise.
  std::string TakeWholeResult() { return std::move(whole_result_); }

  // Why a chunk could not be stored; empty while every chunk was.
  const std::string& error() const { return error_; }
  int64_t stored_chunks() const { return next_chunk_; }

 private:
  const std::string run_id_;
  const std::size_t frames_per_chunk_;
  int64_t frames_left_;  // expected and not yet added
  FrameChunkBuilder pending_;
  int64_t next_chunk_ = 0;
  std::string error_;
  std::string whole_result_;
};

}  // namespace mbstream
