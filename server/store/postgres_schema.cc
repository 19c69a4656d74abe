#include "server/store/postgres_schema.h"

#include <string_view>

#include <pqxx/pqxx>

#include "mbstream/v1/run.pb.h"
#include "server/store/store_codec.h"
#include "server/store/store_schema.h"
#include "server/store/sweep_sql.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// The tables of store_schema.cc in PostgreSQL's types: proto messages as bytea, columns only
// for what queries filter or sort by, times in Unix epoch milliseconds, `ord` keeping
// insertion order (upserts keep it). Probe names sort byte-wise (COLLATE "C") as in SQLite.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE models (
  ord bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id text NOT NULL UNIQUE,
  created_unix_ms bigint NOT NULL,
  info bytea NOT NULL,     -- v1.ModelInfo
  bundle bytea NOT NULL    -- v1.ModelBundle without its assets (they are in model_assets)
);
CREATE TABLE model_assets (
  model_id text NOT NULL REFERENCES models(id) ON DELETE CASCADE,
  position integer NOT NULL,  -- index in ModelBundle.assets
  name text NOT NULL,
  data bytea NOT NULL,
  PRIMARY KEY (model_id, position)
);
CREATE TABLE runs (
  ord bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id text NOT NULL UNIQUE,
  model_id text NOT NULL,
  state integer NOT NULL,  -- v1.RunState
  created_unix_ms bigint NOT NULL,
  info bytea NOT NULL      -- v1.RunInfo
);
CREATE INDEX runs_by_created ON runs (created_unix_ms, ord);
CREATE INDEX runs_by_state ON runs (state);
CREATE INDEX runs_by_model ON runs (model_id);
CREATE TABLE frame_chunks (
  run_id text NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  chunk bigint NOT NULL,
  first_seq bigint NOT NULL,
  frame_count bigint NOT NULL,
  data bytea NOT NULL,     -- length-delimited v1.Frame (frame_chunks.h)
  PRIMARY KEY (run_id, chunk)
);
-- Serialized doubles hardly compress: store the chunks uncompressed, out of line.
ALTER TABLE frame_chunks ALTER COLUMN data SET STORAGE EXTERNAL;
CREATE TABLE probes (
  run_id text NOT NULL,
  seq bigint NOT NULL,
  probe text COLLATE "C" NOT NULL,
  report bytea NOT NULL,   -- v1.ProbeReport
  PRIMARY KEY (run_id, seq, probe)
);
)sql";

constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE probe_sets (
  ord bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id text NOT NULL UNIQUE,
  run_id text NOT NULL,
  info bytea NOT NULL      -- v1.ProbeSet (its `reports` count is computed when read)
);
CREATE INDEX probe_sets_by_run ON probe_sets (run_id, ord);
CREATE TABLE probe_set_reports (
  set_id text NOT NULL,
  seq bigint NOT NULL,
  probe text COLLATE "C" NOT NULL,
  report bytea NOT NULL,   -- v1.ProbeReport
  PRIMARY KEY (set_id, seq, probe)
);
)sql";

// The run queue's leases (run_lease.h), as in store_schema.cc.
constexpr const char* kSchemaV3 = R"sql(
ALTER TABLE runs ADD COLUMN lease_holder text;
ALTER TABLE runs ADD COLUMN lease_expires_unix_ms bigint NOT NULL DEFAULT 0;
CREATE INDEX runs_queue ON runs (state, created_unix_ms, ord);
)sql";

// One index less, as in store_schema.cc (runs_queue answers every lookup by state).
constexpr const char* kSchemaV4 = R"sql(
DROP INDEX IF EXISTS runs_by_state;
)sql";

// Version 5 changed the SQLite store only (its frames moved to a file of their own,
// frame_file.h); PostgreSQL keeps them in frame_chunks.data, which replicas share.
constexpr const char* kSchemaV5 = "SELECT 1";

// Version 6: a run marked to be kept, as in store_schema.cc.
constexpr const char* kSchemaV6 = "ALTER TABLE runs ADD COLUMN keep boolean NOT NULL DEFAULT false";

// Version 7: a run's sweep, indexed, and the mark that it was cancelled, as in store_schema.cc;
// BackfillSweeps fills both from each stored RunInfo.
constexpr const char* kSchemaV7 = R"sql(
ALTER TABLE runs ADD COLUMN sweep_id text;
ALTER TABLE runs ADD COLUMN sweep_cancelled boolean NOT NULL DEFAULT false;
CREATE INDEX runs_by_sweep ON runs (sweep_id, sweep_cancelled) WHERE sweep_id IS NOT NULL;
)sql";

