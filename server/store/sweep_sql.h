// The statements on sweeps, one text for both stores: SQLite numbers a `$NAME` parameter by its
// first appearance, PostgreSQL by its number, so each text names its parameters in order
// (store_sweeps.cc, postgres_store_sweeps.cc).
//
// Schema version 7: runs.sweep_id (NULL for a run started alone), indexed by runs_by_sweep
// (partial: sweep runs only), and runs.sweep_cancelled. Version 8: the sweeps table (a sweep
// the server feeds, stored_sweep.h), runs.sweep_point (0 for a run started alone) and the
// indexes of a sweep's runs by point and by state. PutRun and AddRuns write all three columns.
#pragma once

namespace mbstream {

// A sweep's runs, by point: those of points $2 on, at most $3.
inline constexpr const char* kSelectSweepRunsSql =
    "SELECT info, keep, sweep_cancelled FROM runs WHERE sweep_id = $1 AND sweep_point >= $2 "
    "ORDER BY sweep_point, ord LIMIT $3";
// Its runs in states $2 and $3 (QUEUED, RUNNING), by point.
inline constexpr const char* kSelectUnfinishedSweepRunsSql =
    "SELECT info, keep, sweep_cancelled FROM runs WHERE sweep_id = $1 AND state IN ($2, $3) "
    "ORDER BY sweep_point, ord";
// Its runs by state, from the index runs_by_sweep_state.
inline constexpr const char* kCountSweepRunsSql =
    "SELECT state, count(*) FROM runs WHERE sweep_id = $1 GROUP BY state";

// Whether a run of a sweep carries the mark, from the index alone (it holds the mark: the rows,
// their infos past it, are not read), or the sweep's row does.
inline constexpr const char* kSweepCancelledSql =
    "SELECT 1 FROM runs WHERE sweep_id = $1 AND sweep_cancelled "
    "UNION ALL SELECT 1 FROM sweeps WHERE id = $1 AND cancelled LIMIT 1";

// Marks every stored run of a sweep cancelled, in one statement: a run deleted meanwhile is not
// written again (a read-then-write would re-insert its row). The mark is the row's own column:
// a run's writers (PutRun, FinishRun) never undo it. Rows marked already are left alone.
inline constexpr const char* kMarkSweepCancelledSql =
    "UPDATE runs SET sweep_cancelled = true WHERE sweep_id = $1 AND NOT sweep_cancelled";
inline constexpr const char* kMarkSweepRowCancelledSql =
    "UPDATE sweeps SET cancelled = true WHERE id = $1";

// The sweeps table (version 8).
inline constexpr const char* kInsertSweepSql =
    "INSERT INTO sweeps (id, model_id, owner, created_unix_ms, total_points, next_point, "
    "queue_window, definition) VALUES ($1, $2, $3, $4, $5, 0, $6, $7) ON CONFLICT (id) DO NOTHING";
// A sweep's row with the count of its runs in states $2 and $3 (QUEUED, RUNNING).
inline constexpr const char* kSelectSweepSql =
    "SELECT id, model_id, owner, created_unix_ms, total_points, next_point, queue_window, "
    "cancelled, (SELECT count(*) FROM runs WHERE runs.sweep_id = $1 AND runs.state IN ($2, $3)) "
    "FROM sweeps WHERE id = $1";
inline constexpr const char* kSelectSweepDefinitionSql =
    "SELECT definition FROM sweeps WHERE id = $1";
// The sweeps with points left to queue, oldest first, the same columns.
inline constexpr const char* kSelectOpenSweepsSql =
    "SELECT id, model_id, owner, created_unix_ms, total_points, next_point, queue_window, "
    "cancelled, (SELECT count(*) FROM runs WHERE runs.sweep_id = sweeps.id AND "
    "runs.state IN ($1, $2)) FROM sweeps WHERE NOT cancelled AND next_point < total_points "
    "ORDER BY ord";
// AddSweepRuns: the row (PostgreSQL locks it: FOR UPDATE is added there), its unfinished runs,
// its next point moved.
inline constexpr const char* kSelectSweepFeedSql =
    "SELECT next_point, cancelled, queue_window FROM sweeps WHERE id = $1";
inline constexpr const char* kCountUnfinishedSweepRunsSql =
    "SELECT count(*) FROM runs WHERE sweep_id = $1 AND state IN ($2, $3)";
inline constexpr const char* kMoveSweepNextPointSql =
    "UPDATE sweeps SET next_point = $1 WHERE id = $2";
// The runs in states $1 and $2 (QUEUED, RUNNING) of the stored sweeps not cancelled.
inline constexpr const char* kSelectUnfinishedFedSweepRunsSql =
    "SELECT r.info, r.keep, r.sweep_cancelled FROM runs r JOIN sweeps s ON s.id = r.sweep_id "
    "WHERE r.state IN ($1, $2) AND NOT s.cancelled AND NOT r.sweep_cancelled ORDER BY r.ord";
// MarkUnfinishedRunsInterrupted's runs: in states $1 and $2, but those of the above.
#define MBSTREAM_UNFINISHED_RUNS_SQL                                                     \
  "SELECT info FROM runs WHERE state IN ($1, $2) AND NOT (sweep_id IS NOT NULL AND NOT " \
  "sweep_cancelled AND sweep_id IN (SELECT id FROM sweeps WHERE NOT cancelled)) ORDER BY ord"
inline constexpr const char* kSelectUnfinishedRunsSql = MBSTREAM_UNFINISHED_RUNS_SQL;
inline constexpr const char* kSelectUnfinishedRunsForUpdateSql =
    MBSTREAM_UNFINISHED_RUNS_SQL " FOR UPDATE OF runs";
#undef MBSTREAM_UNFINISHED_RUNS_SQL

// Migration to version 7: each row's sweep id and mark, from its stored RunInfo; to version 8,
// its point.
inline constexpr const char* kSelectRunInfosSql = "SELECT id, info FROM runs";
inline constexpr const char* kBackfillSweepSql =
    "UPDATE runs SET sweep_id = $1, sweep_cancelled = $2 WHERE id = $3";
inline constexpr const char* kSelectSweepRunInfosSql =
    "SELECT id, info FROM runs WHERE sweep_id IS NOT NULL";
inline constexpr const char* kBackfillSweepPointSql =
    "UPDATE runs SET sweep_point = $1 WHERE id = $2";

}  // namespace mbstream
