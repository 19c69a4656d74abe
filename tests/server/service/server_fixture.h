// An in-process mbstream server on port 0 with a fresh data directory, and client helpers.
#pragma once

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/app/server_host.h"

namespace mbstream::testing {

// A fresh directory below the system's temp dir, removed by the destructor.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

class ServerTest : public ::testing::Test {
 protected:
  // Starts (or restarts) a server with the built-in models of models/ and `limits`, on
  // this test's data directory; with `token_file`, calls need tokens.
  void StartServer(const ServerLimits& limits = ServerLimits(), const std::string& token_file = "");
  void TearDown() override;

  v1::Simulation::Stub& stub() { return *stub_; }
  ServerHost& host() { return *host_; }

  // Client calls; each EXPECTs an OK status unless the call's status is returned.
  v1::ModelInfo SubmitOk(const v1::ModelBundle& bundle);
  grpc::Status Submit(const v1::ModelBundle& bundle, v1::ModelInfo* info);
  grpc::Status StartRun(const std::string& model, const v1::RunSpec& spec, v1::RunInfo* info);
  v1::RunInfo StartRunOk(const std::string& model, const v1::RunSpec& spec);
  // CancelRun, expected to succeed; returns the run's info.
  v1::RunInfo CancelRunOk(const std::string& run_id);
  // Watches the run (WatchRun, no frames) until it ended (60 s at most); returns the last info.
  v1::RunInfo WaitForEnd(const std::string& run_id);
  // Waits until the server counts `count` open Subscribe/WatchRun streams (60 s at most).
  void WaitForSubscribers(int count);
  // GetResult: info, frames and probes; `wait`: GetResultRequest.wait, with the call's
  // `deadline` (none when zero).
  grpc::Status Result(const std::string& run_id, v1::RunInfo* info, std::vector<v1::Frame>* frames,
                      std::vector<v1::ProbeReport>* probes, bool wait = false,
                      std::chrono::milliseconds deadline = std::chrono::milliseconds(0));

  // A spec from a JSON file of models/irb1600/ (e.g. "seed-run.json").
  static v1::RunSpec SceneSpec(const std::string& file);
  static v1::ModelBundle IrbBundle();

  TempDir data_;
  std::unique_ptr<ServerHost> host_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

}  // namespace mbstream::testing
