// A test beside a real mbstream-server, driven through the mbstream CLI as a user drives it:
// a temporary directory per test (the server's data in dir_/data, results in Out(name)), the
// server started by the test (StartServer, port 0 on loopback) and `mbstream --server ADDR
// ARGS` run by Cli. The including test target defines MBSTREAM_SERVER and MBSTREAM_CLI (the
// two programs' paths) and links mbstream_test_process.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "tests/common/server_process.h"

namespace mbstream::testing {

inline std::string ReadFile(const std::filesystem::path& path) {
  return ReadTextFile(path.string());
}

// A command's first line (the CLI prints a run's or a model's id there).
inline std::string FirstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

class CliServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = std::filesystem::temp_directory_path() / ("mbstream-cli-" + std::to_string(random()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    server_.reset();
    std::filesystem::remove_all(dir_);
  }
  void StartServer(const std::vector<std::string>& args = {}) {
    server_ = std::make_unique<ServerProcess>(MBSTREAM_SERVER, (dir_ / "data").string(), args);
  }
  // `mbstream --server ADDRESS args` (its output with stderr).
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  std::string Out(const std::string& name) const { return (dir_ / name).string(); }

  std::filesystem::path dir_;
  std::unique_ptr<ServerProcess> server_;
};

}  // namespace mbstream::testing
