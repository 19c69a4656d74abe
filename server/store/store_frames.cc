// Store: a run's frames, written chunk by chunk while it runs and read back chunk by chunk.
#include "server/store/frame_chunks.h"
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Appends one chunk's frames to the frames file and writes its row pointing at them
// (replacing one of the same number). The caller holds the mutex; the bytes are written
// before the row's transaction commits (frame_file.h).
void InsertChunkLocked(SqliteStore::Impl& impl, const std::string& run_id, int64_t index,
                       const EncodedFrameChunk& chunk) {
  const FrameExtent extent = impl.frames.Append(chunk.data);
  SqliteStatement& insert = impl.insert_frame_chunk;
  ResetOnExit reset(insert);
  insert.BindText(1, run_id);
  insert.BindInt64(2, index);
  insert.BindInt64(3, chunk.first_seq);
  insert.BindInt64(4, chunk.frame_count);
  insert.BindBlob(5, std::string_view());
  insert.BindInt64(6, extent.offset);
  insert.BindInt64(7, extent.bytes);
  insert.BindInt64(8, extent.crc32c);
  insert.Run();
}

// Removes the run's chunks numbered after `index`. The caller holds the mutex.
void DeleteChunksAfterLocked(SqliteStore::Impl& impl, const std::string& run_id, int64_t index) {
  SqliteStatement& remove = impl.delete_frame_chunks_after;
  ResetOnExit reset(remove);
  remove.BindText(1, run_id);
  remove.BindInt64(2, index);
  remove.Run();
}

}  // namespace

bool SqliteStore::PutFrameChunk(const std::string& run_id, int64_t index,
                                const EncodedFrameChunk& chunk, const std::string& holder) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "store frames of run " + run_id);
  if (!holder.empty() && !HoldsLeaseLocked(*impl_, run_id, holder)) return false;
  InsertChunkLocked(*impl_, run_id, index, chunk);
  DeleteChunksAfterLocked(*impl_, run_id, index);  // an earlier attempt's
  transaction.Commit();
  return true;
}

bool SqliteStore::FinishRun(const v1::RunInfo& info, int64_t index,
                            const EncodedFrameChunk& last_chunk, const std::string& holder) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "finish run " + info.id());
  if (!holder.empty() && !HoldsLeaseLocked(*impl_, info.id(), holder)) return false;
  UpsertRunLocked(*impl_, info);
  if (last_chunk.frame_count > 0) InsertChunkLocked(*impl_, info.id(), index, last_chunk);
  DeleteChunksAfterLocked(*impl_, info.id(), last_chunk.frame_count > 0 ? index : index - 1);
  transaction.Commit();
  return true;
}

void SqliteStore::FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) {
  // Serialize outside the lock: other runs' store calls only wait for the SQLite writes.
  const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(frames);

  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "finish run " + info.id());
  UpsertRunLocked(*impl_, info);
  {
    SqliteStatement& remove = impl_->delete_frame_chunks;
    ResetOnExit reset(remove);
    remove.BindText(1, info.id());
    remove.Run();
  }
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    InsertChunkLocked(*impl_, info.id(), static_cast<int64_t>(i), chunks[i]);
  }
  transaction.Commit();
}

namespace {

// GetFrameChunkData's read; the caller holds the mutex.
std::optional<int64_t> ReadChunkLocked(SqliteStore::Impl& impl, const std::string& run_id,
                                       int64_t index, std::string& data) {
  SqliteStatement& select = impl.select_frame_chunk;
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  select.BindInt64(2, index);
  if (!select.Step()) return std::nullopt;
  const int64_t chunk = select.ColumnInt64(0);
  if (select.ColumnIsNull(2)) {  // written before schema version 5: in the row
    data.assign(select.ColumnBlob(1));
    return chunk + 1;
  }
  const FrameExtent extent{select.ColumnInt64(2), select.ColumnInt64(3),
                           static_cast<uint32_t>(select.ColumnInt64(4))};
  if (!impl.frames.Read(extent, data)) {
    throw InternalError("store " + impl.db.path() + ": the frames of run " + run_id + " (chunk " +
                        std::to_string(chunk) + ", " + std::to_string(extent.bytes) +
                        " bytes at offset " + std::to_string(extent.offset) + " of " +
                        impl.frames.path() +
                        ") are missing or damaged: the file is shorter or the bytes do not " +
                        "match their checksum (the machine may have stopped before they " +
                        "reached the disk); run the simulation again");
  }
  return chunk + 1;
}

}  // namespace

std::optional<int64_t> SqliteStore::GetFrameChunkData(const std::string& run_id, int64_t index,
                                                      std::string& data) const {
  std::lock_guard lock(impl_->mutex);
  return ReadChunkLocked(*impl_, run_id, index, data);
}

KeptFrames KeptFramesLocked(SqliteStore::Impl& impl, const std::string& run_id) {
  SqliteStatement count(impl.db,
                        "SELECT COUNT(*), COALESCE(SUM(frame_count), 0), MAX(chunk) FROM "
                        "frame_chunks WHERE run_id = ?1",
                        "count stored frames");
  KeptFrames kept;
  while (true) {
    int64_t chunks = 0, frames = 0, last = 0;
    {
      ResetOnExit reset(count);
      count.BindText(1, run_id);
      if (count.Step()) {
        chunks = count.ColumnInt64(0);
        frames = count.ColumnInt64(1);
        last = chunks > 0 ? count.ColumnInt64(2) : 0;
      }
    }
    if (chunks == 0) return kept;
    std::string data;
    try {
      if (ReadChunkLocked(impl, run_id, last, data) == last + 1 &&
          ReadKeptFrames(frames, data, kept)) {
        return kept;
      }
    } catch (const InternalError&) {  // its bytes are missing or damaged
    }
    DeleteChunksAfterLocked(impl, run_id, last - 1);
    ++kept.dropped_chunks;
  }
}

}  // namespace mbstream
