// A server killed with SIGKILL mid-run keeps every probe report it had answered for good
// (issue 32): a viewer answers each frame of a paced run with a probe report; the run's probe
// recorder stores them in batches (one at least every --frame-flush-s, 1 s by default) and
// logs each stored batch. "Answered" is the server's side of it: a report is answered once
// the log says its batch is stored ("probe batch N stored: ..., T in all, through frame S").
// The test waits for the second such line (an event, no sleep), kills the server, restarts
// it on the same data directory and reads the run's probe reports as a client does
// (GetResult): every report the viewer sent for frames up to S is there, at least T in all,
// and none the viewer did not send.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;

// seed-servo lengthened to 600 s: one frame per 0.05 s of simulated time, at realtime 1 as
// long in wall time, of which the test needs about 2 s (the server is killed): a busy machine
// cannot end the run first.
constexpr const char* kSpec = "--spec models/irb1600/seed-servo.json --duration 600 --realtime 1";

std::unique_ptr<v1::Simulation::Stub> Connect(const std::string& address) {
  return v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
}

// A viewer: subscribes to the run and answers every frame it receives with a probe report,
// until the stream ends (the server is killed). The frames it answered, in order.
class AnsweringViewer {
 public:
  AnsweringViewer(const std::string& address, const std::string& run_id)
      : stub_(Connect(address)), thread_([this, run_id] { Answer(run_id); }) {}
  ~AnsweringViewer() { Join(); }

  void Join() {
    if (thread_.joinable()) thread_.join();
  }
  std::set<int64_t> answered() {
    std::lock_guard<std::mutex> lock(mutex_);
    return answered_;
  }

 private:
  void Answer(const std::string& run_id) {
    grpc::ClientContext context;
    auto stream = stub_->Subscribe(&context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(run_id);
    if (!stream->Write(start)) return;
    v1::SubscribeEvent event;
    v1::SubscribeRequest reply;
    while (stream->Read(&event)) {
      if (!event.has_frames()) continue;
      for (const v1::Frame& frame : event.frames().frames()) {
        v1::ProbeReport* probe = reply.mutable_probe();
        probe->set_run_id(run_id);
        probe->set_seq(frame.seq());
        probe->set_t_s(frame.t_s());
        probe->set_probe("tcp");
        probe->set_frame("World");
        *probe->mutable_position_m() = frame.tcp_m();
        if (!stream->Write(reply)) return;
        std::lock_guard<std::mutex> lock(mutex_);
        answered_.insert(frame.seq());
      }
    }
    (void)stream->Finish();
  }

  std::unique_ptr<v1::Simulation::Stub> stub_;
  std::mutex mutex_;
  std::set<int64_t> answered_;
  std::thread thread_;
};

TEST(CrashProbesE2eTest, AKilledServerKeepsEveryProbeReportOfItsStoredBatches) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream-crash-probes-" + std::to_string(std::random_device()()));
  fs::create_directories(dir);
  const std::string data = (dir / "data").string();
  std::string run_id;
  long long total = 0, through = -1;
  std::set<int64_t> answered;
  {
    ServerProcess server(MBSTREAM_SERVER, data);
    const CommandOutcome started = RunCommand(std::string(MBSTREAM_CLI) + " --server " +
                                              server.address() + " run irb1600 " + kSpec);
    ASSERT_EQ(started.exit_code, 0) << started.output;
    run_id = started.output.substr(0, started.output.find('\n'));
    AnsweringViewer viewer(server.address(), run_id);

    // The second stored batch: the first covers the viewer's first second, the second shows
    // that batches keep coming while the run runs (not only at its end).
    const std::optional<std::string> batch =
        WaitForLineIn(server.log_path(), "run " + run_id + ": probe batch 2 stored: ", 60.0);
    ASSERT_TRUE(batch.has_value()) << "no second probe batch in " << server.log_path();
    long long reports = 0;
    ASSERT_EQ(std::sscanf(batch->c_str(), "%lld reports, %lld in all, through frame %lld", &reports,
                          &total, &through),
              3)
        << *batch;
    server.Kill();
    viewer.Join();  // its stream ends with the server
    answered = viewer.answered();
  }
  ASSERT_GT(total, 0);
  ASSERT_GE(through, 0);

  std::set<int64_t> kept;
  v1::RunInfo after;
  {
    ServerProcess server(MBSTREAM_SERVER, data);
    auto stub = Connect(server.address());
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    v1::GetResultRequest request;
    request.set_run_id(run_id);
    auto reader = stub->GetResult(&context, request);
    v1::ResultChunk chunk;
    while (reader->Read(&chunk)) {
      if (chunk.has_info()) after = chunk.info();
      for (const v1::ProbeReport& probe : chunk.probes()) {
        EXPECT_TRUE(kept.insert(probe.seq()).second) << "frame " << probe.seq() << " twice";
        EXPECT_EQ(probe.probe(), "tcp");
      }
    }
    const grpc::Status status = reader->Finish();
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  std::cout << "the viewer answered " << answered.size() << " frames before the kill; the server "
            << "had stored " << total << " reports through frame " << through << "; " << kept.size()
            << " reports kept after the restart" << std::endl;
  EXPECT_EQ(after.state(), v1::INTERRUPTED);
  EXPECT_GE(static_cast<long long>(kept.size()), total);
  for (int64_t seq : answered) {
    if (seq <= through) {
      EXPECT_TRUE(kept.count(seq)) << "the report for frame " << seq << " is lost";
    }
  }
  for (int64_t seq : kept) {
    EXPECT_TRUE(answered.count(seq)) << "frame " << seq << " never answered";
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::testing
