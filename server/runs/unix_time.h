// Wall-clock timestamps of models and runs (RunInfo.*_unix_ms, ModelInfo.created_unix_ms).
#pragma once

#include <chrono>
#include <cstdint>

namespace mbstream {

// Milliseconds since the Unix epoch, UTC.
inline int64_t NowUnixMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace mbstream
