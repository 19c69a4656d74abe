// Subscribe (viewers) and fan-out: probes, slow and vanishing subscribers, follow mode.
#include <gmock/gmock.h>

#include <thread>

#include "server/runs/run_manager.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;

class StreamsServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  std::unique_ptr<Stream> Subscribe(grpc::ClientContext* context, const std::string& run_id,
                                    int max_batch = 0) {
    std::unique_ptr<Stream> stream = stub().Subscribe(context);
    v1::SubscribeRequest start;
    if (run_id.empty()) {
      start.mutable_start()->set_follow(true);
    } else {
      start.mutable_start()->set_run_id(run_id);
    }
    start.mutable_start()->set_max_batch(max_batch);
    EXPECT_TRUE(stream->Write(start));
    v1::SubscribeEvent acknowledgement;  // the subscription is registered
    EXPECT_TRUE(stream->Read(&acknowledgement));
    EXPECT_EQ(acknowledgement.subscribed(), run_id.empty() ? "follow" : run_id);
    return stream;
  }
};

TEST_F(StreamsServiceTest, ViewerAnswersEveryFrameAndProbesAreStoredWithLatency) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(10.0);  // 2 s
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = Subscribe(&context, "");  // follow: from the first frame
  const v1::RunInfo run = StartRunOk("irb1600", spec);
  v1::SubscribeEvent event;
  bool started = false, ended = false;
  int64_t answered = 0;
  while (stream->Read(&event)) {
    if (event.has_run_started()) {
      started = true;
      EXPECT_EQ(event.run_started().run().id(), run.id());
      EXPECT_EQ(event.run_started().model().dofs(), 6);
      EXPECT_FALSE(event.run_started().bundle().urdf().empty());
    } else if (event.has_frames()) {
      for (const v1::Frame& frame : event.frames().frames()) {
        v1::SubscribeRequest reply;
        v1::ProbeReport* probe = reply.mutable_probe();
        probe->set_run_id(run.id());
        probe->set_seq(frame.seq());
        probe->set_t_s(frame.t_s());
        probe->set_probe("tcp");
        *probe->mutable_position_m() = frame.tcp_m();
        probe->set_frame("World");
        ASSERT_TRUE(stream->Write(reply));
        ++answered;
      }
    } else if (event.has_run_ended()) {
      ended = true;
      stream->WritesDone();
    }
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_TRUE(started);
  EXPECT_TRUE(ended);
  EXPECT_EQ(WaitForEnd(run.id()).state(), v1::FINISHED);
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  std::vector<v1::ProbeReport> probes;
  ASSERT_TRUE(Result(run.id(), &info, &frames, &probes).ok());
  ASSERT_EQ(static_cast<int64_t>(probes.size()), answered);
  EXPECT_EQ(answered, 401);
  for (const v1::ProbeReport& probe : probes) {
    const v1::Frame& frame = frames.at(probe.seq());
    EXPECT_EQ(probe.position_m().x(), frame.tcp_m().x());
    EXPECT_EQ(probe.t_s(), frame.t_s());
    EXPECT_GE(probe.latency_us(), 0);
    EXPECT_LT(probe.latency_us(), 1'000'000);
  }
}

TEST_F(StreamsServiceTest, SlowSubscriberDoesNotSlowTheRunAndIsToldWhatItMissed) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_output_interval_s(1e-4);  // 200,001 frames as fast as possible
  spec.set_realtime(0.0);
  v1::RunInfo run;
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream;
  {
    // Follow, so that the subscriber is attached before the run's first frame.
    stream = Subscribe(&context, "", 1);
    WaitForSubscribers(1);
    run = StartRunOk("irb1600", spec);
  }
  v1::SubscribeEvent event;
  ASSERT_TRUE(stream->Read(&event));  // run_started
  ASSERT_TRUE(event.has_run_started());
  ASSERT_TRUE(stream->Read(&event));
  // The subscriber reads nothing more until the run has ended: the run is not held back by
  // it (how much it costs is measured in bench/stream_bench.cc, not here).
  const v1::RunInfo ended = WaitForEnd(run.id());
  ASSERT_EQ(ended.state(), v1::FINISHED);
  int64_t frames = event.frames().frames_size(), missed = event.frames().missed();
  while (stream->Read(&event) && !event.has_run_ended()) {
    frames += event.frames().frames_size();
    missed += event.frames().missed();
  }
  EXPECT_TRUE(event.has_run_ended());
  EXPECT_GT(missed, 100'000);
  EXPECT_EQ(frames + missed, 200'001);
  context.TryCancel();
  stream->Finish();
  WaitForSubscribers(0);
}

TEST_F(StreamsServiceTest, VanishedSubscriberIsCleanedUp) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);
  const v1::RunInfo run = StartRunOk("irb1600", spec);
  for (int i = 0; i < 3; ++i) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = Subscribe(&context, run.id());
    v1::SubscribeEvent event;
    ASSERT_TRUE(stream->Read(&event));
    context.TryCancel();  // the viewer disappears without a goodbye
    stream->Finish();
  }
  WaitForSubscribers(0);
  CancelRunOk(run.id());
}

TEST_F(StreamsServiceTest, FollowAttachesToEachNewRun) {
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = Subscribe(&context, "");
  WaitForSubscribers(1);
  for (int i = 0; i < 2; ++i) {
    const v1::RunInfo run = StartRunOk("single_pendulum", v1::RunSpec());
    v1::SubscribeEvent event;
    ASSERT_TRUE(stream->Read(&event));
    ASSERT_TRUE(event.has_run_started());
    EXPECT_EQ(event.run_started().run().id(), run.id());
    int64_t frames = 0, missed = 0;
    while (stream->Read(&event) && !event.has_run_ended()) {
      frames += event.frames().frames_size();
      missed += event.frames().missed();
    }
    EXPECT_EQ(event.run_ended().id(), run.id());
    EXPECT_EQ(frames + missed, 401);
  }
  context.TryCancel();
  stream->Finish();
  WaitForSubscribers(0);
}

TEST_F(StreamsServiceTest, FirstMessageMustBeStart) {
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = stub().Subscribe(&context);
  v1::SubscribeRequest probe;
  probe.mutable_probe()->set_seq(1);
  stream->Write(probe);
  stream->WritesDone();
  v1::SubscribeEvent event;
  EXPECT_FALSE(stream->Read(&event));
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), ::testing::HasSubstr("start"));
}

TEST_F(StreamsServiceTest, UnknownRunIsNotFoundWhileTheViewerStillStreams) {
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = stub().Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_run_id("r-nosuch");
  ASSERT_TRUE(stream->Write(start));  // and no half-close: the viewer would send probes
  v1::SubscribeEvent event;
  EXPECT_FALSE(stream->Read(&event));
  const grpc::Status status = stream->Finish();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(status.error_message(), ::testing::HasSubstr("r-nosuch"));
  WaitForSubscribers(0);
}

}  // namespace
}  // namespace mbstream::testing
