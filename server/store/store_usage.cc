// SqliteStore: what the store holds and the blocks its files take (store_usage.h).
#include <sys/stat.h>

#include "server/store/sqlite_store.h"
#include "server/store/store_impl.h"

namespace mbstream {

namespace {

// Blocks of `path` on the disk (0 when it does not exist).
int64_t AllocatedBytes(const std::string& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0 ? static_cast<int64_t>(status.st_blocks) * 512 : 0;
}

// Adds `column` 1 of each (model_id, bytes) row of `sql` to the models' `field` and `total`.
// The caller holds the mutex.
void SumByModelLocked(SqliteStore::Impl& impl, const std::string& sql, int64_t ModelUsage::*field,
                      StoreUsage& usage, int64_t& total) {
  SqliteStatement select(impl.db, sql, "read the store's usage");
  while (select.Step()) {
    usage.models[std::string(select.ColumnText(0))].*field += select.ColumnInt64(1);
    total += select.ColumnInt64(1);
  }
}

}  // namespace

StoreUsage SqliteStore::Usage(const std::vector<std::string>& weigh_runs) const {
  std::lock_guard lock(impl_->mutex);
  StoreUsage usage;
  {
    SqliteStatement select(impl_->db, kRunsByModelAndStateSql, "read the store's usage");
    while (select.Step()) {
      const int64_t runs = select.ColumnInt64(2);
      usage.models[std::string(select.ColumnText(0))].runs += runs;
      usage.runs_by_state[static_cast<int>(select.ColumnInt64(1))] += runs;
      usage.run_bytes += select.ColumnInt64(3);
    }
  }
  SumByModelLocked(*impl_, FrameBytesByModelSql(kSqliteChunkBytes), &ModelUsage::frame_bytes, usage,
                   usage.frame_bytes);
  for (const char* sql : kProbeBytesByModelSql) {
    SumByModelLocked(*impl_, sql, &ModelUsage::probe_bytes, usage, usage.probe_bytes);
  }
  SqliteStatement weigh(impl_->db, RunBytesSql(kSqliteChunkBytes), "weigh runs");
  for (const std::string& run_id : weigh_runs) {
    weigh.BindText(1, run_id);
    if (weigh.Step()) usage.weighed_bytes += weigh.ColumnInt64(0);
    weigh.Reset();
  }
  const std::string& db = impl_->db.path();
  usage.disk_bytes =
      AllocatedBytes(db) + AllocatedBytes(db + "-wal") + impl_->frames.allocated_bytes();
  return usage;
}

}  // namespace mbstream
