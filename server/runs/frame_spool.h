// A run's frames on their way to the store: the frames since the last stored chunk are kept
// encoded (frame_chunks.h) and written as one chunk every `frames_per_chunk` frames, so a
// run's memory is one chunk whatever its length; with FlushEvery, also once a wall-time
// interval has passed since the last chunk, so that a crash (kill -9) loses at most that
// interval's frames. Finish writes the rest together with the run's final info. Used by the
// run's worker thread only (not thread-safe).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/runs/run_clock.h"
#include "server/store/frame_chunks.h"

namespace mbstream {

class Store;

class FrameSpool {
 public:
  // `expected_frames` (0: unknown) sizes the chunk buffer once, from the first frame.
  explicit FrameSpool(std::string run_id, int64_t expected_frames = 0,
                      std::size_t frames_per_chunk = kFramesPerChunk);

  // Also stores a chunk that is not full when `interval` of `clock`'s time has passed since
  // the last stored chunk (since `since` for the first): looked at as each frame is added,
  // the frame included. `interval` <= 0: only full chunks (the default). `clock` must
  // outlive the spool's Adds.
  void FlushEvery(const RunClock& clock, RunClock::TimePoint::duration interval,
                  RunClock::TimePoint since);

  // Chunks are stored only while `holder` holds the run's lease (Store::PutFrameChunk); empty
  // (the default, a private store): unconditionally.
  void WriteAs(std::string holder) { holder_ = std::move(holder); }

  // Adds the next frame (in seq order); stores the chunk when it is full or due. A store
  // failure does not throw: it is kept in error() and later frames are dropped (the run
  // should stop); so are they once the lease is lost (lease_lost(): the run should stop and
  // store nothing more).
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
  bool lease_lost() const { return lease_lost_; }
  int64_t stored_chunks() const { return next_chunk_; }
  int64_t stored_frames() const { return stored_frames_; }  // in those chunks

 private:
  const std::string run_id_;
  const std::size_t frames_per_chunk_;
  int64_t frames_left_;  // expected and not yet added
  FrameChunkBuilder pending_;
  int64_t next_chunk_ = 0;
  int64_t stored_frames_ = 0;
  const RunClock* clock_ = nullptr;  // FlushEvery's; nullptr: full chunks only
  RunClock::TimePoint::duration flush_interval_{};
  RunClock::TimePoint last_flush_{};
  std::string holder_;
  bool lease_lost_ = false;
  std::string error_;
  std::string whole_result_;
};

}  // namespace mbstream
