// PostgresStore: deleting a run or a model, each in one transaction, and the keep mark
// (delete_sql.h).
#include "server/store/delete_sql.h"
#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"

namespace mbstream {

bool PostgresStore::DeleteRun(const std::string& run_id) {
  return impl_->Transact("delete run " + run_id, [&](pqxx::work& tx) {
    pqxx::result::size_type rows = 0;
    for (const char* sql : kDeleteRunSql) rows = tx.exec_params(sql, run_id).affected_rows();
    return rows > 0;
  });
}

int64_t PostgresStore::DeleteModel(const std::string& model_id) {
  return impl_->Transact("delete model " + model_id, [&](pqxx::work& tx) -> int64_t {
    const int64_t runs = tx.exec_params1(kCountModelRunsSql, model_id)[0].as<int64_t>();
    if (runs > 0) return runs;
    for (const char* sql : kDeleteModelSql) tx.exec_params(sql, model_id);
    return 0;
  });
}

bool PostgresStore::SetRunKeep(const std::string& run_id, bool keep) {
  return impl_->Transact("mark run " + run_id + " kept", [&](pqxx::work& tx) {
    return tx.exec_params(kSetRunKeepPostgres, run_id, keep).affected_rows() > 0;
  });
}

}  // namespace mbstream
