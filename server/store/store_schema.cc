#include "server/store/store_schema.h"

#include <string>
#include <utility>
#include <vector>

#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_statement.h"
#include "server/store/sqlite_transaction.h"
#include "server/store/store_codec.h"
#include "server/store/sweep_sql.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// Proto messages are stored as serialized blobs; columns exist only for what queries filter
// or sort by. Times are Unix epoch milliseconds. `ord` (the rowid) keeps insertion order for
// rows created in the same millisecond; upserts keep it.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE models (
  ord INTEGER PRIMARY KEY,
  id TEXT NOT NULL UNIQUE,
  created_unix_ms INTEGER NOT NULL,
  info BLOB NOT NULL,     -- v1.ModelInfo
  bundle BLOB NOT NULL    -- v1.ModelBundle without its assets (they are in model_assets)
);
CREATE TABLE model_assets (
  model_id TEXT NOT NULL REFERENCES models(id) ON DELETE CASCADE,
  position INTEGER NOT NULL,  -- index in ModelBundle.assets
  name TEXT NOT NULL,
  data BLOB NOT NULL,
  PRIMARY KEY (model_id, position)
);
-- No foreign key to models: built-in models are loaded from files at start and may not be
-- stored, yet their runs are.
CREATE TABLE runs (
  ord INTEGER PRIMARY KEY,
  id TEXT NOT NULL UNIQUE,
  model_id TEXT NOT NULL,
  state INTEGER NOT NULL,  -- v1.RunState
  created_unix_ms INTEGER NOT NULL,
  info BLOB NOT NULL       -- v1.RunInfo
);
CREATE INDEX runs_by_created ON runs (created_unix_ms, ord);
CREATE INDEX runs_by_state ON runs (state);
CREATE INDEX runs_by_model ON runs (model_id);
-- A run's frames in chunks of consecutive frames; each blob is a sequence of
-- length-delimited serialized v1.Frame (see frame_chunks.h).
CREATE TABLE frame_chunks (
  run_id TEXT NOT NULL REFERENCES runs(id) ON DELETE CASCADE,
  chunk INTEGER NOT NULL,        -- 0, 1, 2, ... in seq order
  first_seq INTEGER NOT NULL,    -- Frame.seq of the chunk's first frame
  frame_count INTEGER NOT NULL,
  data BLOB NOT NULL,
  PRIMARY KEY (run_id, chunk)
);
-- No foreign key to runs: probe batches are written as they arrive, possibly before the
-- writer of the run row got the lock.
CREATE TABLE probes (
  run_id TEXT NOT NULL,
  seq INTEGER NOT NULL,   -- Frame.seq the probe was computed for
  probe TEXT NOT NULL,
  report BLOB NOT NULL,   -- v1.ProbeReport
  PRIMARY KEY (run_id, seq, probe)
) WITHOUT ROWID;
)sql";

// Version 2: the probe reports of replays, one set per replay stream (replay.proto). No
// foreign key to runs, as for probes.
constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE probe_sets (
  ord INTEGER PRIMARY KEY,
  id TEXT NOT NULL UNIQUE,
  run_id TEXT NOT NULL,
  info BLOB NOT NULL      -- v1.ProbeSet (its `reports` count is computed when read)
);
CREATE INDEX probe_sets_by_run ON probe_sets (run_id, ord);
CREATE TABLE probe_set_reports (
  set_id TEXT NOT NULL,
  seq INTEGER NOT NULL,
  probe TEXT NOT NULL,
  report BLOB NOT NULL,   -- v1.ProbeReport
  PRIMARY KEY (set_id, seq, probe)
) WITHOUT ROWID;
)sql";

// Version 3: the run queue of several replicas (run_lease.h): who holds a running run's
// lease ("replica/attempt") and until when (Unix ms; 0 = no lease).
constexpr const char* kSchemaV3 = R"sql(
ALTER TABLE runs ADD COLUMN lease_holder TEXT;
ALTER TABLE runs ADD COLUMN lease_expires_unix_ms INTEGER NOT NULL DEFAULT 0;
CREATE INDEX runs_queue ON runs (state, created_unix_ms, ord);
)sql";

