// Several replicas on one PostgreSQL store (issue 16, many replicas; docs/cluster.md): runs
// started on one replica are integrated by both; a replica killed mid-run has its run marked
// INTERRUPTED by the other while the other runs finish; a drained replica (SIGTERM) lets its
// run finish, or hands it back to the queue for another replica; the gRPC health service
// says NOT_SERVING while draining or without the store. Calls about a run integrating on
// the other replica are proxied to it: WatchRun and Subscribe give the owner's frames bit for
// bit, a probe answered through the proxy is stored, a follower sees the other replica's
// runs (one attached during such a run sees it too), CancelRun reaches the owner, models are
// shared, and a killed owner ends the proxied streams with UNAVAILABLE. Waits are for events (a
// state seen through GetRun, a health status on a Watch stream, stream messages); deadlines are
// failure guards only.
#include <gmock/gmock.h>
#include <grpcpp/grpcpp.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
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
  v1::Simulation::Stub& stub() { return *stub_; }
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

// What a Subscribe stream brought: frames by seq (each as sent), its end.
struct Received {
  std::map<int64_t, std::string> frames;  // seq -> the serialized Frame
  int64_t missed = 0;
  int64_t probes_sent = 0;
  bool started = false;
  v1::SubscribeEvent::RunStarted run_started;  // as received
  v1::RunInfo ended;                           // id empty until run_ended
  std::string closing;
  grpc::Status status;
};

void AddFrames(const v1::FrameBatch& batch, Received* got) {
  got->missed += batch.missed();
  for (const v1::Frame& frame : batch.frames())
    got->frames[frame.seq()] = frame.SerializeAsString();
}

// Subscribes on `address` (run `run_id`, or follow when `follow`) and reads until run
// `run_id` ended (then half-closes) or the stream ends. With `answer`, each frame of that run
// is answered with one probe report. `on_subscribed` runs once the server said `subscribed`,
// `on_frame` after each batch of the run. `run_id` is read as events come (`on_subscribed` may
// set it: a follower subscribes before the run exists).
Received SubscribeTo(const std::string& address, const std::string& run_id, bool follow,
                     bool answer, const std::function<void()>& on_subscribed = {},
                     const std::function<void(const Received&)>& on_frame = {}) {
  auto stub =
      v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  auto stream = stub->Subscribe(&context);
  v1::SubscribeRequest start;
  if (follow) {
    start.mutable_start()->set_follow(true);
  } else {
    start.mutable_start()->set_run_id(run_id);
  }
  start.mutable_start()->set_max_batch(16);
  EXPECT_TRUE(stream->Write(start));
  Received got;
  v1::SubscribeEvent event;
  while (stream->Read(&event)) {
    if (event.has_subscribed() && on_subscribed) on_subscribed();
    if (event.has_closing()) {
      got.closing = event.closing();
      break;
    }
    if (event.has_run_started() && event.run_started().run().id() == run_id) {
      got.started = true;
      got.run_started = event.run_started();
    }
    if (event.has_frames() && event.frames().run_id() == run_id) {
      AddFrames(event.frames(), &got);
      for (const v1::Frame& frame : event.frames().frames()) {
        if (!answer) break;
        v1::SubscribeRequest reply;
        v1::ProbeReport* probe = reply.mutable_probe();
        probe->set_run_id(run_id);
        probe->set_seq(frame.seq());
        probe->set_probe("tcp");
        probe->set_frame("World");
        probe->mutable_position_m()->set_x(frame.t_s());
        if (stream->Write(reply)) ++got.probes_sent;
      }
      if (on_frame) on_frame(got);
    }
    if (event.has_run_ended() && event.run_ended().id() == run_id) {
      got.ended = event.run_ended();
      break;
    }
  }
  stream->WritesDone();
  while (stream->Read(&event)) {
  }
  got.status = stream->Finish();
  return got;
}

