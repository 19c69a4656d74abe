// The server's persistence: models, runs, their frames and probe reports. One interface, two
// implementations with one behaviour: SQLite in a data directory (sqlite_store.h, the
// embedded default) and PostgreSQL (postgres_store.h, for several servers on one database);
// open either from a --store location with OpenStore (store_open.h). A server killed mid-run
// and restarted finds every model and finished run again; runs it left unfinished are marked
// INTERRUPTED at start.
//
// Every method is thread-safe. The implementations declare their overrides from one list
// (store_methods.h). Runtime database failures throw an InternalError (SqliteError,
// PostgresError) naming the operation and the database's message.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/replay.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/store/frame_chunks.h"
#include "server/store/run_lease.h"
#include "server/store/store_usage.h"
#include "server/store/stored_sweep.h"

namespace mbstream {

class Store {
 public:
  // File name of the SQLite database inside the data directory.
  static constexpr const char* kFileName = "mbstream.sqlite3";
  static constexpr const char* kFramesFileName = "mbstream.frames";  // frame_file.h

  // Bytes by model id (ModelBytes).
  using ModelSizes = std::map<std::string, int64_t>;
  // Runs by v1::RunState (CountSweepRuns).
  using StateCounts = std::map<int, int>;

  // The SQLite store in `directory` (as --data; see SqliteStore::Open).
  static std::unique_ptr<Store> Open(const std::string& directory);

  Store() = default;
  virtual ~Store() = default;
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Where the data is, for messages: the SQLite file's path, or the PostgreSQL URI (never
  // with a password).
  virtual const std::string& path() const = 0;

  // Frees the memory of the database's cache that is not in use (after a long run or result).
  virtual void ReleaseMemory() = 0;

  // Models. PutModel is idempotent by info.id (the first stored copy wins, returns false if it
  // existed). The bundle's assets are stored too. info.created_unix_ms == 0 is stored as now.
  virtual bool PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) = 0;
  virtual std::vector<v1::ModelInfo> ListModels() const = 0;  // oldest first
  // The bundle with its assets; without their data (names only) unless `asset_data`.
  virtual std::optional<v1::ModelBundle> GetModelBundle(const std::string& model_id,
                                                        bool asset_data = true) const = 0;
  // Each stored model's size in bytes (its bundle row and its assets' data), by id.
  virtual ModelSizes ModelBytes() const = 0;

  // Runs. PutRun inserts or replaces the run's row (its RunInfo, state, timestamps); the
  // run's frames and probes stay.
  virtual void PutRun(const v1::RunInfo& info) = 0;
  // New runs in ONE transaction: every row is inserted, or none is and the result is false
  // when any of their ids is stored already (by this replica or another: run ids are made
  // unique here, not by asking first).
  virtual bool AddRuns(const std::vector<v1::RunInfo>& infos) = 0;
  virtual std::optional<v1::RunInfo> GetRun(const std::string& run_id) const = 0;
  virtual std::vector<v1::RunInfo> ListRuns()
      const = 0;  // oldest first (created_unix_ms, then insertion)

