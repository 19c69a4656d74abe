// The store's SQLite schema and its version check.
#pragma once

#include <cstdint>

namespace mbstream {

class SqliteConnection;

// PRAGMA application_id of an mbstream database: "mbst" in ASCII. A SQLite file with another
// id (and any tables) belongs to some other program.
inline constexpr int32_t kStoreApplicationId = 0x6d627374;

// PRAGMA user_version written by this build. Raise it with every schema change and migrate
// older versions in EnsureStoreSchema.
// 2: the replays' probe sets (probe_sets, probe_set_reports).
// 3: the run queue's leases (runs.lease_holder, runs.lease_expires_unix_ms).
// 4: runs_by_state dropped.
// 5: frames in the frames file (frame_chunks.file_offset, file_bytes, file_crc32c).
// 6: the keep mark (runs.keep).
// 7: a run's sweep (runs.sweep_id, indexed by runs_by_sweep; runs.sweep_cancelled).
// 8: the sweeps the server feeds (sweeps; runs.sweep_point, runs_by_sweep_point,
//    runs_by_sweep_state).
inline constexpr int32_t kStoreSchemaVersion = 8;

// Creates the schema in a new (empty) database, or checks that an existing one is an mbstream
// database this build can use. Throws InputError naming the file and what to do when it is
// another program's database or has a newer schema version; SqliteError (SQLITE_NOTADB...)
// when the file is not SQLite at all.
void EnsureStoreSchema(SqliteConnection& connection);

}  // namespace mbstream
