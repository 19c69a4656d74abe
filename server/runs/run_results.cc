// RunManager's stored results (run_results.h): an ended run's info, its frames chunk by chunk
// (the whole result from RecentResults when this replica ran it lately), its probe reports.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "server/runs/release_memory.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/runs/run_results.h"
#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

v1::RunInfo RunResults::Info(const std::string& run_id) const {
  std::shared_ptr<Run> run = m_.FindActive(run_id);
  if (run && !IsFinalState(run->Info().state())) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " is " + v1::RunState_Name(run->Info().state()) +
                           "; wait for it to end (`mbstream run --watch` or WatchRun)");
  }
  if (v1::RunInfo pending; m_.pending_finals_.Find(run_id, pending)) return pending;
  std::optional<v1::RunInfo> info = m_.store_->GetRun(run_id);
  if (!info) throw UnknownRunError(run_id);
  if (!IsFinalState(info->state())) {  // queued, or integrating on another replica
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " is " + v1::RunState_Name(info->state()) +
                           "; wait for it to end (`mbstream run --watch` or WatchRun)");
  }
  return *info;
}

std::optional<int64_t> RunResults::Frames(const std::string& run_id, int64_t index,
                                          std::string& data,
                                          std::vector<std::string_view>& frames) const {
  if (index == 0 && m_.recent_results_.Get(run_id, data)) {  // the whole result, one chunk
    MBSTREAM_CHECK(SplitFrameChunk(data, frames));
    return std::nullopt;
  }
  return m_.store_->GetSerializedFrames(run_id, index, data, frames);
}

void RunResults::ReleaseMemory() const {
  m_.store_->ReleaseMemory();
  ReleaseFreedMemory();
}

std::vector<v1::ProbeReport> RunResults::Probes(const std::string& run_id) const {
  return m_.store_->GetProbes(run_id);
}

void RunResults::Forget(const std::string& run_id) {
  m_.recent_results_.Erase(run_id);
  m_.pending_finals_.Erase(run_id);
}

}  // namespace mbstream
