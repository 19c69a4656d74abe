// Helpers for the store tests: a temporary data directory, a fixture that runs a suite against
// both store backends, and sample messages.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/store/store.h"

// SQL that turns the tables of a new store back into what version 7 created (before the sweeps
// table of version 8), for tests that make an older store from a new one.
#define MBSTREAM_DROP_SWEEPS_TABLE_SQL \
  "DROP INDEX runs_by_sweep_point; "   \
  "DROP INDEX runs_by_sweep_state; "   \
  "DROP TABLE sweeps; "                \
  "ALTER TABLE runs DROP COLUMN sweep_point; "
inline constexpr const char* kDropSweepsTable = MBSTREAM_DROP_SWEEPS_TABLE_SQL;

// SQL that turns the tables of a new store back into what version 6 created (before the sweep
// columns of version 7), for tests that make an older store from a new one.
#define MBSTREAM_DROP_SWEEP_COLUMNS_SQL     \
  MBSTREAM_DROP_SWEEPS_TABLE_SQL            \
  "DROP INDEX runs_by_sweep; "              \
  "ALTER TABLE runs DROP COLUMN sweep_id; " \
  "ALTER TABLE runs DROP COLUMN sweep_cancelled; "
inline constexpr const char* kDropSweepColumns = MBSTREAM_DROP_SWEEP_COLUMNS_SQL;

// SQL that turns the tables of a new store back into what versions 1-4 created (before the
// frames file, frame_file.h, the keep mark of version 6 and the sweep columns of version 7), for
// tests that make an older store from a new one.
inline constexpr const char* kDropFrameFileColumns = MBSTREAM_DROP_SWEEP_COLUMNS_SQL
    "ALTER TABLE frame_chunks DROP COLUMN file_offset; "
    "ALTER TABLE frame_chunks DROP COLUMN file_bytes; "
    "ALTER TABLE frame_chunks DROP COLUMN file_crc32c; "
    "ALTER TABLE runs DROP COLUMN keep; ";

namespace mbstream::testing {

// A fresh, uniquely named directory under the system temp directory, removed (with its
// contents) on destruction. It is not created: Store::Open creates it.
class TempDirectory {
 public:
  TempDirectory();
  TempDirectory(const TempDirectory&) = delete;
  TempDirectory& operator=(const TempDirectory&) = delete;
  ~TempDirectory();

  const std::filesystem::path& path() const { return path_; }
  std::string str() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

enum class Backend { kSqlite, kPostgres };

// A suite of store tests run once per backend (TEST_P; INSTANTIATE_STORE_BACKENDS(Suite)):
// SQLite in a temporary directory, PostgreSQL in a fresh database of this process's test
// cluster (postgres_cluster.h). The PostgreSQL variants are skipped, with the reason, when
// PostgreSQL is not installed.
class StoreBackendTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override;
  // Opens this test's store; again after the first store was destroyed, the same data.
  std::unique_ptr<Store> Open();
  Backend backend() const { return GetParam(); }
  const std::string& uri() const { return uri_; }  // the PostgreSQL database's URI

 private:
  TempDirectory temp_;
  std::string uri_;
};

std::string BackendName(const ::testing::TestParamInfo<Backend>& info);

#define INSTANTIATE_STORE_BACKENDS(Suite)                                              \
  INSTANTIATE_TEST_SUITE_P(Backends, Suite,                                            \
                           ::testing::Values(::mbstream::testing::Backend::kSqlite,    \
                                             ::mbstream::testing::Backend::kPostgres), \
                           ::mbstream::testing::BackendName)

v1::ModelInfo MakeModelInfo(const std::string& id, int64_t created_unix_ms);
v1::ModelBundle MakeBundle(const std::string& name, int num_assets);
v1::RunInfo MakeRun(const std::string& id, v1::RunState state, int64_t created_unix_ms);
// `count` frames of `dofs` joints with seq 0..count-1 (torques and energies filled).
std::vector<v1::Frame> MakeFrames(int64_t count, int dofs);
v1::ProbeReport MakeProbe(const std::string& run_id, int64_t seq, const std::string& probe);
// Run `id` of model `model_id` stored whole: RUNNING, then FINISHED with `frames` frames (2
// joints), two live probe reports (seq 0 and 1) and a replay's probe set "ps-<id>" of one.
void StoreWholeRun(Store& store, const std::string& id, int64_t frames,
                   const std::string& model_id = "m-abc");

inline bool Same(const google::protobuf::Message& a, const google::protobuf::Message& b) {
  return google::protobuf::util::MessageDifferencer::Equals(a, b);
}

}  // namespace mbstream::testing