// WatchRun with frames on `address` until its end.
Received WatchFrames(const std::string& address, const std::string& run_id) {
  auto stub =
      v1::Simulation::NewStub(grpc::CreateChannel(address, grpc::InsecureChannelCredentials()));
  grpc::ClientContext context;
  v1::WatchRunRequest request;
  request.set_run_id(run_id);
  request.set_frames(true);
  auto reader = stub->WatchRun(&context, request);
  Received got;
  v1::WatchEvent event;
  while (reader->Read(&event)) {
    if (event.has_frames()) AddFrames(event.frames(), &got);
    if (event.has_progress()) got.ended = event.progress();
  }
  got.status = reader->Finish();
  return got;
}

// Every frame `proxied` got is the one `direct` got with the same seq, byte for byte; the
// proxied frames run without a gap to the run's last frame. The two streams attach in either
// order: frames published before the direct one attached are not compared.
void ExpectSameFrames(const Received& direct, const Received& proxied, int64_t last_seq) {
  ASSERT_FALSE(proxied.frames.empty());
  ASSERT_FALSE(direct.frames.empty());
  EXPECT_EQ(proxied.missed, 0);
  EXPECT_EQ(proxied.frames.rbegin()->first, last_seq);
  EXPECT_EQ(static_cast<int64_t>(proxied.frames.size()),
            last_seq - proxied.frames.begin()->first + 1);
  const int64_t direct_from = direct.frames.begin()->first;
  for (const auto& [seq, bytes] : proxied.frames) {
    if (seq < direct_from) continue;
    auto same = direct.frames.find(seq);
    ASSERT_NE(same, direct.frames.end()) << "frame " << seq << " not seen directly";
    EXPECT_EQ(same->second, bytes) << "frame " << seq << " differs through the proxy";
  }
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
  // Two replicas where `busy_` (started first) integrates a long run on its only worker, so
  // that every run started afterwards is claimed by `free_`: the proxies' tests need to know
  // which replica owns a run.
  void StartBusyAndFree() {
    busy_ = NewReplica("busy");
    long_run_ = busy_->Start(Paced(120.0)).id();
    ASSERT_EQ(
        busy_->WaitFor(long_run_, [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; })
            .state(),
        v1::RUNNING);
    free_ = NewReplica("free");
  }
  // A run started on `free_` and claimed there (waited for).
  v1::RunInfo RunOnFree(double duration_s) {
    const v1::RunInfo started = free_->Start(Paced(duration_s));
    const v1::RunInfo running =
        free_->WaitFor(started.id(), [](const v1::RunInfo& i) { return i.state() != v1::QUEUED; });
    EXPECT_EQ(running.replica_address(), free_->address());
    return running;
  }
  fs::path dir_;
  std::unique_ptr<PostgresCluster> cluster_;
  std::unique_ptr<Replica> busy_, free_;
  std::string long_run_;
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
  // Long enough that it cannot end before the drain, however slow the machine: the test waits
  // for the second attempt to run on b, then cancels it.
  const v1::RunInfo started = a->Start(Paced(120.0, /*retries=*/1));
  ASSERT_EQ(a->WaitFor(started.id(), [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; })
                .state(),
            v1::RUNNING);
  HealthWatch health(a->address());
  ASSERT_TRUE(health.WaitFor(Serving::SERVING));
  auto b = NewReplica("b");
  std::thread drain([&] { EXPECT_EQ(a->process().Drain(), 0); });  // exit 0
  EXPECT_TRUE(health.WaitFor(Serving::NOT_SERVING));
  drain.join();
  const v1::RunInfo again = b->WaitFor(started.id(), [](const v1::RunInfo& i) {
    return (i.state() == v1::RUNNING && i.attempts() == 2) || i.ended_unix_ms() > 0;
  });
  EXPECT_EQ(again.state(), v1::RUNNING) << again.message();
  EXPECT_EQ(again.attempts(), 2);
  EXPECT_EQ(again.replica_address(), b->address());
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(started.id());
  v1::RunInfo answer;
  ASSERT_TRUE(b->stub().CancelRun(&context, request, &answer).ok());
  EXPECT_EQ(b->WaitForEnd(started.id()).state(), v1::CANCELLED);
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

TEST_F(ClusterE2eTest, WatchRunAndSubscribeThroughTheOtherReplicaGetTheOwnersFramesBitForBit) {
  StartBusyAndFree();
  const v1::RunInfo run = free_->Start(Paced(1.5));
  Received direct, proxied, watched_direct, watched_proxied;
  std::thread a([&] { direct = SubscribeTo(free_->address(), run.id(), false, false); });
  std::thread b([&] { proxied = SubscribeTo(busy_->address(), run.id(), false, false); });
  std::thread c([&] { watched_direct = WatchFrames(free_->address(), run.id()); });
  std::thread d([&] { watched_proxied = WatchFrames(busy_->address(), run.id()); });
  for (std::thread* t : {&a, &b, &c, &d}) t->join();
  for (const Received* got : {&direct, &proxied, &watched_direct, &watched_proxied}) {
    EXPECT_TRUE(got->status.ok()) << got->status.error_message();
    EXPECT_EQ(got->ended.state(), v1::FINISHED) << got->ended.message();
    EXPECT_EQ(got->ended.replica_address(), free_->address());
  }
  EXPECT_TRUE(proxied.started);
  const int64_t last = direct.ended.frames() - 1;
  ExpectSameFrames(direct, proxied, last);
  ExpectSameFrames(watched_direct, watched_proxied, last);
  std::cout << "frames through the proxy: Subscribe " << proxied.frames.size() << ", WatchRun "
            << watched_proxied.frames.size() << " of " << last + 1 << "\n";
}

TEST_F(ClusterE2eTest, ProbeReportsAnsweredThroughTheOtherReplicaAreStoredByTheOwner) {
  StartBusyAndFree();
  const v1::RunInfo run = RunOnFree(1.0);
  const Received got = SubscribeTo(busy_->address(), run.id(), false, true);
  ASSERT_TRUE(got.status.ok()) << got.status.error_message();
  ASSERT_GT(got.probes_sent, 0);
  const v1::RunInfo ended = busy_->WaitForEnd(run.id());
  EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.probe_reports(), got.probes_sent);
  EXPECT_EQ(ended.probe_reports(), static_cast<int64_t>(got.frames.size()));
}

