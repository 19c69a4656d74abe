#include "server/runs/frame_spool.h"

#include <algorithm>
#include <exception>
#include <utility>

#include "server/store/store.h"

namespace mbstream {

FrameSpool::FrameSpool(std::string run_id, int64_t expected_frames, std::size_t frames_per_chunk)
    : run_id_(std::move(run_id)),
      frames_per_chunk_(frames_per_chunk),
      frames_left_(expected_frames) {}

void FrameSpool::FlushEvery(const RunClock& clock, RunClock::TimePoint::duration interval,
                            RunClock::TimePoint since) {
  clock_ = interval > RunClock::TimePoint::duration::zero() ? &clock : nullptr;
  flush_interval_ = interval;
  last_flush_ = since;
}

void FrameSpool::Add(const v1::Frame& frame, Store& store) {
  if (!error_.empty() || lease_lost_) return;
  if (pending_.empty() && frames_left_ > 1) {
    // A later frame is longer by at most its scalars that are zero now and not serialized
    // (seq 11 bytes, times and energies 9 each) and a longer size prefix: 41 bytes. After
    // the first chunk the buffer is kept (FrameChunkBuilder::Clear): this reserves nothing
    // more unless the first frames were shorter.
    constexpr std::size_t kMaxGrowth = 48;
    const int64_t frames = std::min<int64_t>(frames_left_, static_cast<int64_t>(frames_per_chunk_));
    pending_.Reserve(static_cast<std::size_t>(frames) * (frame.ByteSizeLong() + kMaxGrowth));
  }
  --frames_left_;
  pending_.Add(frame);
  const bool full = static_cast<std::size_t>(pending_.frame_count()) >= frames_per_chunk_;
  if (clock_ != nullptr) {  // the interval runs from the last stored chunk, full or due
    const RunClock::TimePoint now = clock_->Now();
    if (!full && now - last_flush_ < flush_interval_) return;
    last_flush_ = now;
  } else if (!full) {
    return;
  }
  try {
    if (store.PutFrameChunk(run_id_, next_chunk_, pending_.chunk(), holder_)) {
      ++next_chunk_;
      stored_frames_ += pending_.frame_count();
    } else {
      lease_lost_ = true;
    }
  } catch (const std::exception& failure) {
    error_ = failure.what();
    if (error_.empty()) error_ = "unknown store error";
  }
  pending_.Clear();
}

bool FrameSpool::Finish(const v1::RunInfo& info, Store& store, const std::string& holder) {
  EncodedFrameChunk chunk = pending_.Take();
  if (!store.FinishRun(info, next_chunk_, chunk, holder)) return false;
  if (chunk.frame_count > 0 && next_chunk_ == 0) whole_result_ = std::move(chunk.data);
  stored_frames_ += chunk.frame_count;
  if (chunk.frame_count > 0) ++next_chunk_;
  return true;
}

}  // namespace mbstream
