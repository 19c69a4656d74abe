// Every pure virtual method of Store, listed once: the stores (SqliteStore, PostgresStore) and
// the measuring decorator (server/app/measured_store.h) declare their overrides from this list
// instead of repeating 30 signatures each. Store (store.h) stays the documented declaration;
// an entry missing here leaves an implementation abstract, and one that differs from Store's is
// not an override: either fails to compile.
//
// MBSTREAM_STORE_METHODS(X) calls X(Return, Name, Parameters, Qualifiers) per method, in
// store.h's order. (A return type with a comma needs an alias: Store::ModelSizes,
// Store::StateCounts.)
#pragma once

#define MBSTREAM_STORE_METHODS(X)                                                                \
  X(const std::string&, path, (), const)                                                         \
  X(void, ReleaseMemory, (), )                                                                   \
  X(bool, PutModel, (const v1::ModelInfo& info, const v1::ModelBundle& bundle), )                \
  X(std::vector<v1::ModelInfo>, ListModels, (), const)                                           \
  X(std::optional<v1::ModelBundle>, GetModelBundle,                                              \
    (const std::string& model_id, bool asset_data = true), const)                                \
  X(ModelSizes, ModelBytes, (), const)                                                           \
  X(void, PutRun, (const v1::RunInfo& info), )                                                   \
  X(bool, AddRuns, (const std::vector<v1::RunInfo>& infos), )                                    \
  X(std::optional<v1::RunInfo>, GetRun, (const std::string& run_id), const)                      \
  X(std::vector<v1::RunInfo>, ListRuns, (), const)                                               \
  X(bool, PutFrameChunk,                                                                         \
    (const std::string& run_id, int64_t index, const EncodedFrameChunk& chunk,                   \
     const std::string& holder), )                                                               \
  X(bool, FinishRun,                                                                             \
    (const v1::RunInfo& info, int64_t index, const EncodedFrameChunk& last_chunk,                \
     const std::string& holder), )                                                               \
  X(void, FinishRun, (const v1::RunInfo& info, const std::vector<v1::Frame>& frames), )          \
  X(std::optional<int64_t>, GetFrameChunkData,                                                   \
    (const std::string& run_id, int64_t index, std::string& data), const)                        \
  X(void, AddProbes, (const std::vector<v1::ProbeReport>& reports), )                            \
  X(std::vector<v1::ProbeReport>, GetProbes, (const std::string& run_id), const)                 \
  X(std::optional<int64_t>, FrameChunkHolding, (const std::string& run_id, int64_t seq), const)  \
  X(void, CreateProbeSet, (const v1::ProbeSet& set), )                                           \
  X(void, AddProbeSetReports,                                                                    \
    (const std::string& set_id, const std::vector<v1::ProbeReport>& reports), )                  \
  X(std::vector<v1::ProbeSet>, ListProbeSets, (const std::string& run_id), const)                \
  X(std::optional<v1::ProbeSet>, GetProbeSet, (const std::string& set_id), const)                \
  X(std::vector<v1::ProbeReport>, GetProbeSetReports, (const std::string& set_id), const)        \
  X(bool, DeleteRun, (const std::string& run_id), )                                              \
  X(int64_t, DeleteModel, (const std::string& model_id), )                                       \
  X(bool, SetRunKeep, (const std::string& run_id, bool keep), )                                  \
  X(bool, AddSweep, (const StoredSweep& sweep), )                                                \
  X(std::optional<StoredSweep>, GetSweep, (const std::string& sweep_id, bool definition), const) \
  X(std::vector<StoredSweep>, ListOpenSweeps, (), const)                                         \
  X(SweepFeed, AddSweepRuns,                                                                     \
    (const std::string& sweep_id, const std::vector<v1::RunInfo>& infos), )                      \
  X(std::vector<v1::RunInfo>, ListSweepRuns,                                                     \
    (const std::string& sweep_id, int first_point = 0, int max_runs = 0,                         \
     bool unfinished_only = false),                                                              \
    const)                                                                                       \
  X(StateCounts, CountSweepRuns, (const std::string& sweep_id), const)                           \
  X(int, MarkSweepCancelled, (const std::string& sweep_id), )                                    \
  X(bool, SweepCancelled, (const std::string& sweep_id), const)                                  \
  X(std::vector<v1::RunInfo>, ListUnfinishedSweepRuns, (), const)                                \
  X(StoreUsage, Usage, (const std::vector<std::string>& weigh_runs), const)                      \
  X(StoreBackup, Backup, (const std::string& dir), )                                             \
  X(int, MarkUnfinishedRunsInterrupted, (const std::string& message), )                          \
  X(std::optional<v1::RunInfo>, ClaimQueuedRun, (const RunLease& lease), )                       \
  X(bool, RenewLease,                                                                            \
    (const std::string& run_id, const std::string& holder, int64_t expires_unix_ms), )           \
  X(std::vector<v1::RunInfo>, ReapExpiredLeases,                                                 \
    (int64_t now_unix_ms, const std::string& reaper), )                                          \
  X(std::vector<v1::RunInfo>, ListRunningRuns, (), const)                                        \
  X(bool, PutRunIfHeld, (const v1::RunInfo& info, const std::string& holder), )                  \
  X(std::optional<v1::RunInfo>, EndQueuedRun,                                                    \
    (const std::string& run_id, v1::RunState state, const std::string& message,                  \
     int64_t now_unix_ms), )

// One override declaration, for MBSTREAM_STORE_METHODS.
#define MBSTREAM_STORE_OVERRIDE(Return, Name, Parameters, Qualifiers) \
  Return Name Parameters Qualifiers override;

// Inside a class derived from Store: the declarations of every pure virtual method's override.
#define MBSTREAM_STORE_OVERRIDES MBSTREAM_STORE_METHODS(MBSTREAM_STORE_OVERRIDE)