  // A run's frames are written while it runs, one chunk (frame_chunks.h) at a time (when
  // 4,096 frames are at hand or --frame-flush-s has passed: FrameSpool), then the last chunk
  // together with the final info. A crash mid-run leaves the chunks stored so far with the
  // run's unfinished row; MarkUnfinishedRunsInterrupted (or ReapExpiredLeases) keeps them and
  // writes their count and last time into the row (kept_frames.h).
  //
  // Stores chunk number `index` (0, 1, 2, ... in seq order) of a run whose row exists,
  // replacing a chunk of that number and removing any numbered after it (an earlier
  // attempt's: the stored chunks are always one attempt's frames from seq 0 on). With a
  // `holder` (LeaseHolder; empty: unconditionally), only while that holder still holds the
  // run's lease: false, and nothing written, otherwise (a replica that lost its lease never
  // overwrites the frames of the replica that took the run over). One transaction.
  virtual bool PutFrameChunk(const std::string& run_id, int64_t index,
                             const EncodedFrameChunk& chunk, const std::string& holder) = 0;
  // Stores the run's final info and its last chunk (number `index`, skipped when it holds no
  // frames) in ONE transaction, and removes any chunk numbered after it: after a crash either
  // the final state and every frame are there, or the run still shows its previous row.
  // With a `holder` (LeaseHolder; empty: unconditionally), only while that holder still holds the
  // run's lease (as RenewLease checks it, in the same transaction): false, and nothing written,
  // otherwise.
  virtual bool FinishRun(const v1::RunInfo& info, int64_t index,
                         const EncodedFrameChunk& last_chunk, const std::string& holder) = 0;
  // The same for a run whose frames are all at hand (in seq order): they replace every frame
  // stored earlier for the run.
  virtual void FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) = 0;

  // Reads a run's frames one chunk at a time, as stored: `data` gets the blob of the first
  // stored chunk numbered `index` or later (frame_chunks.h, unchecked), and the number to
  // ask for next is returned; nullopt when there is none. Each call holds the store's lock
  // only to copy one chunk.
  virtual std::optional<int64_t> GetFrameChunkData(const std::string& run_id, int64_t index,
                                                   std::string& data) const = 0;
  // The same, parsed: the chunk's frames are appended to `frames`. Throws InternalError when
  // the stored blob is corrupt.
  std::optional<int64_t> GetFrameChunk(const std::string& run_id, int64_t index,
                                       std::vector<v1::Frame>& frames) const;
  // The same, not parsed: `frames` gets each frame's serialized bytes, views into `data`
  // (SplitFrameChunk: their wire structure checked). Throws InternalError when corrupt.
  std::optional<int64_t> GetSerializedFrames(const std::string& run_id, int64_t index,
                                             std::string& data,
                                             std::vector<std::string_view>& frames) const;
  std::vector<v1::Frame> GetFrames(const std::string& run_id) const;  // all, in seq order

  // Probe reports (stored as they arrive, batched by the caller; one transaction per call);
  // duplicates of (run_id, seq, probe) replace the old row.
  virtual void AddProbes(const std::vector<v1::ProbeReport>& reports) = 0;
  virtual std::vector<v1::ProbeReport> GetProbes(
      const std::string& run_id) const = 0;  // by seq, probe

  // Replays (store_replay.cc). The number of the stored chunk that holds frame `seq` of the
  // run (for a seek), nullopt when no chunk does.
  virtual std::optional<int64_t> FrameChunkHolding(const std::string& run_id,
                                                   int64_t seq) const = 0;
  // A replay's probe set: created once (its id unique), its reports added in batches
  // (duplicates of (set, seq, probe) replace the old row), listed per run oldest first with
  // their report counts, read back by seq and probe.
  virtual void CreateProbeSet(const v1::ProbeSet& set) = 0;
  virtual void AddProbeSetReports(const std::string& set_id,
                                  const std::vector<v1::ProbeReport>& reports) = 0;
  virtual std::vector<v1::ProbeSet> ListProbeSets(const std::string& run_id) const = 0;
  virtual std::optional<v1::ProbeSet> GetProbeSet(const std::string& set_id) const = 0;
  virtual std::vector<v1::ProbeReport> GetProbeSetReports(const std::string& set_id) const = 0;

  // Deleting (store_delete.cc, postgres_store_delete.cc; the statements in delete_sql.h).
  // Removes run `run_id` whole, in ONE transaction: its row, frame chunks, probe reports,
  // probe sets and their reports; a reader sees the run whole or not at all. False when no
  // such run is stored. The SQLite store's frames file keeps the chunks' bytes (frame_file.h).
  virtual bool DeleteRun(const std::string& run_id) = 0;
  // Removes model `model_id` (its row and assets) in one transaction when no run of it is
  // stored. Returns how many runs of it are stored: 0 when it was deleted (or was not stored),
  // else nothing was deleted.
  virtual int64_t DeleteModel(const std::string& model_id) = 0;
  // Marks run `run_id` to be kept (retention never deletes it) or not. The mark is the row's
  // own (GetRun and ListRuns show it as RunInfo.keep); PutRun and FinishRun leave it. False
  // when no such run is stored.
  virtual bool SetRunKeep(const std::string& run_id, bool keep) = 0;

  // Sweeps (store_sweeps.cc, postgres_store_sweeps.cc; the statements in sweep_sql.h).
  //
  // A sweep fed by the server (StoredSweep): stored whole by AddSweep (false, nothing
  // written, when its id is taken), read back by GetSweep (its definition only when asked;
  // nullopt for an unknown sweep), and those with points left to queue (not cancelled,
  // next_point < total_points) listed oldest first without their definitions. Each read
  // counts the sweep's runs QUEUED or RUNNING (unfinished_runs).
  virtual bool AddSweep(const StoredSweep& sweep) = 0;
  virtual std::optional<StoredSweep> GetSweep(const std::string& sweep_id,
                                              bool definition) const = 0;
  virtual std::vector<StoredSweep> ListOpenSweeps() const = 0;
  // Queues the next points of sweep `sweep_id`: `infos` are its runs of points
  // infos[0].sweep_point, +1, ... (QUEUED, or FAILED for a point the model refused), stored
  // in ONE transaction that moves the sweep's next_point past them, only while next_point is
  // infos[0].sweep_point, the sweep is not cancelled and its window has room for the QUEUED
  // ones beside its unfinished runs (the sweep's row locked meanwhile, so that replicas
  // feeding one sweep never queue a point twice nor overfill its window).
  virtual SweepFeed AddSweepRuns(const std::string& sweep_id,
                                 const std::vector<v1::RunInfo>& infos) = 0;
  // The runs of sweep `sweep_id` (RunInfo.sweep_id) as GetRun returns them, by point
  // (runs.sweep_point, indexed): those of points `first_point` on, at most `max_runs`
  // (0 = all); with `unfinished_only`, only those QUEUED or RUNNING. Reads only.
  virtual std::vector<v1::RunInfo> ListSweepRuns(const std::string& sweep_id, int first_point = 0,
                                                 int max_runs = 0,
                                                 bool unfinished_only = false) const = 0;
  // How many runs of sweep `sweep_id` are in each state, from the index (no RunInfo read).
  virtual StateCounts CountSweepRuns(const std::string& sweep_id) const = 0;
  // Marks sweep `sweep_id` cancelled: its stored row (no more points are queued) and every
  // stored run of it (RunInfo.sweep_cancelled), in one transaction on the rows that exist: a
  // run deleted meanwhile stays deleted. The mark is the row's own, as `keep`: PutRun and
  // FinishRun leave it. Returns how many runs were marked now (0 when every one carried the
  // mark already, or the sweep is unknown).
  virtual int MarkSweepCancelled(const std::string& sweep_id) = 0;
  // Whether sweep `sweep_id` was cancelled (its row, or a stored run, carries the mark), from
  // the indexes alone (no RunInfo read). Reads only.
  virtual bool SweepCancelled(const std::string& sweep_id) const = 0;
  // The runs QUEUED or RUNNING of the stored sweeps not cancelled, oldest first: what a
  // server of a private store that died left of its sweeps (RunQueue queues them again).
  // MarkUnfinishedRunsInterrupted leaves them. Reads only.
  virtual std::vector<v1::RunInfo> ListUnfinishedSweepRuns() const = 0;

  // Storage (store_usage.cc, postgres_store_usage.cc; store_usage.h). What the store holds:
  // runs by model and state, the bytes of their frames, probe reports and rows, and (SQLite)
  // the blocks its files take on the disk; `weighed_bytes` sums the frame and probe bytes of
  // `weigh_runs` (what deleting them would free). Reads only.
  virtual StoreUsage Usage(const std::vector<std::string>& weigh_runs) const = 0;
  // A consistent copy of the live store into directory `dir` (created; it must hold no store):
  // the database as of one moment, by SQLite's online backup from a read transaction of its
  // own (writers go on meanwhile), and the frames file up to its size at that moment (every
  // chunk that database refers to was appended before its row committed); chunks deleted
  // meanwhile are released only once the copy is done. `--data dir` starts a server from it.
  // Throws InputError when `dir` holds a store or cannot be written, and for a PostgreSQL
  // store (pg_dump: docs/cluster.md).
  virtual StoreBackup Backup(const std::string& dir) = 0;

  // At server start: every run still QUEUED or RUNNING (but those of stored sweeps not
  // cancelled: ListUnfinishedSweepRuns) becomes INTERRUPTED with `message` and
  // ended_unix_ms = now, its stored frames kept and counted in its row (frames, t_s,
  // stats.t_reached_s; the message names them); returns how many.
  virtual int MarkUnfinishedRunsInterrupted(const std::string& message) = 0;

  // The run queue (store_queue.cc, postgres_store_queue.cc; rules in run_lease.h). Any
  // replica on the store claims queued runs; the claim, renewal and expiry of a lease are one
  // transaction each, so two replicas never hold one run.
  //
  // Claims the oldest QUEUED run (created_unix_ms, then insertion) under `lease`: its row
  // becomes RUNNING (ApplyClaim) with the lease recorded. Returns the claimed info, nullopt
  // when nothing is queued. PostgreSQL: SELECT ... FOR UPDATE SKIP LOCKED; SQLite: one
  // BEGIN IMMEDIATE transaction.
  virtual std::optional<v1::RunInfo> ClaimQueuedRun(const RunLease& lease) = 0;
  // Extends the lease held by `holder` (LeaseHolder) on run `run_id` to `expires_unix_ms`.
  // False when the run is no longer RUNNING under that holder's lease (expired and handed to
  // another replica, re-queued, or ended): the holder must stop the run and store nothing.
  virtual bool RenewLease(const std::string& run_id, const std::string& holder,
                          int64_t expires_unix_ms) = 0;
  // A claim made without the store, by the one server of a private store (its queue is that
  // process's own): `info` as claimed (RUNNING). Nothing is written (the row stays QUEUED
  // until the run ends; a crash marks either INTERRUPTED at the next start); a decorator
  // counts it (MeasuredStore).
  virtual void NoteClaimed(const v1::RunInfo& info) { (void)info; }
  // Every RUNNING run whose lease expired before `now_unix_ms` (a run without a lease
  // counts as expired): queued again or INTERRUPTED (ApplyLeaseExpired, `reaper` named in
  // the message), its frames kept (counted in the row of an INTERRUPTED one, as by
  // MarkUnfinishedRunsInterrupted). Returns the changed runs as stored.
  virtual std::vector<v1::RunInfo> ReapExpiredLeases(int64_t now_unix_ms,
                                                     const std::string& reaper) = 0;
  // Every RUNNING run, oldest claim first (ord): what the replicas integrate now (a follow
  // stream announces those of other replicas, cluster_follow.h). Reads only.
  virtual std::vector<v1::RunInfo> ListRunningRuns() const = 0;
  // Writes `info` (an ended or re-queued run) only while `holder` still holds the run's
  // lease, and drops the lease; false (nothing written) otherwise.
  virtual bool PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) = 0;
  // Ends run `run_id` with `state` and `message` (ended now) if it is still QUEUED (CancelRun
  // of a queued run; a server stopping). Returns the stored info, nullopt when the run is not
  // queued (claimed meanwhile, or unknown).
  virtual std::optional<v1::RunInfo> EndQueuedRun(const std::string& run_id, v1::RunState state,
                                                  const std::string& message,
                                                  int64_t now_unix_ms) = 0;
};

}  // namespace mbstream