// Version 8: the sweeps the server feeds, as in store_schema.cc; BackfillSweepPoints fills
// the points of the sweep runs stored before it.
constexpr const char* kSchemaV8 = R"sql(
CREATE TABLE sweeps (
  ord bigint GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  id text NOT NULL UNIQUE,
  model_id text NOT NULL,
  owner text NOT NULL,
  created_unix_ms bigint NOT NULL,
  total_points integer NOT NULL,
  next_point integer NOT NULL,
  queue_window integer NOT NULL,
  cancelled boolean NOT NULL DEFAULT false,
  definition bytea NOT NULL  -- v1.SweepDefinition
);
ALTER TABLE runs ADD COLUMN sweep_point integer NOT NULL DEFAULT 0;
CREATE INDEX runs_by_sweep_point ON runs (sweep_id, sweep_point) WHERE sweep_id IS NOT NULL;
CREATE INDEX runs_by_sweep_state ON runs (sweep_id, state) WHERE sweep_id IS NOT NULL;
)sql";

// Version 7's columns of the runs stored before it (each RunInfo read once, at the upgrade).
void BackfillSweeps(pqxx::work& tx, const std::string& location) {
  v1::RunInfo info;
  pqxx::binarystring blob(nullptr, 0);
  for (const pqxx::row& row : tx.exec(kSelectRunInfosSql)) {
    blob = pqxx::binarystring(row[1]);
    ParseFromStore(std::string_view(blob.get(), blob.size()), info,
                   "run " + row[0].as<std::string>(), location);
    if (info.sweep_id().empty()) continue;
    tx.exec_params(kBackfillSweepSql, info.sweep_id(), info.sweep_cancelled(), info.id());
  }
}

// Version 8's column of the sweep runs stored before it.
void BackfillSweepPoints(pqxx::work& tx, const std::string& location) {
  v1::RunInfo info;
  pqxx::binarystring blob(nullptr, 0);
  for (const pqxx::row& row : tx.exec(kSelectSweepRunInfosSql)) {
    blob = pqxx::binarystring(row[1]);
    ParseFromStore(std::string_view(blob.get(), blob.size()), info,
                   "run " + row[0].as<std::string>(), location);
    tx.exec_params(kBackfillSweepPointSql, info.sweep_point(), info.id());
  }
}

struct Migration {
  int version;      // the version the step leads to
  const char* sql;  // from the version before
  void (*backfill)(pqxx::work& tx, const std::string& location) = nullptr;  // then, if any
};

constexpr Migration kMigrations[] = {{1, kSchemaV1},
                                     {2, kSchemaV2},
                                     {3, kSchemaV3},
                                     {4, kSchemaV4},
                                     {5, kSchemaV5},
                                     {6, kSchemaV6},
                                     {7, kSchemaV7, BackfillSweeps},
                                     {8, kSchemaV8, BackfillSweepPoints}};
static_assert(sizeof(kMigrations) / sizeof(kMigrations[0]) == kPostgresSchemaVersion);
static_assert(kPostgresSchemaVersion == kStoreSchemaVersion, "both stores, one behaviour");

}  // namespace

void EnsurePostgresSchema(pqxx::connection_base& db, const std::string& location,
                          int target_version) {
  pqxx::work tx(db, "mbstream schema");
  tx.exec_params("SELECT pg_advisory_xact_lock($1)", static_cast<int64_t>(kStoreApplicationId));
  int version = 0;
  if (!tx.exec1("SELECT to_regclass('mbstream_schema') IS NOT NULL")[0].as<bool>()) {
    const auto tables = tx.exec1(
                              "SELECT count(*) FROM information_schema.tables "
                              "WHERE table_schema = current_schema()")[0]
                            .as<int64_t>();
    if (tables > 0) {
      throw InputError(location + " holds " + std::to_string(tables) +
                       " tables of another program and no mbstream schema; give --store an "
                       "empty database of its own (CREATE DATABASE mbstream)");
    }
    tx.exec("CREATE TABLE mbstream_schema (version integer NOT NULL)");
    tx.exec("INSERT INTO mbstream_schema (version) VALUES (0)");
  } else {
    version = tx.exec1("SELECT version FROM mbstream_schema")[0].as<int>();
  }
  if (version > kPostgresSchemaVersion) {
    throw InputError(location + " has store schema version " + std::to_string(version) +
                     ", newer than the " + std::to_string(kPostgresSchemaVersion) +
                     " this mbstream-server understands; run a newer mbstream-server or give "
                     "--store another database");
  }
  for (const Migration& migration : kMigrations) {
    if (migration.version > version && migration.version <= target_version) {
      tx.exec(migration.sql,
              "migrate the store schema to version " + std::to_string(migration.version));
      if (migration.backfill != nullptr) migration.backfill(tx, location);
      tx.exec_params("UPDATE mbstream_schema SET version = $1", migration.version);
    }
  }
  tx.commit();
}

}  // namespace mbstream
