// A full disk is an operating condition (issue 35): a real mbstream-server with --data on a
// 3 MiB tmpfs, mounted in a mount namespace of this test's own (root, as in CI; skipped
// otherwise). Filled, the server refuses new runs with RESOURCE_EXHAUSTED and a message that
// says what to do, keeps the finished run readable, and runs again once space is freed. A run
// that fills the disk mid-run, so that not even its final state can be stored, is still shown
// ended FAILED, naming the full disk, to its watchers (WatchRun, GetRun, GetResult with wait)
// as it happens, and its row is corrected once space returns, without a restart (issue 42,
// item 5: a restart then finds it FAILED, not INTERRUPTED).
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <sys/mount.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;
using testing::ServerProcess;

grpc::Status StartRun(v1::Simulation::Stub& stub, v1::RunInfo* info, double duration_s = 1.0) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  v1::StartRunRequest request;
  request.set_model("single_pendulum");
  request.mutable_spec()->set_duration_s(duration_s);
  request.mutable_spec()->set_output_interval_s(0.01);
  return stub.StartRun(&context, request, info);
}

// Fills the disk of `data` with the file `filler` until at most `left` bytes are free.
void Fill(const fs::path& data, const fs::path& filler, std::uintmax_t left) {
  std::ofstream out(filler, std::ios::binary | std::ios::app);
  const std::string block(16 << 10, 'x');
  while (fs::space(data).available > left && out.write(block.data(), block.size()).flush()) {
  }
  ASSERT_TRUE(out) << "could not fill " << data;
}

// Reads the run's whole stored result, waiting for its end (GetResult with wait), and
// returns its info then.
// The last progress event of a WatchRun stream on the run (its final state), once it ends.
v1::RunInfo Watch(v1::Simulation::Stub& stub, const std::string& run_id) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
  v1::WatchRunRequest request;
  request.set_run_id(run_id);
  auto reader = stub.WatchRun(&context, request);
  v1::WatchEvent event;
  v1::RunInfo last;
  while (reader->Read(&event)) {
    if (event.has_progress()) last = event.progress();
  }
  const grpc::Status status = reader->Finish();
  EXPECT_TRUE(status.ok()) << status.error_message();
  return last;
}

