// SqliteStore::Open, the prepared statements and the helpers shared by the store_*.cc files.
#include "server/store/sqlite_store.h"

#include <filesystem>
#include <system_error>
#include <utility>

#include <sqlite3.h>

#include "server/store/sqlite_error.h"
#include "server/store/store_impl.h"
#include "server/store/store_schema.h"
#include "server/store/sweep_sql.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

// How long a statement waits for a lock held by another connection (ms). Only one server
// should use a data directory; this covers short-lived readers such as the sqlite3 shell.
constexpr int kBusyTimeoutMs = 5000;

// Largest WAL file kept after a checkpoint (bytes): a burst of frame chunks may grow the WAL,
// this truncates it back afterwards.
constexpr int64_t kJournalSizeLimitBytes = 64 << 20;

void CreateDirectory(const std::string& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error || !std::filesystem::is_directory(directory, error)) {
    throw InputError("cannot create the data directory " + directory + ": " +
                     (error ? error.message() : "a file of that name exists") +
                     "; choose another --data directory or fix the path and its permissions");
  }
}

SqliteConnection OpenConfigured(const std::string& path) {
  SqliteConnection connection = SqliteConnection::Open(path);
  connection.SetBusyTimeout(kBusyTimeoutMs);
  // WAL: readers never block the writer and a crash never leaves a half-written commit.
  // synchronous=NORMAL in WAL mode survives a killed process; only a power cut can lose the
  // last commits (never corrupt the file).
  // Pages freed by deletions go back to the file system (PRAGMA incremental_vacuum after each
  // DeleteRun). Takes effect only before the first table exists: an older store is converted
  // once by EnableIncrementalVacuum.
  connection.Exec("PRAGMA auto_vacuum = INCREMENTAL", "enable incremental vacuum");
  connection.Exec("PRAGMA journal_mode = WAL", "switch to the WAL journal");
  connection.Exec(
      "PRAGMA synchronous = NORMAL; PRAGMA foreign_keys = ON; "
      "PRAGMA journal_size_limit = " +
          std::to_string(kJournalSizeLimitBytes),
      "configure connection");
  return connection;
}

// A store created before incremental vacuum (auto_vacuum NONE) is rewritten once (VACUUM; the
// database without the frames file is small since schema version 5).
void EnableIncrementalVacuum(SqliteConnection& connection) {
  constexpr int kIncremental = 2;
  bool incremental = false;
  {
    SqliteStatement mode(connection, "PRAGMA auto_vacuum", "read the vacuum mode");
    incremental = mode.Step() && mode.ColumnInt64(0) == kIncremental;
  }
  if (!incremental) connection.Exec("VACUUM", "convert the store to incremental vacuum");
}

}  // namespace

