// The statements on a sweep's runs (schema version 7: runs.sweep_id, indexed, and
// runs.sweep_cancelled), one text for both stores: SQLite numbers a `$NAME` parameter by its
// first appearance, PostgreSQL by its number, so each text names its parameters in order
// (store_sweeps.cc, postgres_store_sweeps.cc). PutRun and AddRuns write runs.sweep_id, NULL
// for a run started alone: the index (runs_by_sweep, partial) holds sweep runs only.
#pragma once

namespace mbstream {

// A sweep's runs, by index, oldest first; the marks of the row's own (keep, sweep_cancelled).
inline constexpr const char* kSelectSweepRunsSql =
    "SELECT info, keep, sweep_cancelled FROM runs WHERE sweep_id = $1 "
    "ORDER BY created_unix_ms, ord";

// Whether a run of a sweep carries the mark, from the index alone (it holds the mark: the rows,
// their infos past it, are not read). StartSweep asks it before each slice.
inline constexpr const char* kSweepCancelledSql =
    "SELECT 1 FROM runs WHERE sweep_id = $1 AND sweep_cancelled LIMIT 1";

// Marks every stored run of a sweep cancelled, in one statement: a run deleted meanwhile is not
// written again (a read-then-write would re-insert its row). The mark is the row's own column:
// a run's writers (PutRun, FinishRun) never undo it. Rows marked already are left alone.
inline constexpr const char* kMarkSweepCancelledSql =
    "UPDATE runs SET sweep_cancelled = true WHERE sweep_id = $1 AND NOT sweep_cancelled";

// Migration to version 7: each row's sweep id and mark, from its stored RunInfo.
inline constexpr const char* kSelectRunInfosSql = "SELECT id, info FROM runs";
inline constexpr const char* kBackfillSweepSql =
    "UPDATE runs SET sweep_id = $1, sweep_cancelled = $2 WHERE id = $3";

}  // namespace mbstream
