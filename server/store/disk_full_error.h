// The exception for a store write refused for space (SQLITE_FULL, ENOSPC or a short write to
// the frames file): an operating condition, not a bug in mbstream. A LimitError, so the
// service answers RESOURCE_EXHAUSTED (status_from_exception.cc) and a run that meets it ends
// FAILED with its message, which names the full disk and says what to do.
#pragma once

#include "shared/common/check.h"

namespace mbstream {

class DiskFullError : public LimitError {
 public:
  using LimitError::LimitError;
};

// What a full disk's message ends with.
inline constexpr const char* kDiskFullAdvice =
    "the disk holding the data directory is full: free space on it or move --data to a bigger "
    "disk (delete runs (mbstream delete, --retain-runs, --retain-days); the finished runs stay "
    "readable)";

}  // namespace mbstream
