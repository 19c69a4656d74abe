// What every Store does the same way whatever its database.
#include "server/store/store.h"

#include "server/store/sqlite_store.h"
#include "shared/common/check.h"

namespace mbstream {

std::unique_ptr<Store> Store::Open(const std::string& directory) {
  return SqliteStore::Open(directory);
}

namespace {

[[noreturn]] void ThrowCorrupt(const Store& store, const std::string& run_id, int64_t chunk,
                               std::size_t good_frames) {
  throw InternalError("store " + store.path() + ": the stored frames of run " + run_id +
                      " are corrupt (chunk " + std::to_string(chunk) + " after its frame " +
                      std::to_string(good_frames) + " cannot be parsed)");
}

}  // namespace

std::optional<int64_t> Store::GetFrameChunk(const std::string& run_id, int64_t index,
                                            std::vector<v1::Frame>& frames) const {
  std::string data;
  const std::optional<int64_t> next = GetFrameChunkData(run_id, index, data);
  if (!next) return std::nullopt;
  const std::size_t before = frames.size();
  if (!DecodeFrameChunk(data, frames))
    ThrowCorrupt(*this, run_id, *next - 1, frames.size() - before);
  return next;
}

std::optional<int64_t> Store::GetSerializedFrames(const std::string& run_id, int64_t index,
                                                  std::string& data,
                                                  std::vector<std::string_view>& frames) const {
  const std::optional<int64_t> next = GetFrameChunkData(run_id, index, data);
  if (!next) return std::nullopt;
  const std::size_t before = frames.size();
  if (!SplitFrameChunk(data, frames))
    ThrowCorrupt(*this, run_id, *next - 1, frames.size() - before);
  return next;
}

std::vector<v1::Frame> Store::GetFrames(const std::string& run_id) const {
  std::vector<v1::Frame> frames;
  std::optional<int64_t> next = 0;
  while (next) next = GetFrameChunk(run_id, *next, frames);
  return frames;
}

}  // namespace mbstream
