// Helpers for the store tests: a temporary data directory and sample messages.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <google/protobuf/util/message_differencer.h>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"

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

v1::ModelInfo MakeModelInfo(const std::string& id, int64_t created_unix_ms);
v1::ModelBundle MakeBundle(const std::string& name, int num_assets);
v1::RunInfo MakeRun(const std::string& id, v1::RunState state, int64_t created_unix_ms);
// `count` frames of `dofs` joints with seq 0..count-1 (torques and energies filled).
std::vector<v1::Frame> MakeFrames(int64_t count, int dofs);
v1::ProbeReport MakeProbe(const std::string& run_id, int64_t seq, const std::string& probe);

inline bool Same(const google::protobuf::Message& a, const google::protobuf::Message& b) {
  return google::protobuf::util::MessageDifferencer::Equals(a, b);
}

}  // namespace mbstream::testing
