// Store: probe reports, keyed by (run_id, seq, probe).
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

void SqliteStore::AddProbes(const std::vector<v1::ProbeReport>& reports) {
  if (reports.empty()) return;
  std::vector<std::string> bytes;
  bytes.reserve(reports.size());
  for (const v1::ProbeReport& report : reports) {
    bytes.push_back(SerializeForStore(report, "probe report of run " + report.run_id()));
  }
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "store probe reports");
  for (std::size_t i = 0; i < reports.size(); ++i) {
    SqliteStatement& upsert = impl_->upsert_probe;
    ResetOnExit reset(upsert);
    upsert.BindText(1, reports[i].run_id());
    upsert.BindInt64(2, reports[i].seq());
    upsert.BindText(3, reports[i].probe());
    upsert.BindBlob(4, bytes[i]);
    upsert.Run();
  }
  transaction.Commit();
}

std::vector<v1::ProbeReport> SqliteStore::GetProbes(const std::string& run_id) const {
  std::vector<v1::ProbeReport> reports;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement& select = impl_->select_probes;
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  while (select.Step()) {
    ParseFromStore(select.ColumnBlob(0), reports.emplace_back(), "probe report of run " + run_id,
                   impl_->db.path());
  }
  return reports;
}

}  // namespace mbstream
