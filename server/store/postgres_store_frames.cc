// PostgresStore: frames (chunk blobs), probe reports and the replays' probe sets (multi-row
// inserts, never one statement per report).
#include <algorithm>
#include <map>
#include <tuple>

#include "server/store/frame_chunks.h"
#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// Rows per multi-row INSERT: 4 parameters each, well under PostgreSQL's 65,535.
constexpr std::size_t kReportRowsPerStatement = 2000;

struct ReportRow {
  std::string key;  // run id or probe set id
  int64_t seq = 0;
  std::string probe;
  std::string report;  // serialized v1.ProbeReport
};

// Inserts `rows` into `table` (columns key_column, seq, probe, report), a row of the same
// (key, seq, probe) replacing the old one: the last of duplicates within `rows` wins, as
// with one INSERT OR REPLACE per row in SQLite.
void UpsertReports(pqxx::work& tx, const std::string& table, const std::string& key_column,
                   const std::vector<ReportRow>& rows) {
  std::map<std::tuple<std::string_view, int64_t, std::string_view>, std::size_t> last;
  for (std::size_t i = 0; i < rows.size(); ++i) last[{rows[i].key, rows[i].seq, rows[i].probe}] = i;
  std::vector<std::size_t> kept;
  kept.reserve(last.size());
  for (const auto& [key, index] : last) kept.push_back(index);
  std::sort(kept.begin(), kept.end());

  for (std::size_t begin = 0; begin < kept.size(); begin += kReportRowsPerStatement) {
    const std::size_t n = std::min(kReportRowsPerStatement, kept.size() - begin);
    std::vector<std::string> keys, probes;
    std::vector<int64_t> seqs;
    std::vector<pqxx::binarystring> reports;
    std::string sql = "INSERT INTO " + table + " (" + key_column + ", seq, probe, report) VALUES ";
    for (std::size_t i = 0; i < n; ++i) {
      const ReportRow& row = rows[kept[begin + i]];
      keys.push_back(row.key);
      seqs.push_back(row.seq);
      probes.push_back(row.probe);
      reports.push_back(BlobParam(row.report));
      const auto param = [&](std::size_t column) {
        return "$" + std::to_string(column * n + i + 1);
      };
      sql += (i == 0 ? "(" : ", (") + param(0) + "::text, " + param(1) + "::bigint, " + param(2) +
             "::text, " + param(3) + "::bytea)";
    }
    sql += " ON CONFLICT (" + key_column + ", seq, probe) DO UPDATE SET report = excluded.report";
    tx.exec_params(
        sql, pqxx::prepare::make_dynamic_params(keys), pqxx::prepare::make_dynamic_params(seqs),
        pqxx::prepare::make_dynamic_params(probes), pqxx::prepare::make_dynamic_params(reports));
  }
}

std::vector<v1::ProbeReport> ReadReports(pqxx::work& tx, const char* statement,
                                         const std::string& key, const std::string& what,
                                         const std::string& location) {
  std::vector<v1::ProbeReport> reports;
  pqxx::binarystring blob(nullptr, 0);
  for (const pqxx::row& row : tx.exec_prepared(statement, key)) {
    ParseFromStore(BlobOf(row[0], blob), reports.emplace_back(), what, location);
  }
  return reports;
}

v1::ProbeSet ReadSet(const pqxx::row& row, const std::string& location) {
  v1::ProbeSet set;
  pqxx::binarystring blob(nullptr, 0);
  ParseFromStore(BlobOf(row[0], blob), set, "probe set", location);
  set.set_reports(row[1].as<int64_t>());
  return set;
}

void UpsertChunk(pqxx::work& tx, const std::string& run_id, int64_t index,
                 const EncodedFrameChunk& chunk) {
  tx.exec_prepared("upsert_frame_chunk", run_id, index, chunk.first_seq, chunk.frame_count,
                   BlobParam(chunk.data));
}

}  // namespace

bool PostgresStore::PutFrameChunk(const std::string& run_id, int64_t index,
                                  const EncodedFrameChunk& chunk, const std::string& holder) {
  return impl_->Transact("insert frames of run " + run_id, [&](pqxx::work& tx) {
    if (!holder.empty() && !HoldsLease(tx, run_id, holder)) return false;
    UpsertChunk(tx, run_id, index, chunk);
    tx.exec_prepared("delete_frame_chunks_after", run_id, index);  // an earlier attempt's
    return true;
  });
}

KeptFrames KeptFramesOf(pqxx::transaction_base& tx, const std::string& run_id) {
  KeptFrames kept;
  pqxx::binarystring blob(nullptr, 0);
  while (true) {
    const pqxx::result counted = tx.exec_params(
        "SELECT COUNT(*), COALESCE(SUM(frame_count), 0), MAX(chunk) FROM frame_chunks "
        "WHERE run_id = $1",
        run_id);
    if (counted.empty() || counted[0][0].as<int64_t>() == 0) return kept;
    const int64_t frames = counted[0][1].as<int64_t>();
    const int64_t last = counted[0][2].as<int64_t>();
    const pqxx::result chunk = tx.exec_params(
        "SELECT data FROM frame_chunks WHERE run_id = $1 AND chunk = $2", run_id, last);
    if (!chunk.empty() && ReadKeptFrames(frames, BlobOf(chunk[0][0], blob), kept)) return kept;
    tx.exec_prepared("delete_frame_chunks_after", run_id, last - 1);
    ++kept.dropped_chunks;
  }
}

