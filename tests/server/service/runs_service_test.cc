// StartRun, WatchRun, GetResult, CancelRun and the run limits through a real server.
#include <gmock/gmock.h>

#include <thread>

#include "tests/common/seed_kinematics.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class RunsServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // Waits (polling GetRun) until the run is RUNNING with at least `frames` frames.
  void WaitForFrames(const std::string& run_id, int64_t frames) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (std::chrono::steady_clock::now() < deadline) {
      grpc::ClientContext context;
      v1::GetRunRequest request;
      request.set_run_id(run_id);
      v1::RunInfo now;
      ASSERT_TRUE(stub().GetRun(&context, request, &now).ok());
      if (now.state() == v1::RUNNING && now.frames() >= frames) return;
      ASSERT_EQ(now.state() == v1::QUEUED || now.state() == v1::RUNNING, true)
          << v1::RunState_Name(now.state());
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    FAIL() << "run " << run_id << " has no frame after 60 s";
  }
};

TEST_F(RunsServiceTest, SeedRunMatchesDirectKinematics) {
  const v1::RunInfo started = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  EXPECT_EQ(started.state(), v1::QUEUED);
  EXPECT_EQ(started.expected_frames(), 401);
  const v1::RunInfo ended = WaitForEnd(started.id());
  ASSERT_EQ(ended.state(), v1::FINISHED) << ended.message();
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  ASSERT_TRUE(Result(started.id(), &info, &frames, nullptr).ok());
  ASSERT_EQ(frames.size(), 401u);
  EXPECT_EQ(info.num_dofs(), 6);
  double worst = 0.0;
  for (size_t k = 0; k < frames.size(); ++k) {
    const v1::Frame& f = frames[k];
    EXPECT_EQ(f.seq(), static_cast<int64_t>(k));
    EXPECT_NEAR(f.t_s(), 0.05 * k, 1e-12);
    const Eigen::Vector3d expected = SeedTcp(f.q().data());
    const Eigen::Vector3d got(f.tcp_m().x(), f.tcp_m().y(), f.tcp_m().z());
    worst = std::max(worst, (got - expected).norm());
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(info.stats().formulation(), "kinematic");
}

TEST_F(RunsServiceTest, ExpectedFramesIncludeTheLastFrameOfAnUnevenDuration) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_duration_s(1.03);  // frames at 0, 0.05, ..., 1.0 and one at 1.03
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  EXPECT_EQ(started.expected_frames(), 22);
  const v1::RunInfo ended = WaitForEnd(started.id());
  ASSERT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.frames(), 22);
  spec.set_max_output_frames(21);
  v1::RunInfo info;
  EXPECT_EQ(StartRun("irb1600", spec, &info).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(RunsServiceTest, WatchRunStreamsProgressAndFramesToTheFinalState) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);  // 20 s of wall time: cancelled once the watch has seen enough
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  WaitForFrames(started.id(), 1);
  int64_t frames_before = 0;
  {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(started.id());
    v1::RunInfo now;
    ASSERT_TRUE(stub().GetRun(&context, request, &now).ok());
    frames_before = now.frames();
  }
  grpc::ClientContext context;
  v1::WatchRunRequest request;
  request.set_run_id(started.id());
  request.set_frames(true);
  request.set_progress_interval_s(0.1);
  auto reader = stub().WatchRun(&context, request);
  v1::WatchEvent event;
  int progress = 0;
  bool cancelled = false;
  int64_t frames = 0, missed = 0, last_seq = -1, first_seq = -1;
  v1::RunInfo last;
  while (reader->Read(&event)) {
    if (event.has_progress()) {
      ++progress;
      last = event.progress();
    } else {
      for (const v1::Frame& f : event.frames().frames()) {
        if (first_seq < 0) first_seq = f.seq();
        EXPECT_GT(f.seq(), last_seq);
        last_seq = f.seq();
        ++frames;
      }
      missed += event.frames().missed();
    }
    if (progress >= 5 && frames > 0 && !cancelled) {  // progress while it runs, and frames
      grpc::ClientContext cancel_context;
      v1::CancelRunRequest cancel;
      cancel.set_run_id(started.id());
      v1::RunInfo answer;
      ASSERT_TRUE(stub().CancelRun(&cancel_context, cancel, &answer).ok());
      cancelled = true;
    }
  }
  ASSERT_TRUE(reader->Finish().ok());
  EXPECT_TRUE(cancelled);
  EXPECT_EQ(last.state(), v1::CANCELLED);  // the stream ends with the final state
  EXPECT_GE(progress, 5);
  // The watch attaches while the run goes: it starts at the latest frame then, not at 0.
  EXPECT_GE(first_seq, frames_before - 1);
  EXPECT_EQ(frames + missed, last_seq - first_seq + 1);
  EXPECT_LT(last_seq, last.frames());
}

TEST_F(RunsServiceTest, CancelStopsARunningRunAndKeepsItsFrames) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);  // 20 s of wall time unless cancelled
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  WaitForFrames(started.id(), 1);  // running, with a frame to keep
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(started.id());
  v1::RunInfo cancelled;
  ASSERT_TRUE(stub().CancelRun(&context, request, &cancelled).ok());
  const v1::RunInfo ended = WaitForEnd(started.id());
  EXPECT_EQ(ended.state(), v1::CANCELLED);
  EXPECT_THAT(ended.message(), HasSubstr("cancelled at t ="));
  EXPECT_GT(ended.frames(), 0);
  EXPECT_LT(ended.frames(), 401);
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  ASSERT_TRUE(Result(started.id(), &info, &frames, nullptr).ok());
  EXPECT_EQ(static_cast<int64_t>(frames.size()), ended.frames());
}

