// Several replicas on one PostgreSQL store (issue 16, many replicas; docs/cluster.md): runs
// started on one replica are integrated by both; a replica killed mid-run has its run marked
// INTERRUPTED by the other while the other runs finish; a drained replica (SIGTERM) lets its
// run finish, or hands it back to the queue for another replica; the gRPC health service
// says NOT_SERVING while draining or without the store. Waits are for events (a state seen
// through GetRun, a health status on a Watch stream); deadlines are failure guards only.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <random>
#include <set>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "tests/common/health_client.h"
#include "tests/common/postgres_cluster.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using Serving = grpc::health::v1::HealthCheckResponse;

// A failure guard for the polls below, far beyond what the events take.
constexpr auto kGuard = std::chrono::seconds(60);

class Replica {
 public:
  Replica(const std::string& data, const std::vector<std::string>& args)
      : process_(MBSTREAM_SERVER, data, args),
        stub_(v1::Simulation::NewStub(
            grpc::CreateChannel(process_.address(), grpc::InsecureChannelCredentials()))) {}

  v1::RunInfo Start(const v1::RunSpec& spec) {
    grpc::ClientContext context;
    v1::StartRunRequest request;
    request.set_model("single_pendulum");
    *request.mutable_spec() = spec;
    v1::RunInfo info;
    const grpc::Status status = stub_->StartRun(&context, request, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info;
  }
  v1::RunInfo Get(const std::string& run_id) {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(run_id);
    v1::RunInfo info;
    const grpc::Status status = stub_->GetRun(&context, request, &info);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return info;
  }
  // Polls GetRun until `done` holds (an event of the cluster); the guard only fails the test.
  v1::RunInfo WaitFor(const std::string& run_id,
                      const std::function<bool(const v1::RunInfo&)>& done) {
    const auto guard = std::chrono::steady_clock::now() + kGuard;
    for (;;) {
      v1::RunInfo info = Get(run_id);
      if (done(info) || std::chrono::steady_clock::now() > guard) return info;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  v1::RunInfo WaitForEnd(const std::string& run_id) {
    return WaitFor(run_id, [](const v1::RunInfo& info) { return info.ended_unix_ms() > 0; });
  }
  ServerProcess& process() { return process_; }
  const std::string& address() const { return process_.address(); }

 private:
  ServerProcess process_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
};

v1::RunSpec Paced(double duration_s, int retries = 0) {
  v1::RunSpec spec;
  spec.set_duration_s(duration_s);
  spec.set_output_interval_s(0.01);
  spec.set_realtime(1.0);  // duration_s of wall time: long enough to be seen running
  spec.set_retries(retries);
  return spec;
}

class ClusterE2eTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = PostgresCluster::Unavailable(); !why.empty()) {
      GTEST_SKIP() << "PostgreSQL test skipped: " << why;
    }
    dir_ = fs::temp_directory_path() /
           ("mbstream-cluster-e2e-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
    cluster_ = std::make_unique<PostgresCluster>();
    uri_ = cluster_->CreateDatabase("mbstream");
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  // The lease timeout: 2 s, or MBSTREAM_CLUSTER_LEASE_S (to measure the default's timeline,
  // docs/cluster.md).
  static std::string LeaseTimeout() {
    const char* lease = std::getenv("MBSTREAM_CLUSTER_LEASE_S");
    return lease != nullptr ? lease : "2";
  }
  std::unique_ptr<Replica> NewReplica(const std::string& name,
                                      std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--store",           uri_,          "--workers", "1",
                                     "--lease-timeout-s", LeaseTimeout()};
    args.insert(args.end(), extra.begin(), extra.end());
    return std::make_unique<Replica>((dir_ / name).string(), args);
  }
  fs::path dir_;
  std::unique_ptr<PostgresCluster> cluster_;
  std::string uri_;
};

TEST_F(ClusterE2eTest, RunsStartedOnOneReplicaAreIntegratedByBoth) {
  auto a = NewReplica("a");
  auto b = NewReplica("b");
  std::vector<std::string> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(a->Start(Paced(1.0)).id());
  std::set<std::string> replicas;
  for (const std::string& id : ids) {
    const v1::RunInfo ended = a->WaitForEnd(id);
    EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
    EXPECT_EQ(ended.frames(), 101);
    EXPECT_EQ(ended.attempts(), 1);
    replicas.insert(ended.replica());
    EXPECT_EQ(b->Get(id).state(), v1::FINISHED);  // every replica answers for every run
  }
  EXPECT_EQ(replicas.size(), 2u) << "one worker each, four runs of 1 s: both must have worked";
}

TEST_F(ClusterE2eTest, KilledReplicasRunIsInterruptedByTheOtherWhileOtherRunsFinish) {
  auto a = NewReplica("a");
  auto b = NewReplica("b");
  const v1::RunInfo slow = a->Start(Paced(30.0));
  const v1::RunInfo running =
      a->WaitFor(slow.id(), [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; });
  ASSERT_EQ(running.state(), v1::RUNNING);
  const bool on_a = running.replica_address() == a->address();
  Replica& victim = on_a ? *a : *b;
  Replica& survivor = on_a ? *b : *a;
  // Frames are stored a chunk at a time; the victim dies with its run unfinished.
  std::vector<std::string> others;
  for (int i = 0; i < 2; ++i) others.push_back(survivor.Start(Paced(0.5)).id());
  victim.process().Kill();
  const auto killed = std::chrono::steady_clock::now();

  const v1::RunInfo reaped =
      survivor.WaitFor(slow.id(), [](const v1::RunInfo& i) { return i.state() != v1::RUNNING; });
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - killed).count();
  EXPECT_EQ(reaped.state(), v1::INTERRUPTED) << reaped.message();
  EXPECT_THAT(reaped.message(), HasSubstr("replica " + running.replica()));
  EXPECT_THAT(reaped.message(), HasSubstr("stopped renewing its lease"));
  std::cout << "replica death to INTERRUPTED: " << seconds << " s (--lease-timeout-s "
            << LeaseTimeout() << ")\n";
  for (const std::string& id : others) {
    const v1::RunInfo ended = survivor.WaitForEnd(id);
    EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
    EXPECT_NE(ended.replica(), running.replica());
  }
}