TEST_F(ClusterE2eTest, FollowOnOneReplicaSeesARunClaimedByTheOther) {
  StartBusyAndFree();
  v1::RunInfo run;
  std::string run_id;  // the run started once the follow stream is subscribed
  const Received got = SubscribeTo(busy_->address(), run_id, /*follow=*/true, /*answer=*/true, [&] {
    run = free_->Start(Paced(1.0));  // claimed by free_: busy_ is busy
    run_id = run.id();
  });
  EXPECT_TRUE(got.status.ok()) << got.status.error_message();
  EXPECT_TRUE(got.started);
  EXPECT_EQ(got.run_started.model().id(), run.model_id());
  EXPECT_FALSE(got.run_started.bundle().urdf().empty());
  EXPECT_EQ(got.ended.state(), v1::FINISHED) << got.ended.message();
  EXPECT_EQ(got.ended.replica_address(), free_->address());
  ASSERT_FALSE(got.frames.empty());
  EXPECT_EQ(got.frames.rbegin()->first, got.ended.frames() - 1);
  EXPECT_EQ(got.missed, 0);
  EXPECT_EQ(free_->WaitForEnd(run.id()).probe_reports(), got.probes_sent);
}

TEST_F(ClusterE2eTest, FollowAttachedDuringARunOfTheOtherReplicaSeesThatRun) {
  StartBusyAndFree();  // long_run_ runs on busy_ before anyone follows; free_ runs nothing
  bool cancelled = false;
  const Received got =
      SubscribeTo(free_->address(), long_run_, /*follow=*/true, /*answer=*/false, {},
                  [&](const Received&) {  // a frame of it came through free_: end it on its owner
                    if (cancelled) return;
                    cancelled = true;
                    grpc::ClientContext context;
                    v1::CancelRunRequest request;
                    request.set_run_id(long_run_);
                    v1::RunInfo answer;
                    EXPECT_TRUE(busy_->stub().CancelRun(&context, request, &answer).ok());
                  });
  EXPECT_TRUE(got.started);
  EXPECT_FALSE(got.frames.empty());
  EXPECT_EQ(got.missed, 0);
  EXPECT_EQ(got.ended.id(), long_run_);
  EXPECT_EQ(got.ended.state(), v1::CANCELLED) << got.ended.message();
  EXPECT_EQ(got.ended.replica_address(), busy_->address());
}

