// PostgresStore: the sweeps the server feeds (the sweeps table, its row locked while points
// are queued, so that replicas feeding one sweep never queue a point twice), a sweep's runs by
// its indexed id and point, and the mark that it was cancelled (sweep_sql.h).
#include <limits>
#include <string>

#include "server/store/postgres_store.h"
#include "server/store/postgres_store_impl.h"
#include "server/store/sweep_sql.h"

namespace mbstream {

namespace {

StoredSweep ReadSweepRow(const pqxx::row& row) {
  StoredSweep sweep;
  sweep.id = row[0].as<std::string>();
  sweep.model_id = row[1].as<std::string>();
  sweep.owner = row[2].as<std::string>();
  sweep.created_unix_ms = row[3].as<int64_t>();
  sweep.total_points = row[4].as<int32_t>();
  sweep.next_point = row[5].as<int32_t>();
  sweep.window = row[6].as<int32_t>();
  sweep.cancelled = row[7].as<bool>();
  sweep.unfinished_runs = static_cast<int32_t>(row[8].as<int64_t>());
  return sweep;
}

struct SweepIdTaken {};  // leaves Transact without committing: the transaction is aborted

const std::string kSelectSweepFeedForUpdateSql = std::string(kSelectSweepFeedSql) + " FOR UPDATE";

}  // namespace

bool PostgresStore::AddSweep(const StoredSweep& sweep) {
  return impl_->Transact("write sweep " + sweep.id, [&](pqxx::work& tx) {
    return tx.exec_params(kInsertSweepSql, sweep.id, sweep.model_id, sweep.owner,
                          sweep.created_unix_ms, sweep.total_points, sweep.window,
                          BlobParam(sweep.definition))
               .affected_rows() > 0;
  });
}

std::optional<StoredSweep> PostgresStore::GetSweep(const std::string& sweep_id,
                                                   bool definition) const {
  return impl_->Transact("read sweep " + sweep_id, [&](pqxx::work& tx) {
    std::optional<StoredSweep> sweep;
    const pqxx::result found = tx.exec_params(
        kSelectSweepSql, sweep_id, static_cast<int>(v1::QUEUED), static_cast<int>(v1::RUNNING));
    if (found.empty()) return sweep;
    sweep = ReadSweepRow(found[0]);
    if (definition) {
      const pqxx::result blob_row = tx.exec_params(kSelectSweepDefinitionSql, sweep_id);
      pqxx::binarystring blob(nullptr, 0);
      if (!blob_row.empty()) sweep->definition = std::string(BlobOf(blob_row[0][0], blob));
    }
    return sweep;
  });
}

std::vector<StoredSweep> PostgresStore::ListOpenSweeps() const {
  return impl_->Transact("list open sweeps", [&](pqxx::work& tx) {
    std::vector<StoredSweep> sweeps;
    for (const pqxx::row& row : tx.exec_params(kSelectOpenSweepsSql, static_cast<int>(v1::QUEUED),
                                               static_cast<int>(v1::RUNNING))) {
      sweeps.push_back(ReadSweepRow(row));
    }
    return sweeps;
  });
}

SweepFeed PostgresStore::AddSweepRuns(const std::string& sweep_id,
                                      const std::vector<v1::RunInfo>& infos) {
  if (infos.empty()) return SweepFeed::kAdded;
  try {
    return impl_->Transact("queue points of sweep " + sweep_id, [&](pqxx::work& tx) {
      const pqxx::result row = tx.exec_params(kSelectSweepFeedForUpdateSql, sweep_id);
      if (row.empty() || row[0][1].as<bool>()) return SweepFeed::kRefused;
      const int64_t next = row[0][0].as<int64_t>();
      const int64_t window = row[0][2].as<int64_t>();
      if (next != infos.front().sweep_point()) return SweepFeed::kRefused;
      const int64_t unfinished =
          tx.exec_params1(kCountUnfinishedSweepRunsSql, sweep_id, static_cast<int>(v1::QUEUED),
                          static_cast<int>(v1::RUNNING))[0]
              .as<int64_t>();
      int64_t queued = 0;
      for (const v1::RunInfo& info : infos) queued += info.state() == v1::QUEUED ? 1 : 0;
      if (queued > 0 && unfinished + queued > window) return SweepFeed::kRefused;
      for (const v1::RunInfo& info : infos) {
        if (!InsertNewRun(tx, info)) throw SweepIdTaken{};
      }
      tx.exec_params(kMoveSweepNextPointSql, next + static_cast<int64_t>(infos.size()), sweep_id);
      return SweepFeed::kAdded;
    });
  } catch (const SweepIdTaken&) {
    return SweepFeed::kIdTaken;
  }
}

std::vector<v1::RunInfo> PostgresStore::ListSweepRuns(const std::string& sweep_id, int first_point,
                                                      int max_runs, bool unfinished_only) const {
  return impl_->Transact("list sweep " + sweep_id, [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> runs;
    pqxx::binarystring blob(nullptr, 0);
    const pqxx::result rows =
        unfinished_only
            ? tx.exec_params(kSelectUnfinishedSweepRunsSql, sweep_id, static_cast<int>(v1::QUEUED),
                             static_cast<int>(v1::RUNNING))
            : tx.exec_params(kSelectSweepRunsSql, sweep_id, first_point,
                             max_runs > 0 ? static_cast<int64_t>(max_runs)
                                          : std::numeric_limits<int64_t>::max());
    for (const pqxx::row& row : rows) {
      ReadRunRow(row, blob, runs.emplace_back(), impl_->location);
      if (runs.back().sweep_point() < first_point) runs.pop_back();
    }
    return runs;
  });
}

Store::StateCounts PostgresStore::CountSweepRuns(const std::string& sweep_id) const {
  return impl_->Transact("count sweep " + sweep_id, [&](pqxx::work& tx) {
    StateCounts counts;
    for (const pqxx::row& row : tx.exec_params(kCountSweepRunsSql, sweep_id)) {
      counts[row[0].as<int>()] = static_cast<int>(row[1].as<int64_t>());
    }
    return counts;
  });
}

int PostgresStore::MarkSweepCancelled(const std::string& sweep_id) {
  return impl_->Transact("mark sweep " + sweep_id + " cancelled", [&](pqxx::work& tx) {
    tx.exec_params(kMarkSweepRowCancelledSql, sweep_id);
    return static_cast<int>(tx.exec_params(kMarkSweepCancelledSql, sweep_id).affected_rows());
  });
}

bool PostgresStore::SweepCancelled(const std::string& sweep_id) const {
  return impl_->Transact("read sweep " + sweep_id, [&](pqxx::work& tx) {
    return !tx.exec_params(kSweepCancelledSql, sweep_id).empty();
  });
}

std::vector<v1::RunInfo> PostgresStore::ListUnfinishedSweepRuns() const {
  return impl_->Transact("list unfinished runs of sweeps", [&](pqxx::work& tx) {
    std::vector<v1::RunInfo> runs;
    pqxx::binarystring blob(nullptr, 0);
    for (const pqxx::row& row :
         tx.exec_params(kSelectUnfinishedFedSweepRunsSql, static_cast<int>(v1::QUEUED),
                        static_cast<int>(v1::RUNNING))) {
      ReadRunRow(row, blob, runs.emplace_back(), impl_->location);
    }
    return runs;
  });
}

}  // namespace mbstream
