// What every Store does the same way whatever its database.
#include "server/store/store.h"

#include "server/store/sqlite_store.h"

namespace mbstream {

std::unique_ptr<Store> Store::Open(const std::string& directory) {
  return SqliteStore::Open(directory);
}

std::vector<v1::Frame> Store::GetFrames(const std::string& run_id) const {
  std::vector<v1::Frame> frames;
  std::optional<int64_t> next = 0;
  while (next) next = GetFrameChunk(run_id, *next, frames);
  return frames;
}

}  // namespace mbstream