SqliteStore::Impl::Impl(SqliteConnection connection, const std::string& frames_path)
    : db(std::move(connection)),
      insert_model(db,
                   "INSERT INTO models (id, created_unix_ms, info, bundle) VALUES (?1, ?2, ?3, ?4) "
                   "ON CONFLICT (id) DO NOTHING",
                   "insert model"),
      insert_asset(db,
                   "INSERT INTO model_assets (model_id, position, name, data) "
                   "VALUES (?1, ?2, ?3, ?4)",
                   "insert model asset"),
      select_model_infos(db, "SELECT info FROM models ORDER BY created_unix_ms, ord",
                         "list models"),
      select_model_bundle(db, "SELECT bundle FROM models WHERE id = ?1", "read model bundle"),
      select_model_assets(db,
                          "SELECT name, data FROM model_assets WHERE model_id = ?1 "
                          "ORDER BY position",
                          "read model assets"),
      select_model_asset_names(db,
                               "SELECT name FROM model_assets WHERE model_id = ?1 "
                               "ORDER BY position",
                               "read model asset names"),
      select_model_bytes(db,
                         "SELECT m.id, length(m.bundle) + COALESCE((SELECT sum(length(a.data)) "
                         "FROM model_assets a WHERE a.model_id = m.id), 0) FROM models m",
                         "read model sizes"),
      upsert_run(db,
                 "INSERT INTO runs (id, model_id, state, created_unix_ms, info, sweep_id, "
                 "sweep_point) VALUES (?1, ?2, ?3, ?4, ?5, NULLIF(?6, ''), ?7) ON CONFLICT (id) "
                 "DO UPDATE SET model_id = excluded.model_id, state = excluded.state, "
                 "created_unix_ms = excluded.created_unix_ms, info = excluded.info, "
                 "sweep_id = excluded.sweep_id, sweep_point = excluded.sweep_point",
                 "write run"),
      insert_new_run(db,
                     "INSERT INTO runs (id, model_id, state, created_unix_ms, info, sweep_id, "
                     "sweep_point) VALUES (?1, ?2, ?3, ?4, ?5, NULLIF(?6, ''), ?7) "
                     "ON CONFLICT (id) DO NOTHING",
                     "write new run"),
      select_run(db, "SELECT info, keep, sweep_cancelled FROM runs WHERE id = ?1", "read run"),
      select_runs(db, "SELECT info, keep, sweep_cancelled FROM runs ORDER BY created_unix_ms, ord",
                  "list runs"),
      select_sweep_runs(db, kSelectSweepRunsSql, "list a sweep's runs"),
      count_sweep_runs(db, kCountSweepRunsSql, "count a sweep's runs"),
      select_sweep(db, kSelectSweepSql, "read a sweep"),
      select_sweep_cancelled(db, kSweepCancelledSql, "read a sweep's mark"),
      select_unfinished_runs(db, kSelectUnfinishedRunsSql, "list unfinished runs"),
      select_oldest_queued_run(
          db, "SELECT info FROM runs WHERE state = ?1 ORDER BY created_unix_ms, ord LIMIT 1",
          "claim a queued run"),
      select_run_lease(db, "SELECT 1 FROM runs WHERE id = ?1 AND state = ?2 AND lease_holder = ?3",
                       "check run lease"),
      update_run_lease(
          db, "UPDATE runs SET lease_holder = ?2, lease_expires_unix_ms = ?3 WHERE id = ?1",
          "write run lease"),
      delete_frame_chunks(db, "DELETE FROM frame_chunks WHERE run_id = ?1", "delete old frames"),
      delete_frame_chunks_after(db, "DELETE FROM frame_chunks WHERE run_id = ?1 AND chunk > ?2",
                                "delete stale frames"),
      insert_frame_chunk(db,
                         "INSERT OR REPLACE INTO frame_chunks "
                         "(run_id, chunk, first_seq, frame_count, data, file_offset, file_bytes, "
                         "file_crc32c) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)",
                         "insert frames"),
      select_frame_chunk(db,
                         "SELECT chunk, data, file_offset, file_bytes, file_crc32c FROM "
                         "frame_chunks WHERE run_id = ?1 AND chunk >= ?2 "
                         "ORDER BY chunk LIMIT 1",
                         "read frames"),
      upsert_probe(db,
                   "INSERT OR REPLACE INTO probes (run_id, seq, probe, report) "
                   "VALUES (?1, ?2, ?3, ?4)",
                   "write probe report"),
      select_probes(db, "SELECT report FROM probes WHERE run_id = ?1 ORDER BY seq, probe",
                    "read probe reports"),
      frames(frames_path),
      checkpointer(db, [this] { frames.Sync(); }) {}

std::unique_ptr<SqliteStore> SqliteStore::Open(const std::string& directory) {
  CreateDirectory(directory);
  const std::string path = (std::filesystem::path(directory) / kFileName).string();
  try {
    SqliteConnection connection = OpenConfigured(path);
    EnsureStoreSchema(connection);
    EnableIncrementalVacuum(connection);
    auto impl = std::make_unique<Impl>(
        std::move(connection), (std::filesystem::path(directory) / kFramesFileName).string());
    ReleaseUnreferencedFramesLocked(*impl);  // the store is not shared yet
    return std::unique_ptr<SqliteStore>(new SqliteStore(std::move(impl)));
  } catch (const SqliteError& error) {
    switch (error.code() & 0xff) {
      case SQLITE_NOTADB:
      case SQLITE_CORRUPT:
        throw InputError(path + " is not an mbstream database (" + error.what() +
                         "); move the file away or start the server with another --data "
                         "directory");
      case SQLITE_CANTOPEN:
      case SQLITE_READONLY:
      case SQLITE_PERM:
      case SQLITE_AUTH:
        throw InputError("cannot open " + path + " for writing (" + error.what() +
                         "); fix the permissions of the data directory or choose another --data");
      default:
        throw;
    }
  }
}

SqliteStore::SqliteStore(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

SqliteStore::~SqliteStore() = default;

const std::string& SqliteStore::path() const { return impl_->db.path(); }

void SqliteStore::ReleaseMemory() {
  std::lock_guard lock(impl_->mutex);
  sqlite3_db_release_memory(impl_->db.get());
}

}  // namespace mbstream