// A controlled run (issue 45) integrates on the server its Control stream reaches, so a
// replica of a cluster (any replica may claim a run) refuses one with FAILED_PRECONDITION and
// says where control runs; the replica goes on serving ordinary runs.
TEST_F(ClusterE2eTest, AControlStreamToAReplicaIsRefusedNamingWhereControlRuns) {
  auto replica = NewReplica("a");
  grpc::ClientContext context;
  auto stream = replica->stub().Control(&context);
  v1::ControlRequest start;
  start.mutable_start()->set_model("single_pendulum");
  v1::RunSpec* spec = start.mutable_start()->mutable_spec();
  spec->set_duration_s(0.05);
  spec->set_output_interval_s(0.01);
  spec->add_drives()->mutable_external()->set_period_s(0.01);
  ASSERT_TRUE(stream->Write(start));
  stream->WritesDone();
  v1::ControlResponse response;
  EXPECT_FALSE(stream->Read(&response));
  const grpc::Status refused = stream->Finish();
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::FAILED_PRECONDITION) << refused.error_message();
  EXPECT_THAT(refused.error_message(), HasSubstr("cluster"));
  EXPECT_THAT(refused.error_message(), HasSubstr("--data"));
  const v1::RunInfo run = replica->Start(Paced(0.05));
  EXPECT_EQ(replica->WaitForEnd(run.id()).state(), v1::FINISHED);
}

TEST_F(ClusterE2eTest, CancelThroughTheOtherReplicaCancelsTheRunOnItsOwner) {
  StartBusyAndFree();
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(long_run_);
  v1::RunInfo answer;
  const grpc::Status status = free_->stub().CancelRun(&context, request, &answer);
  ASSERT_TRUE(status.ok()) << status.error_message();
  const v1::RunInfo ended = free_->WaitForEnd(long_run_);
  EXPECT_EQ(ended.state(), v1::CANCELLED) << ended.message();
  EXPECT_EQ(ended.replica_address(), busy_->address());
}

