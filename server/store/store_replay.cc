// Store: what replays need: the chunk holding a frame (seek) and the replays' probe sets.
// Each statement is prepared per call: replays are rare next to frames and probes.
#include "server/store/sqlite_store.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_impl.h"

namespace mbstream {

namespace {

constexpr const char* kSelectSet =
    "SELECT s.info, (SELECT count(*) FROM probe_set_reports r WHERE r.set_id = s.id) "
    "FROM probe_sets s ";

v1::ProbeSet ReadSet(const SqliteStatement& select, const std::string& path) {
  v1::ProbeSet set;
  ParseFromStore(select.ColumnBlob(0), set, "probe set", path);
  set.set_reports(select.ColumnInt64(1));
  return set;
}

}  // namespace

std::optional<int64_t> SqliteStore::FrameChunkHolding(const std::string& run_id,
                                                      int64_t seq) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db,
                         "SELECT chunk FROM frame_chunks WHERE run_id = ?1 AND first_seq <= ?2 "
                         "AND first_seq + frame_count > ?2 ORDER BY chunk LIMIT 1",
                         "find the frame chunk of a seek");
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  select.BindInt64(2, seq);
  if (!select.Step()) return std::nullopt;
  return select.ColumnInt64(0);
}

void SqliteStore::CreateProbeSet(const v1::ProbeSet& set) {
  v1::ProbeSet stored = set;
  stored.set_reports(0);
  if (stored.created_unix_ms() == 0) stored.set_created_unix_ms(UnixNowMs());
  const std::string bytes = SerializeForStore(stored, "probe set " + set.id());
  std::lock_guard lock(impl_->mutex);
  SqliteStatement insert(impl_->db, "INSERT INTO probe_sets (id, run_id, info) VALUES (?1, ?2, ?3)",
                         "create probe set");
  ResetOnExit reset(insert);
  insert.BindText(1, set.id());
  insert.BindText(2, set.run_id());
  insert.BindBlob(3, bytes);
  insert.Run();
}

void SqliteStore::AddProbeSetReports(const std::string& set_id,
                                     const std::vector<v1::ProbeReport>& reports) {
  if (reports.empty()) return;
  std::vector<std::string> bytes;
  bytes.reserve(reports.size());
  for (const v1::ProbeReport& report : reports) {
    bytes.push_back(SerializeForStore(report, "probe report of probe set " + set_id));
  }
  std::lock_guard lock(impl_->mutex);
  SqliteTransaction transaction(impl_->db, "store probe set reports");
  SqliteStatement upsert(impl_->db,
                         "INSERT OR REPLACE INTO probe_set_reports (set_id, seq, probe, report) "
                         "VALUES (?1, ?2, ?3, ?4)",
                         "write probe set report");
  for (std::size_t i = 0; i < reports.size(); ++i) {
    ResetOnExit reset(upsert);
    upsert.BindText(1, set_id);
    upsert.BindInt64(2, reports[i].seq());
    upsert.BindText(3, reports[i].probe());
    upsert.BindBlob(4, bytes[i]);
    upsert.Run();
  }
  transaction.Commit();
}

std::vector<v1::ProbeSet> SqliteStore::ListProbeSets(const std::string& run_id) const {
  std::vector<v1::ProbeSet> sets;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db, std::string(kSelectSet) + "WHERE s.run_id = ?1 ORDER BY s.ord",
                         "list probe sets");
  ResetOnExit reset(select);
  select.BindText(1, run_id);
  while (select.Step()) sets.push_back(ReadSet(select, impl_->db.path()));
  return sets;
}

std::optional<v1::ProbeSet> SqliteStore::GetProbeSet(const std::string& set_id) const {
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db, std::string(kSelectSet) + "WHERE s.id = ?1", "read probe set");
  ResetOnExit reset(select);
  select.BindText(1, set_id);
  if (!select.Step()) return std::nullopt;
  return ReadSet(select, impl_->db.path());
}

std::vector<v1::ProbeReport> SqliteStore::GetProbeSetReports(const std::string& set_id) const {
  std::vector<v1::ProbeReport> reports;
  std::lock_guard lock(impl_->mutex);
  SqliteStatement select(impl_->db,
                         "SELECT report FROM probe_set_reports WHERE set_id = ?1 "
                         "ORDER BY seq, probe",
                         "read probe set reports");
  ResetOnExit reset(select);
  select.BindText(1, set_id);
  while (select.Step()) {
    ParseFromStore(select.ColumnBlob(0), reports.emplace_back(),
                   "probe report of probe set " + set_id, impl_->db.path());
  }
  return reports;
}

}  // namespace mbstream