TEST_F(RunsServiceTest, ResultOfARunningRunIsFailedPrecondition) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  const grpc::Status status = Result(started.id(), &info, &frames, nullptr);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("wait for it to end"));
}

TEST_F(RunsServiceTest, ResultWithWaitArrivesWhenTheRunEnds) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(20.0);  // 1 s of wall time: the call is made long before the end
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  const grpc::Status status = Result(started.id(), &info, &frames, nullptr, /*wait=*/true);
  ASSERT_TRUE(status.ok()) << status.error_message();
  EXPECT_EQ(info.state(), v1::FINISHED);
  ASSERT_EQ(frames.size(), 401u);
  EXPECT_EQ(frames.back().seq(), 400);
  EXPECT_DOUBLE_EQ(frames.back().t_s(), 20.0);
}

TEST_F(RunsServiceTest, ResultWithWaitEndsWithTheCallsDeadline) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);  // 20 s of wall time unless cancelled
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  const grpc::Status status =
      Result(started.id(), &info, &frames, nullptr, /*wait=*/true, std::chrono::milliseconds(300));
  EXPECT_EQ(status.error_code(), grpc::StatusCode::DEADLINE_EXCEEDED) << status.error_message();
  EXPECT_TRUE(frames.empty());
  grpc::ClientContext context;
  v1::CancelRunRequest request;
  request.set_run_id(started.id());
  v1::RunInfo cancelled;
  ASSERT_TRUE(stub().CancelRun(&context, request, &cancelled).ok());
  // The run ends CANCELLED; a waiting GetResult then gets what it stored.
  ASSERT_TRUE(Result(started.id(), &info, &frames, nullptr, /*wait=*/true).ok());
  EXPECT_EQ(info.state(), v1::CANCELLED);
  EXPECT_EQ(static_cast<int64_t>(frames.size()), info.frames());
}

TEST_F(RunsServiceTest, BadRequestsGetTheirStatusCodes) {
  v1::RunInfo info;
  EXPECT_EQ(StartRun("nosuch", v1::RunSpec(), &info).error_code(), grpc::StatusCode::NOT_FOUND);

  v1::RunSpec negative = SceneSpec("seed-run.json");
  negative.set_duration_s(-1.0);
  grpc::Status status = StartRun("irb1600", negative, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("duration_s"));

  v1::RunSpec few_frames = SceneSpec("seed-run.json");
  few_frames.set_max_output_frames(100);
  status = StartRun("irb1600", few_frames, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("max_output_frames"));

  grpc::ClientContext context;
  v1::GetRunRequest request;
  request.set_run_id("r-nosuch");
  EXPECT_EQ(stub().GetRun(&context, request, &info).error_code(), grpc::StatusCode::NOT_FOUND);
}

TEST_F(RunsServiceTest, ServerLimitsAreResourceExhausted) {
  ServerLimits limits;
  limits.max_duration_s = 10.0;
  limits.max_output_frames = 1000;
  limits.workers = 1;
  limits.max_queued_runs = 1;
  StartServer(limits);
  v1::RunInfo info;
  grpc::Status status = StartRun("irb1600", SceneSpec("seed-run.json"), &info);  // 20 s
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("10"));

  v1::RunSpec dense = SceneSpec("seed-run.json");
  dense.set_duration_s(5.0);
  dense.set_output_interval_s(1e-3);  // 5001 frames
  status = StartRun("irb1600", dense, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("output_interval_s"));

  // One worker busy (slow run), one run queued: the next is refused.
  v1::RunSpec slow = SceneSpec("seed-run.json");
  slow.set_duration_s(5.0);
  slow.set_realtime(1.0);
  const v1::RunInfo running = StartRunOk("irb1600", slow);
  WaitForFrames(running.id(), 1);  // the worker has taken it off the queue
  const v1::RunInfo queued = StartRunOk("irb1600", slow);
  status = StartRun("irb1600", slow, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("queue is full"));
  for (const std::string& id : {running.id(), queued.id()}) {
    grpc::ClientContext context;
    v1::CancelRunRequest request;
    request.set_run_id(id);
    ASSERT_TRUE(stub().CancelRun(&context, request, &info).ok());
  }
  EXPECT_EQ(WaitForEnd(queued.id()).state(), v1::CANCELLED);
}

TEST_F(RunsServiceTest, ShutdownInterruptsRunningRunsAndTheyStayListed) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  WaitForFrames(started.id(), 1);
  host_->Shutdown();
  StartServer();  // same data directory
  grpc::ClientContext context;
  v1::GetRunRequest request;
  request.set_run_id(started.id());
  v1::RunInfo info;
  ASSERT_TRUE(stub().GetRun(&context, request, &info).ok());
  EXPECT_EQ(info.state(), v1::INTERRUPTED);
  EXPECT_THAT(info.message(), HasSubstr("shut down"));
}

}  // namespace
}  // namespace mbstream::testing