// A sweep started on one replica is followed and cancelled through the other: its runs are
// found by their sweep id in the shared store, the one integrating on the first replica is
// cancelled there (forwarded), and the sweep's later slices are refused by either replica.
TEST_F(ClusterE2eTest, ASweepIsFollowedAndCancelledThroughEitherReplica) {
  auto a = NewReplica("a");
  auto b = NewReplica("b");
  v1::StartSweepRequest start;
  start.set_model("single_pendulum");
  *start.mutable_base() = Paced(30.0);
  v1::SweepAxis& axis = *start.add_grid();
  axis.set_path("duration_s");
  for (const char* value : {"30", "31", "32", "33", "34", "35"}) axis.add_values(value);
  start.set_max_runs(4);
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    const grpc::Status status = a->stub().StartSweep(&context, start, &started);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  const auto sweep_on = [&](Replica& replica) {
    grpc::ClientContext context;
    v1::GetSweepRequest request;
    request.set_sweep_id(started.sweep_id());
    v1::SweepProgress progress;
    const grpc::Status status = replica.stub().GetSweep(&context, request, &progress);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return progress;
  };
  const auto running = [](const v1::SweepProgress& progress) {
    for (const v1::SweepStateCount& entry : progress.states()) {
      if (entry.state() == v1::RUNNING) return entry.runs();
    }
    return 0;
  };
  // One worker each: two runs integrate, one per replica, two wait in the queue.
  for (const std::string& id : {started.runs(0).id(), started.runs(1).id()}) {
    a->WaitFor(id, [](const v1::RunInfo& i) { return i.state() == v1::RUNNING; });
  }
  v1::SweepProgress progress = sweep_on(*b);
  EXPECT_EQ(progress.total_points(), 6);
  EXPECT_EQ(progress.started_runs(), 4);
  EXPECT_EQ(progress.ended_runs(), 0);
  EXPECT_EQ(running(progress), 2);
  EXPECT_EQ(progress.run_ids(3), started.runs(3).id());

  {
    grpc::ClientContext context;
    v1::CancelSweepRequest request;
    request.set_sweep_id(started.sweep_id());
    const grpc::Status status = b->stub().CancelSweep(&context, request, &progress);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  EXPECT_TRUE(progress.cancelled());
  EXPECT_EQ(progress.ended_runs(), 4);
  std::set<std::string> owners;
  for (const v1::RunInfo& run : started.runs()) {
    const v1::RunInfo ended = a->WaitForEnd(run.id());
    EXPECT_EQ(ended.state(), v1::CANCELLED) << ended.message();
    if (!ended.replica_address().empty()) owners.insert(ended.replica_address());
  }
  EXPECT_EQ(owners, (std::set<std::string>{a->address(), b->address()}));
  EXPECT_TRUE(sweep_on(*a).cancelled());

  start.set_sweep_id(started.sweep_id());
  start.set_first_point(4);
  start.set_max_runs(0);
  grpc::ClientContext context;
  const grpc::Status later = a->stub().StartSweep(&context, start, &started);
  EXPECT_EQ(later.error_code(), grpc::StatusCode::FAILED_PRECONDITION) << later.error_message();
}

// A sweep the server feeds, across two replicas on one store (issue 42): both integrate its
// points, each point is queued exactly once (the feeders of both replicas claim the next
// points in one transaction each), at most its window at once; replica a, where it was
// started, killed mid-sweep: b goes on feeding it (a's run is queued again: retries 1) and
// the sweep completes.
TEST_F(ClusterE2eTest, ASweepIsFedByBothReplicasAndOutlivesTheOneThatStartedIt) {
  auto a = NewReplica("a");
  auto b = NewReplica("b");
  v1::StartSweepRequest start;
  start.set_model("single_pendulum");
  *start.mutable_base() = Paced(0.3, 1);
  v1::SweepAxis& axis = *start.add_grid();
  axis.set_path("duration_s");
  for (int k = 0; k < 12; ++k) axis.add_values(std::to_string(0.3 + 0.02 * k));
  start.set_window(3);
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    const grpc::Status status = a->stub().StartSweep(&context, start, &started);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  const auto sweep_on = [&](Replica& replica) {
    grpc::ClientContext context;
    v1::GetSweepRequest request;
    request.set_sweep_id(started.sweep_id());
    v1::SweepProgress progress;
    const grpc::Status status = replica.stub().GetSweep(&context, request, &progress);
    EXPECT_TRUE(status.ok()) << status.error_message();
    return progress;
  };
  const auto await_sweep = [&](Replica& replica,
                               const std::function<bool(const v1::SweepProgress&)>& done) {
    const auto guard = std::chrono::steady_clock::now() + kGuard;
    for (;;) {
      v1::SweepProgress progress = sweep_on(replica);
      EXPECT_LE(progress.started_runs() - progress.ended_runs(), 3) << "more than its window";
      if (done(progress) || std::chrono::steady_clock::now() > guard) return progress;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  };
  // Mid-sweep, through b: some points ended.
  const v1::SweepProgress before =
      await_sweep(*b, [](const v1::SweepProgress& p) { return p.ended_runs() >= 4; });
  ASSERT_GE(before.ended_runs(), 4);
  ASSERT_LT(before.started_runs(), 12);
  a->process().Kill();

  const v1::SweepProgress done = await_sweep(
      *b, [](const v1::SweepProgress& p) { return p.ended_runs() == p.total_points(); });
  EXPECT_EQ(done.total_points(), 12);
  EXPECT_EQ(done.started_runs(), 12);
  ASSERT_EQ(done.run_ids_size(), 12);  // each point once
  EXPECT_EQ(std::set<std::string>(done.run_ids().begin(), done.run_ids().end()).size(), 12u);
  std::set<std::string> owners;
  for (int k = 0; k < done.run_ids_size(); ++k) {
    const v1::RunInfo run = b->Get(done.run_ids(k));
    EXPECT_EQ(run.state(), v1::FINISHED) << run.id() << ": " << run.message();
    EXPECT_EQ(run.sweep_point(), k);
    owners.insert(run.replica_address());
  }
  EXPECT_TRUE(owners.count(a->address()) && owners.count(b->address()))
      << "both replicas integrate the sweep's points";
}

TEST_F(ClusterE2eTest, ModelsSubmittedToOneReplicaAreListedAndReadByTheOther) {
  auto a = NewReplica("a");
  auto b = NewReplica("b");
  v1::SubmitModelRequest submit;
  submit.mutable_bundle()->set_name("pendulum_of_a");
  submit.mutable_bundle()->set_urdf(
      "<robot name='pendulum_of_a'><link name='base'/>"
      "<joint name='j' type='continuous'><parent link='base'/><child link='bob'/>"
      "<axis xyz='0 1 0'/></joint>"
      "<link name='bob'><inertial><origin xyz='0 0 -0.5'/><mass value='2'/>"
      "<inertia ixx='1e-3' ixy='0' ixz='0' iyy='1e-3' iyz='0' izz='1e-3'/></inertial></link>"
      "</robot>");
  v1::ModelInfo submitted;
  {
    grpc::ClientContext context;
    const grpc::Status status = a->stub().SubmitModel(&context, submit, &submitted);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  grpc::ClientContext list_context;
  v1::ListModelsResponse listed;
  ASSERT_TRUE(b->stub().ListModels(&list_context, v1::ListModelsRequest(), &listed).ok());
  bool found = false;
  for (const v1::ModelInfo& model : listed.models()) found = found || model.id() == submitted.id();
  EXPECT_TRUE(found) << "ListModels on the other replica lacks " << submitted.id();
  grpc::ClientContext get_context;
  v1::GetModelRequest get;
  get.set_model("pendulum_of_a");
  v1::GetModelResponse model;
  const grpc::Status got = b->stub().GetModel(&get_context, get, &model);
  ASSERT_TRUE(got.ok()) << got.error_message();
  EXPECT_EQ(model.info().id(), submitted.id());
}

TEST_F(ClusterE2eTest, KilledOwnerEndsTheProxiedStreamsWithUnavailable) {
  StartBusyAndFree();
  const v1::RunInfo run = RunOnFree(60.0);
  Received watched;
  std::thread watcher([&] { watched = WatchFrames(busy_->address(), run.id()); });
  bool killed = false;
  const Received got =
      SubscribeTo(busy_->address(), run.id(), false, false, {}, [&](const Received&) {
        if (!killed) free_->process().Kill();
        killed = true;
      });
  watcher.join();
  ASSERT_TRUE(killed) << got.status.error_message();
  EXPECT_EQ(got.status.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_THAT(got.status.error_message(), HasSubstr(free_->address()));
  EXPECT_THAT(got.closing, HasSubstr(free_->address()));
  EXPECT_EQ(watched.status.error_code(), grpc::StatusCode::UNAVAILABLE);
  EXPECT_THAT(watched.status.error_message(), HasSubstr(free_->address()));
  // A new subscription is refused at once while the dead owner's lease runs, naming it.
  const Received again = SubscribeTo(busy_->address(), run.id(), false, false);
  if (again.ended.id().empty()) {  // not reaped yet
    EXPECT_EQ(again.status.error_code(), grpc::StatusCode::UNAVAILABLE);
    EXPECT_THAT(again.status.error_message(), HasSubstr(free_->address()));
  }
}

}  // namespace
}  // namespace mbstream::testing