// Version 4: runs_by_state goes; runs_queue (state, created_unix_ms, ord) answers every
// lookup by state, and every change of a run's state wrote both (one WAL page more for each
// run queued and each run ended).
constexpr const char* kSchemaV4 = R"sql(
DROP INDEX IF EXISTS runs_by_state;
)sql";

// Version 5: a chunk's frames may live in the frames file beside the database (frame_file.h):
// then `data` is empty and the three columns say where (NULL: the frames are in `data`, as
// every chunk written before version 5).
constexpr const char* kSchemaV5 = R"sql(
ALTER TABLE frame_chunks ADD COLUMN file_offset INTEGER;
ALTER TABLE frame_chunks ADD COLUMN file_bytes INTEGER;
ALTER TABLE frame_chunks ADD COLUMN file_crc32c INTEGER;
)sql";

// Version 6: a run marked to be kept (SetRunKeep): retention never deletes it. A column of its
// own, not in `info`: a run's writers (PutRun, FinishRun) never undo the mark.
constexpr const char* kSchemaV6 = R"sql(
ALTER TABLE runs ADD COLUMN keep INTEGER NOT NULL DEFAULT 0;
)sql";

// Version 7: a run's sweep (RunInfo.sweep_id; NULL for a run started alone), indexed for a
// sweep's progress and cancel, and the mark that its sweep was cancelled, a column of its own
// as `keep` is (sweep_sql.h). BackfillSweeps fills both from each stored RunInfo.
constexpr const char* kSchemaV7 = R"sql(
ALTER TABLE runs ADD COLUMN sweep_id TEXT;
ALTER TABLE runs ADD COLUMN sweep_cancelled INTEGER NOT NULL DEFAULT 0;
CREATE INDEX runs_by_sweep ON runs (sweep_id, sweep_cancelled) WHERE sweep_id IS NOT NULL;
)sql";

// Version 8: a sweep the server feeds (stored_sweep.h): stored whole, its points queued as its
// window frees up. runs.sweep_point (0 for a run started alone) and the indexes of a sweep's
// runs by point (paging) and by state (its counts, and how many of its runs are unfinished).
// BackfillSweepPoints fills the points of the sweep runs stored before it.
constexpr const char* kSchemaV8 = R"sql(
CREATE TABLE sweeps (
  ord INTEGER PRIMARY KEY,
  id TEXT NOT NULL UNIQUE,
  model_id TEXT NOT NULL,
  owner TEXT NOT NULL,
  created_unix_ms INTEGER NOT NULL,
  total_points INTEGER NOT NULL,
  next_point INTEGER NOT NULL,     -- the first point without a run
  queue_window INTEGER NOT NULL,   -- most of its runs queued or running at once
  cancelled INTEGER NOT NULL DEFAULT 0,
  definition BLOB NOT NULL         -- v1.SweepDefinition
);
ALTER TABLE runs ADD COLUMN sweep_point INTEGER NOT NULL DEFAULT 0;
CREATE INDEX runs_by_sweep_point ON runs (sweep_id, sweep_point) WHERE sweep_id IS NOT NULL;
CREATE INDEX runs_by_sweep_state ON runs (sweep_id, state) WHERE sweep_id IS NOT NULL;
)sql";

// Version 7's columns of the runs stored before it (each RunInfo read once, at the upgrade).
void BackfillSweeps(SqliteConnection& connection) {
  std::vector<v1::RunInfo> swept;
  {
    SqliteStatement select(connection, kSelectRunInfosSql, "read runs for schema version 7");
    ResetOnExit reset(select);
    v1::RunInfo info;
    while (select.Step()) {
      ParseFromStore(select.ColumnBlob(1), info, "run " + std::string(select.ColumnText(0)),
                     connection.path());
      if (!info.sweep_id().empty()) swept.push_back(info);
    }
  }
  SqliteStatement update(connection, kBackfillSweepSql, "migrate schema to version 7");
  for (const v1::RunInfo& info : swept) {
    ResetOnExit reset(update);
    update.BindText(1, info.sweep_id());
    update.BindInt64(2, info.sweep_cancelled() ? 1 : 0);
    update.BindText(3, info.id());
    update.Run();
  }
}

// Version 8's column of the sweep runs stored before it.
void BackfillSweepPoints(SqliteConnection& connection) {
  std::vector<std::pair<std::string, int32_t>> points;
  {
    SqliteStatement select(connection, kSelectSweepRunInfosSql, "read runs for schema version 8");
    ResetOnExit reset(select);
    v1::RunInfo info;
    while (select.Step()) {
      ParseFromStore(select.ColumnBlob(1), info, "run " + std::string(select.ColumnText(0)),
                     connection.path());
      points.emplace_back(info.id(), info.sweep_point());
    }
  }
  SqliteStatement update(connection, kBackfillSweepPointSql, "migrate schema to version 8");
  for (const auto& [id, point] : points) {
    ResetOnExit reset(update);
    update.BindInt64(1, point);
    update.BindText(2, id);
    update.Run();
  }
}

void WriteVersion(SqliteConnection& connection) {
  connection.Exec("PRAGMA application_id = " + std::to_string(kStoreApplicationId) +
                      "; PRAGMA user_version = " + std::to_string(kStoreSchemaVersion),
                  "write schema version");
}

int64_t QueryInt(SqliteConnection& connection, const std::string& sql) {
  SqliteStatement statement(connection, sql, sql);
  ResetOnExit reset(statement);
  return statement.Step() ? statement.ColumnInt64(0) : 0;
}

}  // namespace

void EnsureStoreSchema(SqliteConnection& connection) {
  const std::string& path = connection.path();
  SqliteTransaction transaction(connection, "check schema");
  const int64_t application_id = QueryInt(connection, "PRAGMA application_id");
  const int64_t version = QueryInt(connection, "PRAGMA user_version");
  const int64_t tables = QueryInt(connection, "SELECT count(*) FROM sqlite_master");

  if (application_id == 0 && version == 0 && tables == 0) {  // a new, empty database
    connection.Exec(kSchemaV1, "create schema");
    connection.Exec(kSchemaV2, "create schema version 2");
    connection.Exec(kSchemaV3, "create schema version 3");
    connection.Exec(kSchemaV4, "create schema version 4");
    connection.Exec(kSchemaV5, "create schema version 5");
    connection.Exec(kSchemaV6, "create schema version 6");
    connection.Exec(kSchemaV7, "create schema version 7");
    connection.Exec(kSchemaV8, "create schema version 8");
    WriteVersion(connection);
    transaction.Commit();
    return;
  }
  if (application_id != kStoreApplicationId) {
    throw InputError(path +
                     " is a SQLite database of another program, not an mbstream database; "
                     "move it away or start the server with another --data directory");
  }
  if (version > kStoreSchemaVersion) {
    throw InputError(path + " has store schema version " + std::to_string(version) +
                     ", newer than the " + std::to_string(kStoreSchemaVersion) +
                     " this mbstream-server understands; run a newer mbstream-server or use "
                     "another --data directory");
  }
  if (version < 1) {
    throw InputError(path + " is an mbstream database with unknown schema version " +
                     std::to_string(version) + "; move it away or use another --data directory");
  }
  if (version < 2) {  // a version-1 store: add the probe sets
    connection.Exec(kSchemaV2, "migrate schema to version 2");
  }
  if (version < 3) {  // add the run queue's leases
    connection.Exec(kSchemaV3, "migrate schema to version 3");
  }
  if (version < 4) {  // one index less
    connection.Exec(kSchemaV4, "migrate schema to version 4");
  }
  if (version < 5) {  // frames outside the database
    connection.Exec(kSchemaV5, "migrate schema to version 5");
  }
  if (version < 6) {  // the keep mark
    connection.Exec(kSchemaV6, "migrate schema to version 6");
  }
  if (version < 7) {  // the sweep columns
    connection.Exec(kSchemaV7, "migrate schema to version 7");
    BackfillSweeps(connection);
  }
  if (version < 8) {  // the sweeps the server feeds
    connection.Exec(kSchemaV8, "migrate schema to version 8");
    BackfillSweepPoints(connection);
  }
  if (version < kStoreSchemaVersion) WriteVersion(connection);
  transaction.Commit();
}

}  // namespace mbstream
