// Store: run rows (RunInfo with state and creation time as columns).
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

namespace {

// Runs `statement` (upsert_run or insert_new_run: the same seven parameters) for `info`.
void WriteRunLocked(SqliteStatement& statement, const v1::RunInfo& info) {
  const std::string bytes = SerializeForStore(info, "run " + info.id());
  ResetOnExit reset(statement);
  statement.BindText(1, info.id());
  statement.BindText(2, info.model_id());
  statement.BindInt64(3, info.state());
  statement.BindInt64(4, info.created_unix_ms());
  statement.BindBlob(5, bytes);
  statement.BindText(6, info.sweep_id());
  statement.BindInt64(7, info.sweep_point());
  statement.Run();
}

}  // namespace

void ReadRunRowLocked(const SqliteStore::Impl& impl, const SqliteStatement& row,
                      v1::RunInfo& info) {
  ParseFromStore(row.ColumnBlob(0), info, "run info", impl.db.path());
  info.set_keep(row.ColumnInt64(1) != 0);
  if (row.ColumnInt64(2) != 0) info.set_sweep_cancelled(true);
}

void UpsertRunLocked(SqliteStore::Impl& impl, const v1::RunInfo& info) {
  WriteRunLocked(impl.upsert_run, info);
}

bool InsertNewRunLocked(SqliteStore::Impl& impl, const v1::RunInfo& info) {
  WriteRunLocked(impl.insert_new_run, info);
  return impl.db.Changes() > 0;
}

void SqliteStore::PutRun(const v1::RunInfo& info) {
  std::lock_guard lock(impl_->mutex);
  UpsertRunLocked(*impl_, info);
}

bool SqliteStore::AddRuns(const std::vector<v1::RunInfo>& infos) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "write " + std::to_string(infos.size()) + " runs");
  for (const v1::RunInfo& info : infos) {
    if (!InsertNewRunLocked(*impl_, info)) return false;  // the id is taken: none is stored
  }
  transaction.Commit();
  return true;
}

std::optional<v1::RunInfo> SqliteStore::GetRun(const std::string& run_id) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_run;
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  if (!select.Step()) return std::nullopt;
  v1::RunInfo info;
  ReadRunRowLocked(*impl_, select, info);
  return info;
}

std::vector<v1::RunInfo> SqliteStore::ListRuns() const {
  std::vector<v1::RunInfo> runs;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_runs;
  ResetOnExit reset(select);
  while (select.Step()) ReadRunRowLocked(*impl_, select, runs.emplace_back());
  return runs;
}

int SqliteStore::MarkUnfinishedRunsInterrupted(const std::string& message) {
  const int64_t now_ms = UnixNowMs();
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "mark unfinished runs interrupted");
  std::vector<v1::RunInfo> unfinished;
  {
    SqliteStatement& select = impl_->select_unfinished_runs;
    ResetOnExit reset(select);
    select.BindInt64(1, v1::QUEUED);
    select.BindInt64(2, v1::RUNNING);
    while (select.Step()) {
      ParseFromStore(select.ColumnBlob(0), unfinished.emplace_back(), "run info", impl_->db.path());
    }
  }
  for (v1::RunInfo& info : unfinished) {
    MarkInterrupted(info, message, now_ms);
    ApplyKeptFrames(KeptFramesLocked(*impl_, info.id()), info);
    UpsertRunLocked(*impl_, info);
  }
  transaction.Commit();
  return static_cast<int>(unfinished.size());
}

}  // namespace mbstream
