#include "server/runs/replay_cursor.h"

#include <algorithm>
#include <atomic>

#include "server/store/store.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

std::atomic<int64_t> g_held{0};
std::atomic<int64_t> g_peak{0};

}  // namespace

int64_t replay_frames_held() { return g_held; }
int64_t replay_frames_peak() { return g_peak; }
void ResetReplayFramesPeak() { g_peak = g_held.load(); }

ReplayCursor::ReplayCursor(const Store* store, std::string run_id, int64_t frame_count)
    : store_(store), run_id_(std::move(run_id)), frame_count_(frame_count) {}

ReplayCursor::~ReplayCursor() { Hold(0); }

void ReplayCursor::Hold(std::size_t frames) {
  const int64_t now = g_held += static_cast<int64_t>(frames) - static_cast<int64_t>(held_);
  held_ = frames;
  int64_t peak = g_peak;
  while (now > peak && !g_peak.compare_exchange_weak(peak, now)) {
  }
}

const v1::Frame& ReplayCursor::At(int64_t seq) {
  MBSTREAM_CHECK(seq >= 0 && seq < frame_count_);
  const int64_t held_count = static_cast<int64_t>(chunk_.size());
  if (chunk_first_ < 0 || seq < chunk_first_ || seq >= chunk_first_ + held_count) {
    std::vector<v1::Frame>().swap(chunk_);  // the old chunk goes before the new one comes
    chunk_first_ = -1;
    Hold(0);
    const std::optional<int64_t> index = store_->FrameChunkHolding(run_id_, seq);
    if (!index || !store_->GetFrameChunk(run_id_, *index, chunk_) || chunk_.empty()) {
      throw InternalError("store: run " + run_id_ + " has no stored frame " + std::to_string(seq) +
                          " although it lists " + std::to_string(frame_count_) + " frames");
    }
    chunk_first_ = chunk_.front().seq();
    Hold(chunk_.size());
  }
  const v1::Frame& frame = chunk_[static_cast<std::size_t>(seq - chunk_first_)];
  if (frame.seq() != seq) {
    throw InternalError("store: the stored frames of run " + run_id_ +
                        " are not consecutive (frame " + std::to_string(frame.seq()) + " where " +
                        std::to_string(seq) + " was expected)");
  }
  return frame;
}

}  // namespace mbstream
