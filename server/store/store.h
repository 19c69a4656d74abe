// The server's persistence: models, runs, their frames and probe reports in one SQLite file,
// <data directory>/mbstream.sqlite3. A server killed mid-run and restarted finds every model
// and finished run again; runs it left unfinished are marked INTERRUPTED at start.
//
// Every method is thread-safe (one mutex around one connection). Runtime SQLite failures
// throw SqliteError (an InternalError) naming the operation and SQLite's message.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"

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

  // Models. PutModel is idempotent by info.id (the first stored copy wins, returns false if it
  // existed). The bundle's assets are stored too. info.created_unix_ms == 0 is stored as now.
  bool PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle);
  std::vector<v1::ModelInfo> ListModels() const;  // oldest first
  std::optional<v1::ModelBundle> GetModelBundle(const std::string& model_id) const;

  // Runs. PutRun inserts or replaces the run's row (its RunInfo, state, timestamps); the
  // run's frames and probes stay.
  void PutRun(const v1::RunInfo& info);
  std::optional<v1::RunInfo> GetRun(const std::string& run_id) const;
  std::vector<v1::RunInfo> ListRuns() const;  // oldest first (created_unix_ms, then insertion)

  // Stores the run's final info and all its frames (in seq order) in ONE transaction: after a
  // crash either both are there or neither (the run then still shows its previous row).
  // Frames stored earlier for the run are replaced.
  void FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames);
  std::vector<v1::Frame> GetFrames(const std::string& run_id) const;  // in seq order

  // Probe reports (stored as they arrive, batched by the caller; one transaction per call);
  // duplicates of (run_id, seq, probe) replace the old row.
  void AddProbes(const std::vector<v1::ProbeReport>& reports);
  std::vector<v1::ProbeReport> GetProbes(const std::string& run_id) const;  // by seq, probe

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
