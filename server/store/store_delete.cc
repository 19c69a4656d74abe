// SqliteStore: deleting a run or a model, each in one transaction, and the keep mark
// (delete_sql.h).
#include <algorithm>
#include <vector>

#include "server/store/delete_sql.h"
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

namespace {

// Runs `sql` with `id` as its parameter; returns the rows it changed. The caller holds the
// mutex, in a transaction.
int64_t RunWithIdLocked(SqliteStore::Impl& impl, const char* sql, const std::string& id,
                        const std::string& operation) {
  SqliteStatement statement(impl.db, sql, operation);
  statement.BindText(1, id);
  statement.Run();
  return impl.db.Changes();
}

}  // namespace

bool SqliteStore::DeleteRun(const std::string& run_id) {
  const std::string operation = "delete run " + run_id;
  std::lock_guard lock(impl_->mutex);
  std::vector<FrameExtent> extents;  // its chunks' bytes in the frames file
  int64_t rows = 0;
  {
    SqliteTransaction transaction(impl_->db, operation);
    SqliteStatement select(impl_->db,
                           "SELECT file_offset, file_bytes FROM frame_chunks WHERE run_id = ?1 "
                           "AND file_offset IS NOT NULL",
                           operation);
    select.BindText(1, run_id);
    while (select.Step()) extents.push_back({select.ColumnInt64(0), select.ColumnInt64(1), 0});
    for (const char* sql : kDeleteRunSql) rows = RunWithIdLocked(*impl_, sql, run_id, operation);
    transaction.Commit();
  }
  // After the commit (frame_file.h): a crash before this leaves the bytes allocated until the
  // next open. Readers hold the mutex while they read a chunk of a row they found: none reads
  // these any more.
  for (const FrameExtent& extent : extents) impl_->frames.Release(extent.offset, extent.bytes);
  impl_->db.Exec("PRAGMA incremental_vacuum", "return the free pages of run " + run_id);
  return rows > 0;
}

int64_t ReleaseUnreferencedFramesLocked(SqliteStore::Impl& impl) {
  SqliteStatement select(impl.db,
                         "SELECT file_offset, file_bytes FROM frame_chunks WHERE file_offset IS "
                         "NOT NULL ORDER BY file_offset",
                         "list the frames file's chunks");
  // Only gaps between referenced chunks: bytes after the last one may be a chunk another
  // writer has appended and not yet committed (frame_file.h).
  int64_t end = 0;  // of the chunks so far
  int64_t released = 0;
  while (select.Step()) {
    const int64_t offset = select.ColumnInt64(0), bytes = select.ColumnInt64(1);
    if (offset > end && impl.frames.Release(end, offset - end)) released += offset - end;
    end = std::max(end, offset + bytes);
  }
  return released;
}

int64_t SqliteStore::DeleteModel(const std::string& model_id) {
  const std::string operation = "delete model " + model_id;
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, operation);
  int64_t runs = 0;
  {
    SqliteStatement count(impl_->db, kCountModelRunsSql, operation);
    count.BindText(1, model_id);
    if (count.Step()) runs = count.ColumnInt64(0);
  }
  if (runs > 0) return runs;
  for (const char* sql : kDeleteModelSql) RunWithIdLocked(*impl_, sql, model_id, operation);
  transaction.Commit();
  return 0;
}

bool SqliteStore::SetRunKeep(const std::string& run_id, bool keep) {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement update(impl_->db, kSetRunKeepSqlite, "mark run " + run_id + " kept");
  update.BindText(1, run_id);
  update.BindInt64(2, keep ? 1 : 0);
  update.Run();
  return impl_->db.Changes() > 0;
}

}  // namespace mbstream
