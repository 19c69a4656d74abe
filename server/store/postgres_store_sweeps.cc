// PostgresStore: a sweep's runs by its indexed id, and the mark that it was cancelled
// (sweep_sql.h).
#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"
#include "server/store/sweep_sql.h"

namespace mbstream {

std::vector<v1::RunInfo> PostgresStore::ListSweepRuns(const std::string& sweep_id) const {
  return impl_->Transact("list sweep " + sweep_id, [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> runs;
    pqxx::binarystring blob(nullptr, 0);
    for (const pqxx::row& row : tx.exec_params(kSelectSweepRunsSql, sweep_id)) {
      ReadRunRow(row, blob, runs.emplace_back(), impl_->location);
    }
    return runs;
  });
}

int PostgresStore::MarkSweepCancelled(const std::string& sweep_id) {
  return impl_->Transact("mark sweep " + sweep_id + " cancelled", [&](pqxx::work& tx) {
    return static_cast<int>(tx.exec_params(kMarkSweepCancelledSql, sweep_id).affected_rows());
  });
}

bool PostgresStore::SweepCancelled(const std::string& sweep_id) const {
  return impl_->Transact("read sweep " + sweep_id, [&](pqxx::work& tx) {
    return !tx.exec_params(kSweepCancelledSql, sweep_id).empty();
  });
}

}  // namespace mbstream