bool PostgresStore::FinishRun(const v1::RunInfo& info, int64_t index,
                              const EncodedFrameChunk& last_chunk, const std::string& holder) {
  return impl_->Transact("finish run " + info.id(), [&](pqxx::work& tx) {
    if (!holder.empty() && !HoldsLease(tx, info.id(), holder)) return false;
    UpsertRun(tx, info);
    if (last_chunk.frame_count > 0) UpsertChunk(tx, info.id(), index, last_chunk);
    tx.exec_prepared("delete_frame_chunks_after", info.id(),
                     last_chunk.frame_count > 0 ? index : index - 1);
    return true;
  });
}

void PostgresStore::FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) {
  const std::vector<EncodedFrameChunk> chunks = EncodeFrameChunks(frames);
  impl_->Transact("finish run " + info.id(), [&](pqxx::work& tx) {
    UpsertRun(tx, info);
    tx.exec_prepared("delete_frame_chunks", info.id());
    for (std::size_t i = 0; i < chunks.size(); ++i) {
      UpsertChunk(tx, info.id(), static_cast<int64_t>(i), chunks[i]);
    }
  });
}

std::optional<int64_t> PostgresStore::GetFrameChunkData(const std::string& run_id, int64_t index,
                                                        std::string& data) const {
  return impl_->Transact("read frames of run " + run_id, [&](pqxx::work& tx) {
    std::optional<int64_t> next;
    const pqxx::result rows = tx.exec_prepared("select_frame_chunk", run_id, index);
    if (rows.empty()) return next;
    const pqxx::binarystring blob(rows[0][1]);
    data.assign(blob.get(), blob.size());
    next = rows[0][0].as<int64_t>() + 1;
    return next;
  });
}

std::optional<int64_t> PostgresStore::FrameChunkHolding(const std::string& run_id,
                                                        int64_t seq) const {
  return impl_->Transact("find the frame chunk of a seek", [&](pqxx::work& tx) {
    std::optional<int64_t> chunk;
    const pqxx::result rows = tx.exec_prepared("select_frame_chunk_holding", run_id, seq);
    if (!rows.empty()) chunk = rows[0][0].as<int64_t>();
    return chunk;
  });
}

void PostgresStore::AddProbes(const std::vector<v1::ProbeReport>& reports) {
  if (reports.empty()) return;
  std::vector<ReportRow> rows;
  rows.reserve(reports.size());
  for (const v1::ProbeReport& report : reports) {
    rows.push_back({report.run_id(), report.seq(), report.probe(),
                    SerializeForStore(report, "probe report of run " + report.run_id())});
  }
  impl_->Transact("store probe reports",
                  [&](pqxx::work& tx) { UpsertReports(tx, "probes", "run_id", rows); });
}

std::vector<v1::ProbeReport> PostgresStore::GetProbes(const std::string& run_id) const {
  return impl_->Transact("read probe reports", [&](pqxx::work& tx) {
    return ReadReports(tx, "select_probes", run_id, "probe report of run " + run_id,
                       impl_->location);
  });
}

void PostgresStore::CreateProbeSet(const v1::ProbeSet& set) {
  v1::ProbeSet stored = set;
  stored.set_reports(0);
  if (stored.created_unix_ms() == 0) stored.set_created_unix_ms(UnixNowMs());
  const std::string bytes = SerializeForStore(stored, "probe set " + set.id());
  impl_->Transact("create probe set", [&](pqxx::work& tx) {
    tx.exec_prepared("insert_probe_set", set.id(), set.run_id(), BlobParam(bytes));
  });
}

void PostgresStore::AddProbeSetReports(const std::string& set_id,
                                       const std::vector<v1::ProbeReport>& reports) {
  if (reports.empty()) return;
  std::vector<ReportRow> rows;
  rows.reserve(reports.size());
  for (const v1::ProbeReport& report : reports) {
    rows.push_back({set_id, report.seq(), report.probe(),
                    SerializeForStore(report, "probe report of probe set " + set_id)});
  }
  impl_->Transact("store probe set reports",
                  [&](pqxx::work& tx) { UpsertReports(tx, "probe_set_reports", "set_id", rows); });
}

std::vector<v1::ProbeSet> PostgresStore::ListProbeSets(const std::string& run_id) const {
  return impl_->Transact("list probe sets", [&](pqxx::work& tx) {
    std::vector<v1::ProbeSet> sets;
    for (const pqxx::row& row : tx.exec_prepared("select_probe_sets", run_id)) {
      sets.push_back(ReadSet(row, impl_->location));
    }
    return sets;
  });
}

std::optional<v1::ProbeSet> PostgresStore::GetProbeSet(const std::string& set_id) const {
  return impl_->Transact("read probe set", [&](pqxx::work& tx) {
    std::optional<v1::ProbeSet> set;
    const pqxx::result rows = tx.exec_prepared("select_probe_set", set_id);
    if (!rows.empty()) set = ReadSet(rows[0], impl_->location);
    return set;
  });
}

std::vector<v1::ProbeReport> PostgresStore::GetProbeSetReports(const std::string& set_id) const {
  return impl_->Transact("read probe set reports", [&](pqxx::work& tx) {
    return ReadReports(tx, "select_probe_set_reports", set_id,
                       "probe report of probe set " + set_id, impl_->location);
  });
}

}  // namespace mbstream
