// SqliteStore: the sweeps the server feeds (the sweeps table), a sweep's runs by its indexed
// id and point, and the mark that it was cancelled (sweep_sql.h).
#include <limits>

#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"
#include "server/store/sweep_sql.h"

namespace mbstream {

namespace {

// A row of kSelectSweepSql or kSelectOpenSweepsSql.
StoredSweep ReadSweepRow(const SqliteStatement& row) {
  StoredSweep sweep;
  sweep.id = std::string(row.ColumnText(0));
  sweep.model_id = std::string(row.ColumnText(1));
  sweep.owner = std::string(row.ColumnText(2));
  sweep.created_unix_ms = row.ColumnInt64(3);
  sweep.total_points = static_cast<int32_t>(row.ColumnInt64(4));
  sweep.next_point = static_cast<int32_t>(row.ColumnInt64(5));
  sweep.window = static_cast<int32_t>(row.ColumnInt64(6));
  sweep.cancelled = row.ColumnInt64(7) != 0;
  sweep.unfinished_runs = static_cast<int32_t>(row.ColumnInt64(8));
  return sweep;
}

}  // namespace

bool SqliteStore::AddSweep(const StoredSweep& sweep) {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement insert(impl_->db, kInsertSweepSql, "write sweep " + sweep.id);
  insert.BindText(1, sweep.id);
  insert.BindText(2, sweep.model_id);
  insert.BindText(3, sweep.owner);
  insert.BindInt64(4, sweep.created_unix_ms);
  insert.BindInt64(5, sweep.total_points);
  insert.BindInt64(6, sweep.window);
  insert.BindBlob(7, sweep.definition);
  insert.Run();
  return impl_->db.Changes() > 0;
}

std::optional<StoredSweep> SqliteStore::GetSweep(const std::string& sweep_id,
                                                 bool definition) const {
  std::lock_guard lock(impl_->mutex);
  std::optional<StoredSweep> sweep;
  {
    SqliteStatement& select = impl_->select_sweep;
    ResetOnExit reset(select);
    select.BindText(1, sweep_id);
    select.BindInt64(2, v1::QUEUED);
    select.BindInt64(3, v1::RUNNING);
    if (!select.Step()) return sweep;
    sweep = ReadSweepRow(select);
  }
  if (definition) {
    SqliteStatement select(impl_->db, kSelectSweepDefinitionSql, "read sweep " + sweep_id);
    select.BindText(1, sweep_id);
    if (select.Step()) sweep->definition = std::string(select.ColumnBlob(0));
  }
  return sweep;
}

std::vector<StoredSweep> SqliteStore::ListOpenSweeps() const {
  std::lock_guard lock(impl_->mutex);
  std::vector<StoredSweep> sweeps;
  SqliteStatement select(impl_->db, kSelectOpenSweepsSql, "list open sweeps");
  select.BindInt64(1, v1::QUEUED);
  select.BindInt64(2, v1::RUNNING);
  while (select.Step()) sweeps.push_back(ReadSweepRow(select));
  return sweeps;
}

SweepFeed SqliteStore::AddSweepRuns(const std::string& sweep_id,
                                    const std::vector<v1::RunInfo>& infos) {
  if (infos.empty()) return SweepFeed::kAdded;
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "queue points of sweep " + sweep_id);
  int64_t next = 0, window = 0, unfinished = 0;
  {
    SqliteStatement select(impl_->db, kSelectSweepFeedSql, "read sweep " + sweep_id);
    select.BindText(1, sweep_id);
    if (!select.Step() || select.ColumnInt64(1) != 0) return SweepFeed::kRefused;
    next = select.ColumnInt64(0);
    window = select.ColumnInt64(2);
  }
  if (next != infos.front().sweep_point()) return SweepFeed::kRefused;
  {
    SqliteStatement count(impl_->db, kCountUnfinishedSweepRunsSql, "count runs of " + sweep_id);
    count.BindText(1, sweep_id);
    count.BindInt64(2, v1::QUEUED);
    count.BindInt64(3, v1::RUNNING);
    if (count.Step()) unfinished = count.ColumnInt64(0);
  }
  int64_t queued = 0;
  for (const v1::RunInfo& info : infos) queued += info.state() == v1::QUEUED ? 1 : 0;
  if (queued > 0 && unfinished + queued > window) return SweepFeed::kRefused;
  for (const v1::RunInfo& info : infos) {
    if (!InsertNewRunLocked(*impl_, info)) return SweepFeed::kIdTaken;  // rolled back
  }
  SqliteStatement move(impl_->db, kMoveSweepNextPointSql, "move sweep " + sweep_id);
  move.BindInt64(1, next + static_cast<int64_t>(infos.size()));
  move.BindText(2, sweep_id);
  move.Run();
  transaction.Commit();
  return SweepFeed::kAdded;
}

