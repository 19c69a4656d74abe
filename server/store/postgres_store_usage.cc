// PostgresStore: what the store holds (store_usage.h); its backups are PostgreSQL's (pg_dump).
#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"
#include "shared/common/check.h"

namespace mbstream {

StoreUsage PostgresStore::Usage(const std::vector<std::string>& weigh_runs) const {
  return impl_->Transact("read the store's usage", [&](pqxx::work& tx) {
    StoreUsage usage;
    for (const auto& row : tx.exec(kRunsByModelAndStateSql)) {
      const int64_t runs = row[2].as<int64_t>();
      usage.models[row[0].as<std::string>()].runs += runs;
      usage.runs_by_state[row[1].as<int>()] += runs;
      usage.run_bytes += row[3].as<int64_t>();
    }
    for (const auto& row : tx.exec(FrameBytesByModelSql(kPostgresChunkBytes))) {
      usage.models[row[0].as<std::string>()].frame_bytes += row[1].as<int64_t>();
      usage.frame_bytes += row[1].as<int64_t>();
    }
    for (const char* sql : kProbeBytesByModelSql) {
      for (const auto& row : tx.exec(sql)) {
        usage.models[row[0].as<std::string>()].probe_bytes += row[1].as<int64_t>();
        usage.probe_bytes += row[1].as<int64_t>();
      }
    }
    const std::string weigh = RunBytesSql(kPostgresChunkBytes);
    for (const std::string& run_id : weigh_runs) {
      usage.weighed_bytes += tx.exec_params1(weigh, run_id)[0].as<int64_t>();
    }
    return usage;  // disk_bytes: the database server's disk, not this server's
  });
}

StoreBackup PostgresStore::Backup(const std::string&) {
  throw InputError(
      "a PostgreSQL store is backed up with PostgreSQL's own tools (pg_dump; docs/cluster.md), "
      "not by mbstream-server");
}

}  // namespace mbstream
