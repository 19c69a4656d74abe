#include "server/runs/frame_spool.h"

#include <exception>
#include <utility>

#include "server/store/store.h"

namespace mbstream {

FrameSpool::FrameSpool(std::string run_id, std::size_t frames_per_chunk)
    : run_id_(std::move(run_id)), frames_per_chunk_(frames_per_chunk) {}

void FrameSpool::Add(const v1::Frame& frame, Store& store) {
  if (!error_.empty()) return;
  pending_.Add(frame);
  if (static_cast<std::size_t>(pending_.frame_count()) < frames_per_chunk_) return;
  const EncodedFrameChunk chunk = pending_.Take();
  try {
    store.PutFrameChunk(run_id_, next_chunk_, chunk);
    ++next_chunk_;
  } catch (const std::exception& failure) {
    error_ = failure.what();
    if (error_.empty()) error_ = "unknown store error";
  }
}

void FrameSpool::Finish(const v1::RunInfo& info, Store& store) {
  const EncodedFrameChunk chunk = pending_.Take();
  store.FinishRun(info, next_chunk_, chunk);
  if (chunk.frame_count > 0) ++next_chunk_;
}

}  // namespace mbstream
