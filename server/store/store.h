// The server's persistence: models, runs, their frames and probe reports in one SQLite file,
// <data directory>/mbstream.sqlite3. A server killed mid-run and restarted finds every model
// and finished run again; runs it left unfinished are marked INTERRUPTED at start.
//
// Every method is thread-safe (one mutex around one connection). Runtime SQLite failures
// throw SqliteError (an InternalError) naming the operation and SQLite's message.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/replay.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/store/frame_chunks.h"

namespace mbstream {

class Store {
 public:
  // File name of the database inside the data directory.
  static constexpr const char* kFileName = "mbstream.sqlite3";

  // Opens or creates <directory>/mbstream.sqlite3 (creating the directory). WAL journal,
  // foreign keys on, busy timeout. Throws InputError naming the path and what to do when the
  // directory cannot be created or the file is not an mbstream database (or has a newer
  // schema version, PRAGMA user_version).
  static std::unique_ptr<Store> Open(const std::string& directory);
  ~Store();
  Store(const Store&) = delete;
  Store& operator=(const Store&) = delete;

  // Full path of the database file.
  const std::string& path() const;

  // Frees the memory of SQLite's page cache that is not in use (after a long run or result).
  void ReleaseMemory();

  // Models. PutModel is idempotent by info.id (the first stored copy wins, returns false if it
  // existed). The bundle's assets are stored too. info.created_unix_ms == 0 is stored as now.
  bool PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle);
  std::vector<v1::ModelInfo> ListModels() const;  // oldest first
  // The bundle with its assets; without their data (names only) unless `asset_data`.
  std::optional<v1::ModelBundle> GetModelBundle(const std::string& model_id,
                                                bool asset_data = true) const;
  // Each stored model's size in bytes (its bundle row and its assets' data), by id.
  std::map<std::string, int64_t> ModelBytes() const;

  // Runs. PutRun inserts or replaces the run's row (its RunInfo, state, timestamps); the
  // run's frames and probes stay.
  void PutRun(const v1::RunInfo& info);
  std::optional<v1::RunInfo> GetRun(const std::string& run_id) const;
  std::vector<v1::RunInfo> ListRuns() const;  // oldest first (created_unix_ms, then insertion)

  // A run's frames are written while it runs, one chunk (frame_chunks.h) at a time, then
  // the last chunk together with the final info. A crash mid-run leaves the chunks stored so
  // far with the run's RUNNING row (INTERRUPTED at the next start).
  //
  // Stores chunk number `index` (0, 1, 2, ... in seq order) of a run whose row exists,
  // replacing a chunk of that number. One transaction.
  void PutFrameChunk(const std::string& run_id, int64_t index, const EncodedFrameChunk& chunk);
  // Stores the run's final info and its last chunk (number `index`, skipped when it holds no
  // frames) in ONE transaction, and removes any chunk numbered after it: after a crash either
  // the final state and every frame are there, or the run still shows its previous row.
  void FinishRun(const v1::RunInfo& info, int64_t index, const EncodedFrameChunk& last_chunk);
  // The same for a run whose frames are all at hand (in seq order): they replace every frame
  // stored earlier for the run.
  void FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames);

  // Reads a run's frames one chunk at a time: the frames of the first stored chunk numbered
  // `index` or later are appended to `frames`, and the number to ask for next is returned;
  // nullopt when there is none. Each call holds the store's lock only to copy one chunk.
  std::optional<int64_t> GetFrameChunk(const std::string& run_id, int64_t index,
                                       std::vector<v1::Frame>& frames) const;
  std::vector<v1::Frame> GetFrames(const std::string& run_id) const;  // all, in seq order

  // Probe reports (stored as they arrive, batched by the caller; one transaction per call);
  // duplicates of (run_id, seq, probe) replace the old row.
  void AddProbes(const std::vector<v1::ProbeReport>& reports);
  std::vector<v1::ProbeReport> GetProbes(const std::string& run_id) const;  // by seq, probe

  // Replays (store_replay.cc). The number of the stored chunk that holds frame `seq` of the
  // run (for a seek), nullopt when no chunk does.
  std::optional<int64_t> FrameChunkHolding(const std::string& run_id, int64_t seq) const;
  // A replay's probe set: created once (its id unique), its reports added in batches
  // (duplicates of (set, seq, probe) replace the old row), listed per run oldest first with
  // their report counts, read back by seq and probe.
  void CreateProbeSet(const v1::ProbeSet& set);
  void AddProbeSetReports(const std::string& set_id, const std::vector<v1::ProbeReport>& reports);
  std::vector<v1::ProbeSet> ListProbeSets(const std::string& run_id) const;
  std::optional<v1::ProbeSet> GetProbeSet(const std::string& set_id) const;
  std::vector<v1::ProbeReport> GetProbeSetReports(const std::string& set_id) const;

  // At server start: every run still QUEUED or RUNNING becomes INTERRUPTED with `message`
  // and ended_unix_ms = now; returns how many.
  int MarkUnfinishedRunsInterrupted(const std::string& message);

  // Private state, opaque here (defined in store_impl.h for the store's own .cc files).
  struct Impl;

 private:
  explicit Store(std::unique_ptr<Impl> impl);

  std::unique_ptr<Impl> impl_;
};

}  // namespace mbstream
