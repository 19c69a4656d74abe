// The SQLite implementation of Store: one file, <data directory>/mbstream.sqlite3, WAL
// journal, one mutex around one connection. Runtime SQLite failures throw SqliteError (an
// InternalError) naming the operation and SQLite's message.
#pragma once

#include <memory>
#include <string>

#include "server/store/store.h"

namespace mbstream {

class SqliteStore final : public Store {
 public:
  // Opens or creates <directory>/mbstream.sqlite3 (creating the directory). WAL journal,
  // foreign keys on, busy timeout. Throws InputError naming the path and what to do when the
  // directory cannot be created or the file is not an mbstream database (or has a newer
  // schema version, PRAGMA user_version).
  static std::unique_ptr<SqliteStore> Open(const std::string& directory);
  ~SqliteStore() override;

  const std::string& path() const override;
  void ReleaseMemory() override;
  bool PutModel(const v1::ModelInfo& info, const v1::ModelBundle& bundle) override;
  std::vector<v1::ModelInfo> ListModels() const override;
  std::optional<v1::ModelBundle> GetModelBundle(const std::string& model_id,
                                                bool asset_data = true) const override;
  std::map<std::string, int64_t> ModelBytes() const override;
  void PutRun(const v1::RunInfo& info) override;
  bool AddRuns(const std::vector<v1::RunInfo>& infos) override;
  std::optional<v1::RunInfo> GetRun(const std::string& run_id) const override;
  std::vector<v1::RunInfo> ListRuns() const override;
  bool PutFrameChunk(const std::string& run_id, int64_t index, const EncodedFrameChunk& chunk,
                     const std::string& holder) override;
  bool FinishRun(const v1::RunInfo& info, int64_t index, const EncodedFrameChunk& last_chunk,
                 const std::string& holder) override;
  void FinishRun(const v1::RunInfo& info, const std::vector<v1::Frame>& frames) override;
  std::optional<int64_t> GetFrameChunkData(const std::string& run_id, int64_t index,
                                           std::string& data) const override;
  void AddProbes(const std::vector<v1::ProbeReport>& reports) override;
  std::vector<v1::ProbeReport> GetProbes(const std::string& run_id) const override;
  std::optional<int64_t> FrameChunkHolding(const std::string& run_id, int64_t seq) const override;
  void CreateProbeSet(const v1::ProbeSet& set) override;
  void AddProbeSetReports(const std::string& set_id,
                          const std::vector<v1::ProbeReport>& reports) override;
  std::vector<v1::ProbeSet> ListProbeSets(const std::string& run_id) const override;
  std::optional<v1::ProbeSet> GetProbeSet(const std::string& set_id) const override;
  std::vector<v1::ProbeReport> GetProbeSetReports(const std::string& set_id) const override;
  int MarkUnfinishedRunsInterrupted(const std::string& message) override;
  std::optional<v1::RunInfo> ClaimQueuedRun(const RunLease& lease) override;
  bool RenewLease(const std::string& run_id, const std::string& holder,
                  int64_t expires_unix_ms) override;
  std::vector<v1::RunInfo> ReapExpiredLeases(int64_t now_unix_ms,
                                             const std::string& reaper) override;
  std::vector<v1::RunInfo> ListRunningRuns() const override;
  bool PutRunIfHeld(const v1::RunInfo& info, const std::string& holder) override;
  std::optional<v1::RunInfo> EndQueuedRun(const std::string& run_id, v1::RunState state,
                                          const std::string& message, int64_t now_unix_ms) override;

  // Private state, opaque here (defined in store_impl.h for the store's own .cc files).
  struct Impl;

 private:
  explicit SqliteStore(std::unique_ptr<Impl> impl);

  std::unique_ptr<Impl> impl_;
};

}  // namespace mbstream
