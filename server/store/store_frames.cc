// Store: a run's frames, written once with its final info and read back in seq order.
#include "server/common/check.h"
#include "server/store/frame_chunks.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store.h"
#include "server/store/store_impl.h"

namespace mbstream {

void Store::FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) {
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
    SqliteStatement& insert = impl_->insert_frame_chunk;
    ResetOnExit reset(insert);
    insert.BindText(1, info.id());
    insert.BindInt64(2, static_cast<int64_t>(i));
    insert.BindInt64(3, chunks[i].first_seq);
    insert.BindInt64(4, chunks[i].frame_count);
    insert.BindBlob(5, chunks[i].data);
    insert.Run();
  }
  transaction.Commit();
}

std::vector<v1::Frame> Store::GetFrames(const std::string& run_id) const {
  // Copy the chunk blobs under the lock, parse them after releasing it: parsing a million
  // frames takes far longer than copying their bytes.
  std::vector<std::string> blobs;
  std::size_t frame_count = 0;
  {
    std::lock_guard lock(impl_->mutex);
    SqliteStatement& select = impl_->select_frame_chunks;
    ResetOnExit reset(select);
    select.BindText(1, run_id);
    while (select.Step()) {
      blobs.emplace_back(select.ColumnBlob(0));
      frame_count += static_cast<std::size_t>(select.ColumnInt64(1));
    }
  }
  std::vector<v1::Frame> frames;
  frames.reserve(frame_count);
  for (std::string& blob : blobs) {
    if (!DecodeFrameChunk(blob, frames)) {
      throw InternalError("store " + impl_->db.path() + ": the stored frames of run " + run_id +
                          " are corrupt (a chunk after frame " + std::to_string(frames.size()) +
                          " cannot be parsed)");
    }
    std::string().swap(blob);  // free each chunk's bytes as soon as it is parsed
  }
  return frames;
}

}  // namespace mbstream
