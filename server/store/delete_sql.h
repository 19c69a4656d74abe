// The statements that delete a run or a model (and mark a run kept), one list for both stores:
// SQLite reads `$1` as a named parameter (its first, index 1), PostgreSQL as its first. Each store
// runs a list in order in one transaction (store_delete.cc, postgres_store_delete.cc).
#pragma once

namespace mbstream {

// A run whole. The row goes last: its count of deleted rows says whether the run existed.
inline constexpr const char* kDeleteRunSql[] = {
    "DELETE FROM probe_set_reports WHERE set_id IN (SELECT id FROM probe_sets WHERE run_id = $1)",
    "DELETE FROM probe_sets WHERE run_id = $1",
    "DELETE FROM probes WHERE run_id = $1",
    "DELETE FROM frame_chunks WHERE run_id = $1",
    "DELETE FROM runs WHERE id = $1",
};

// How many runs of a model are stored (DeleteModel deletes nothing while there are some).
inline constexpr const char* kCountModelRunsSql = "SELECT count(*) FROM runs WHERE model_id = $1";

// A model whole: its assets, then its row.
inline constexpr const char* kDeleteModelSql[] = {
    "DELETE FROM model_assets WHERE model_id = $1",
    "DELETE FROM models WHERE id = $1",
};

// Marks a run to be kept or not: each store's own text, SQLite numbering a `$NAME` parameter by
// its first appearance (the 1 or 0 of the mark second, as PostgreSQL's boolean).
inline constexpr const char* kSetRunKeepSqlite = "UPDATE runs SET keep = ?2 WHERE id = ?1";
inline constexpr const char* kSetRunKeepPostgres = "UPDATE runs SET keep = $2 WHERE id = $1";

}  // namespace mbstream