v1::RunInfo GetRun(v1::Simulation::Stub& stub, const std::string& run_id) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  v1::GetRunRequest request;
  request.set_run_id(run_id);
  v1::RunInfo info;
  const grpc::Status status = stub.GetRun(&context, request, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

v1::RunInfo AwaitEnd(v1::Simulation::Stub& stub, const std::string& run_id) {
  {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::GetResultRequest request;
    request.set_run_id(run_id);
    request.set_wait(true);
    auto reader = stub.GetResult(&context, request);
    v1::ResultChunk chunk;
    int chunks = 0;
    while (reader->Read(&chunk)) ++chunks;
    const grpc::Status status = reader->Finish();
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_GT(chunks, 0);
  }
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  v1::GetRunRequest request;
  request.set_run_id(run_id);
  v1::RunInfo info;
  const grpc::Status status = stub.GetRun(&context, request, &info);
  EXPECT_TRUE(status.ok()) << status.error_message();
  return info;
}

TEST(DiskFullE2eTest, AFullDataDiskRefusesRunsUntilSpaceIsFreed) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a 3 MiB tmpfs (CI runs as root)";
  // This thread's own mount namespace; the server forked from it inherits it.
  if (::unshare(CLONE_NEWNS) != 0) {
    GTEST_SKIP() << "cannot make a mount namespace (" << std::strerror(errno) << ")";
  }
  ASSERT_EQ(::mount("none", "/", nullptr, MS_REC | MS_PRIVATE, nullptr), 0) << std::strerror(errno);
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream-disk-full-" + std::to_string(std::random_device()()));
  const fs::path data = dir / "data";
  fs::create_directories(data);
  ASSERT_EQ(::mount("tmpfs", data.c_str(), "tmpfs", 0, "size=3m"), 0) << std::strerror(errno);
  std::string big_id;
  {
    ServerProcess server(
        MBSTREAM_SERVER, data.string(),
        {"--models", std::string(MBSTREAM_SOURCE_DIR) + "/models", "--min-free-mb", "1"});
    auto stub = v1::Simulation::NewStub(
        grpc::CreateChannel(server.address(), grpc::InsecureChannelCredentials()));
    v1::RunInfo first;
    ASSERT_TRUE(StartRun(*stub, &first).ok());
    ASSERT_EQ(AwaitEnd(*stub, first.id()).state(), v1::FINISHED);

    // Above --min-free-mb, a run of far more frames than the disk holds starts, meets the
    // full disk and ends FAILED with a message naming it; the first run stays readable.
    Fill(data, data / "filler", (3u << 20) / 2);
    ASSERT_GT(fs::space(data).available, 1u << 20);
    v1::RunInfo big;
    const grpc::Status big_status = StartRun(*stub, &big, 2000.0);  // 200,001 frames
    ASSERT_TRUE(big_status.ok()) << big_status.error_message();
    big_id = big.id();
    v1::RunInfo watched;  // a watcher from the start: it gets the end as it happens
    std::thread watcher([&] { watched = Watch(*stub, big.id()); });
    const std::optional<std::string> ended =
        testing::WaitForLineIn(server.log_path(), "run " + big.id() + " FAILED", 60.0);
    watcher.join();
    ASSERT_TRUE(ended.has_value()) << testing::ReadTextFile(server.log_path());
    EXPECT_NE(ended->find("disk holding the data directory is full"), std::string::npos) << *ended;
    EXPECT_EQ(ended->find("internal error"), std::string::npos) << *ended;
    // Not even its final state could be stored (the disk is full): shown ended all the same.
    ASSERT_TRUE(testing::WaitForLineIn(
        server.log_path(), "run " + big.id() + ": storing its final state failed too", 10.0))
        << testing::ReadTextFile(server.log_path());
    EXPECT_EQ(watched.state(), v1::FAILED);
    EXPECT_NE(watched.message().find("disk holding the data directory is full"), std::string::npos)
        << watched.message();
    EXPECT_EQ(GetRun(*stub, big.id()).state(), v1::FAILED);
    {  // `mbstream runs` too shows it ended, not the QUEUED row the store still has
      grpc::ClientContext context;
      v1::ListRunsRequest request;
      v1::ListRunsResponse listed;
      ASSERT_TRUE(stub->ListRuns(&context, request, &listed).ok());
      const auto it = std::find_if(listed.runs().begin(), listed.runs().end(),
                                   [&](const v1::RunInfo& run) { return run.id() == big.id(); });
      ASSERT_NE(it, listed.runs().end());
      EXPECT_EQ(it->state(), v1::FAILED) << it->message();
    }
    EXPECT_EQ(AwaitEnd(*stub, big.id()).state(), v1::FAILED);  // result --wait, .result()
    EXPECT_EQ(AwaitEnd(*stub, first.id()).state(), v1::FINISHED);

    // Below it: refused.
    Fill(data, data / "filler", 512u << 10);
    v1::RunInfo refused;
    const grpc::Status status = StartRun(*stub, &refused);
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << status.error_message();
    for (const char* part : {data.c_str(), "--min-free-mb", "free space", "bigger one"}) {
      EXPECT_NE(status.error_message().find(part), std::string::npos)
          << part << " not in: " << status.error_message();
    }
    EXPECT_EQ(AwaitEnd(*stub, first.id()).state(), v1::FINISHED);  // still readable

    fs::remove(data / "filler");  // space freed: runs work again
    v1::RunInfo again;
    const grpc::Status again_status = StartRun(*stub, &again);
    ASSERT_TRUE(again_status.ok()) << again_status.error_message();
    EXPECT_EQ(AwaitEnd(*stub, again.id()).state(), v1::FINISHED);
    // The failed run's row is written again once the store takes it, without a restart.
    ASSERT_TRUE(testing::WaitForLineIn(
        server.log_path(), "run " + big.id() + ": its final state FAILED is stored now", 30.0))
        << testing::ReadTextFile(server.log_path());
  }
  {  // what the store holds: FAILED, not the QUEUED row a restart would mark INTERRUPTED
    ServerProcess server(MBSTREAM_SERVER, data.string(),
                         {"--models", std::string(MBSTREAM_SOURCE_DIR) + "/models"});
    auto stub = v1::Simulation::NewStub(
        grpc::CreateChannel(server.address(), grpc::InsecureChannelCredentials()));
    const v1::RunInfo stored = GetRun(*stub, big_id);
    EXPECT_EQ(stored.state(), v1::FAILED) << stored.message();
    EXPECT_NE(stored.message().find("disk holding the data directory is full"), std::string::npos)
        << stored.message();
  }
  ::umount(data.c_str());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream
