// What a store holds and what it takes (Store::Usage, for GetStorage and `mbstream storage`),
// and what a backup copied (Store::Backup). The queries are one list for both stores except the
// bytes of a frame chunk: the SQLite store keeps them in its frames file (file_bytes), the
// PostgreSQL store in the row (length(data)). `$1` is the first parameter in both (delete_sql.h).
#pragma once

#include <cstdint>
#include <map>
#include <string>

namespace mbstream {

// One model's runs (by its id).
struct ModelUsage {
  int64_t runs = 0;
  int64_t frame_bytes = 0;
  int64_t probe_bytes = 0;  // probe reports and probe-set reports
};

struct StoreUsage {
  std::map<std::string, ModelUsage> models;  // by model id: every model with runs
  std::map<int, int64_t> runs_by_state;      // v1::RunState -> runs
  int64_t frame_bytes = 0;
  int64_t probe_bytes = 0;
  int64_t run_bytes = 0;      // the runs' rows (RunInfo)
  int64_t disk_bytes = 0;     // SQLite: blocks of the database, its WAL and the frames file
  int64_t weighed_bytes = 0;  // frames and probes of the runs Usage was asked to weigh
};

// A consistent copy of a SQLite store (SqliteStore::Backup).
struct StoreBackup {
  std::string dir;
  int64_t database_bytes = 0;
  int64_t frames_bytes = 0;
  int64_t runs = 0;
};

// Runs by model and state, with their rows' bytes: model_id, state, count, bytes.
inline constexpr const char* kRunsByModelAndStateSql =
    "SELECT model_id, state, count(*), CAST(coalesce(sum(length(info)), 0) AS bigint) "
    "FROM runs GROUP BY model_id, state";

// The bytes of a frame chunk `f`, each store's own.
inline constexpr const char* kSqliteChunkBytes = "coalesce(f.file_bytes, 0) + length(f.data)";
inline constexpr const char* kPostgresChunkBytes = "length(f.data)";

// Frame bytes by model (model_id, bytes), with the chunk bytes expression put in.
inline std::string FrameBytesByModelSql(const char* chunk_bytes) {
  return std::string("SELECT r.model_id, CAST(coalesce(sum(") + chunk_bytes +
         "), 0) AS bigint) FROM frame_chunks f JOIN runs r ON r.id = f.run_id GROUP BY r.model_id";
}

// Probe and probe-set report bytes by model (model_id, bytes).
inline constexpr const char* kProbeBytesByModelSql[] = {
    "SELECT r.model_id, CAST(coalesce(sum(length(p.report)), 0) AS bigint) FROM probes p "
    "JOIN runs r ON r.id = p.run_id GROUP BY r.model_id",
    "SELECT r.model_id, CAST(coalesce(sum(length(s.report)), 0) AS bigint) FROM "
    "probe_set_reports s JOIN probe_sets ps ON ps.id = s.set_id JOIN runs r ON r.id = ps.run_id "
    "GROUP BY r.model_id",
};

// The frame and probe bytes of run $1, with the chunk bytes expression put in.
inline std::string RunBytesSql(const char* chunk_bytes) {
  return std::string("SELECT CAST(coalesce((SELECT sum(") + chunk_bytes +
         ") FROM frame_chunks f WHERE f.run_id = $1), 0) + "
         "coalesce((SELECT sum(length(report)) FROM probes WHERE run_id = $1), 0) + "
         "coalesce((SELECT sum(length(s.report)) FROM probe_set_reports s JOIN probe_sets ps "
         "ON ps.id = s.set_id WHERE ps.run_id = $1), 0) AS bigint)";
}

}  // namespace mbstream
