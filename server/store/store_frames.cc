// Store: a run's frames, written chunk by chunk while it runs and read back chunk by chunk.
#include "common/check.h"
#include "server/store/frame_chunks.h"
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

namespace {

// Writes one chunk row (replacing one of the same number). The caller holds the mutex.
void InsertChunkLocked(SqliteStore::Impl& impl, const std::string& run_id, int64_t index,
                       const EncodedFrameChunk& chunk) {
  SqliteStatement& insert = impl.insert_frame_chunk;
  ResetOnExit reset(insert);
  insert.BindText(1, run_id);
  insert.BindInt64(2, index);
  insert.BindInt64(3, chunk.first_seq);
  insert.BindInt64(4, chunk.frame_count);
  insert.BindBlob(5, chunk.data);
  insert.Run();
}

}  // namespace

void SqliteStore::PutFrameChunk(const std::string& run_id, int64_t index,
                                const EncodedFrameChunk& chunk) {
  std::lock_guard lock(impl_->mutex);
  InsertChunkLocked(*impl_, run_id, index, chunk);  // one statement: its own transaction
}

bool SqliteStore::FinishRun(const v1::RunInfo& info, int64_t index,
                            const EncodedFrameChunk& last_chunk, const std::string& holder) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "finish run " + info.id());
  if (!holder.empty() && !HoldsLeaseLocked(*impl_, info.id(), holder)) return false;
  UpsertRunLocked(*impl_, info);
  if (last_chunk.frame_count > 0) InsertChunkLocked(*impl_, info.id(), index, last_chunk);
  {
    SqliteStatement& remove = impl_->delete_frame_chunks_after;
    ResetOnExit reset(remove);
    remove.BindText(1, info.id());
    remove.BindInt64(2, last_chunk.frame_count > 0 ? index : index - 1);
    remove.Run();
  }
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

std::optional<int64_t> SqliteStore::GetFrameChunkData(const std::string& run_id, int64_t index,
                                                      std::string& data) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_frame_chunk;
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  select.BindInt64(2, index);
  if (!select.Step()) return std::nullopt;
  data.assign(select.ColumnBlob(1));
  return select.ColumnInt64(0) + 1;
}

}  // namespace mbstream
