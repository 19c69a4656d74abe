// SqliteStore: a sweep's runs by its indexed id, and the mark that it was cancelled
// (sweep_sql.h).
#include "server/store/sqlite_store.h"
#include "server/store/store_impl.h"
#include "server/store/sweep_sql.h"

namespace mbstream {

std::vector<v1::RunInfo> SqliteStore::ListSweepRuns(const std::string& sweep_id) const {
  std::vector<v1::RunInfo> runs;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_sweep_runs;
  ResetOnExit reset(select);
  select.BindText(1, sweep_id);
  while (select.Step()) ReadRunRowLocked(*impl_, select, runs.emplace_back());
  return runs;
}

int SqliteStore::MarkSweepCancelled(const std::string& sweep_id) {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement update(impl_->db, kMarkSweepCancelledSql,
                         "mark sweep " + sweep_id + " cancelled");
  update.BindText(1, sweep_id);
  update.Run();
  return static_cast<int>(impl_->db.Changes());
}

bool SqliteStore::SweepCancelled(const std::string& sweep_id) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_sweep_cancelled;
  ResetOnExit reset(select);
  select.BindText(1, sweep_id);
  return select.Step();
}

}  // namespace mbstream