TEST_F(ClusterE2eTest, DrainedReplicaHandsItsRunBackToAnotherWhenItHasRetries) {
  auto a = NewReplica("a", {"--grace-s", "0"});
  const v1::RunInfo started = a->Start(Paced(1.5, /*retries=*/1));
  ASSERT_EQ(a->WaitFor(started.id(), [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; })
                .state(),
            v1::RUNNING);
  HealthWatch health(a->address());
  ASSERT_TRUE(health.WaitFor(Serving::SERVING));
  auto b = NewReplica("b");
  std::thread drain([&] { EXPECT_EQ(a->process().Drain(), 0); });  // exit 0
  EXPECT_TRUE(health.WaitFor(Serving::NOT_SERVING));
  drain.join();
  const v1::RunInfo ended = b->WaitForEnd(started.id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.attempts(), 2);
  EXPECT_EQ(ended.replica_address(), b->address());
}

TEST_F(ClusterE2eTest, DrainLetsTheRunningRunFinishWithinTheGracePeriod) {
  auto a = NewReplica("a", {"--grace-s", "60"});
  const v1::RunInfo started = a->Start(Paced(1.0));
  ASSERT_EQ(a->WaitFor(started.id(), [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; })
                .state(),
            v1::RUNNING);
  EXPECT_EQ(a->process().Drain(), 0);
  auto b = NewReplica("b");
  const v1::RunInfo ended = b->Get(started.id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.frames(), 101);
  EXPECT_EQ(ended.attempts(), 1);
}

TEST_F(ClusterE2eTest, HealthIsNotServingWithoutTheStore) {
  auto a = NewReplica("a");
  EXPECT_EQ(CheckHealth(a->address()), Serving::SERVING);
  HealthWatch health(a->address());
  ASSERT_TRUE(health.WaitFor(Serving::SERVING));
  cluster_.reset();  // PostgreSQL stops
  EXPECT_TRUE(health.WaitFor(Serving::NOT_SERVING));
  EXPECT_EQ(CheckHealth(a->address()), Serving::NOT_SERVING);
}

}  // namespace
}  // namespace mbstream::testing