std::vector<v1::RunInfo> SqliteStore::ListSweepRuns(const std::string& sweep_id, int first_point,
                                                    int max_runs, bool unfinished_only) const {
  std::vector<v1::RunInfo> runs;
  std::lock_guard lock(impl_->mutex);
  if (unfinished_only) {
    SqliteStatement select(impl_->db, kSelectUnfinishedSweepRunsSql,
                           "list unfinished runs of " + sweep_id);
    select.BindText(1, sweep_id);
    select.BindInt64(2, v1::QUEUED);
    select.BindInt64(3, v1::RUNNING);
    while (select.Step()) {
      ReadRunRowLocked(*impl_, select, runs.emplace_back());
      if (runs.back().sweep_point() < first_point) runs.pop_back();
    }
    return runs;
  }
  SqliteStatement& select = impl_->select_sweep_runs;
  ResetOnExit reset(select);
  select.BindText(1, sweep_id);
  select.BindInt64(2, first_point);
  select.BindInt64(3, max_runs > 0 ? max_runs : std::numeric_limits<int64_t>::max());
  while (select.Step()) ReadRunRowLocked(*impl_, select, runs.emplace_back());
  return runs;
}

Store::StateCounts SqliteStore::CountSweepRuns(const std::string& sweep_id) const {
  StateCounts counts;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->count_sweep_runs;
  ResetOnExit reset(select);
  select.BindText(1, sweep_id);
  while (select.Step()) {
    counts[static_cast<int>(select.ColumnInt64(0))] = static_cast<int>(select.ColumnInt64(1));
  }
  return counts;
}

int SqliteStore::MarkSweepCancelled(const std::string& sweep_id) {
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "mark sweep " + sweep_id + " cancelled");
  {
    SqliteStatement row(impl_->db, kMarkSweepRowCancelledSql, "mark sweep " + sweep_id);
    row.BindText(1, sweep_id);
    row.Run();
  }
  SqliteStatement update(impl_->db, kMarkSweepCancelledSql,
                         "mark sweep " + sweep_id + " cancelled");
  update.BindText(1, sweep_id);
  update.Run();
  const int marked = static_cast<int>(impl_->db.Changes());
  transaction.Commit();
  return marked;
}

bool SqliteStore::SweepCancelled(const std::string& sweep_id) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_sweep_cancelled;
  ResetOnExit reset(select);
  select.BindText(1, sweep_id);
  return select.Step();
}

std::vector<v1::RunInfo> SqliteStore::ListUnfinishedSweepRuns() const {
  std::vector<v1::RunInfo> runs;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db, kSelectUnfinishedFedSweepRunsSql,
                         "list unfinished runs of sweeps");
  select.BindInt64(1, v1::QUEUED);
  select.BindInt64(2, v1::RUNNING);
  while (select.Step()) ReadRunRowLocked(*impl_, select, runs.emplace_back());
  return runs;
}

}  // namespace mbstream
