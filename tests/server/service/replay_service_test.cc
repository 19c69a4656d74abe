// Replays of stored runs on the Subscribe stream (replay.proto): the same frames bit for bit,
// seeks, pause and step, probe sets, comparisons, the errors, and the memory bound.
#include <gmock/gmock.h>

#include <google/protobuf/util/message_differencer.h>

#include "server/runs/replay_cursor.h"
#include "server/runs/run_manager.h"
#include "server/store/frame_chunks.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;
using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;
using google::protobuf::util::MessageDifferencer;

class ReplayServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // An ended run of `model` with `spec` (unpaced).
  v1::RunInfo EndedRun(const std::string& model, v1::RunSpec spec) {
    spec.set_realtime(0.0);
    const v1::RunInfo ended = WaitForEnd(StartRunOk(model, spec).id());
    EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
    return ended;
  }
  std::vector<v1::Frame> Frames(const std::string& run_id) {
    v1::RunInfo info;
    std::vector<v1::Frame> frames;
    EXPECT_TRUE(Result(run_id, &info, &frames, nullptr).ok());
    return frames;
  }

  // Opens a replay stream and reads its first events (subscribed, run_started, the state).
  std::unique_ptr<Stream> Replay(grpc::ClientContext* context, const std::string& run_id,
                                 const v1::Replay& replay, v1::ReplayState* state,
                                 int max_batch = 0) {
    std::unique_ptr<Stream> stream = stub().Subscribe(context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(run_id);
    start.mutable_start()->set_max_batch(max_batch);
    *start.mutable_start()->mutable_replay() = replay;
    EXPECT_TRUE(stream->Write(start));
    v1::SubscribeEvent event;
    EXPECT_TRUE(stream->Read(&event));
    EXPECT_EQ(event.subscribed(), "replay " + run_id);
    EXPECT_TRUE(stream->Read(&event));
    EXPECT_EQ(event.run_started().run().id(), run_id);
    EXPECT_TRUE(stream->Read(&event));
    EXPECT_TRUE(event.has_replay_state());
    *state = event.replay_state();
    return stream;
  }
  // The status of a replay the server refuses before it starts.
  grpc::Status Refusal(const std::string& run_id, const v1::Replay& replay) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = stub().Subscribe(&context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(run_id);
    *start.mutable_start()->mutable_replay() = replay;
    EXPECT_TRUE(stream->Write(start));
    v1::SubscribeEvent event;
    while (stream->Read(&event)) {
    }
    return stream->Finish();
  }
  static void Control(Stream& stream, const std::function<void(v1::ReplayControl&)>& set) {
    v1::SubscribeRequest request;
    set(*request.mutable_control());
    ASSERT_TRUE(stream.Write(request));
  }
  // The next event that is not a frame batch, with the frames read before it.
  static v1::SubscribeEvent NextNonFrame(Stream& stream, std::vector<v1::Frame>* frames) {
    v1::SubscribeEvent event;
    while (stream.Read(&event)) {
      if (!event.has_frames()) return event;
      frames->insert(frames->end(), event.frames().frames().begin(), event.frames().frames().end());
    }
    return v1::SubscribeEvent();
  }
  static void Finish(Stream& stream) {
    stream.WritesDone();
    v1::SubscribeEvent event;
    while (stream.Read(&event)) {
    }
    EXPECT_TRUE(stream.Finish().ok());
  }
};

TEST_F(ReplayServiceTest, ReplayGivesTheStoredFramesBitForBitAndStoresItsProbeSet) {
  const v1::RunInfo run = EndedRun("irb1600", SceneSpec("seed-run.json"));
  const std::vector<v1::Frame> stored = Frames(run.id());
  ASSERT_EQ(stored.size(), 401u);

  grpc::ClientContext context;
  v1::Replay replay;
  replay.set_speed(0.0);
  replay.set_viewer("test-viewer");
  replay.set_scene("seed scene");
  v1::ReplayState state;
  std::unique_ptr<Stream> stream = Replay(&context, run.id(), replay, &state, 16);
  EXPECT_EQ(state.frames(), 401);
  EXPECT_EQ(state.grid_frames(), 401);
  EXPECT_FALSE(state.paused());
  ASSERT_THAT(state.probe_set(), HasSubstr("ps-"));
  std::vector<v1::Frame> replayed;
  v1::SubscribeEvent event;
  while (stream->Read(&event) && !event.has_run_ended()) {
    ASSERT_TRUE(event.has_frames());
    EXPECT_EQ(event.frames().ghost_frames_size(), 0);
    for (const v1::Frame& frame : event.frames().frames()) {
      replayed.push_back(frame);
      v1::SubscribeRequest reply;
      v1::ProbeReport* probe = reply.mutable_probe();
      probe->set_seq(frame.seq());
      probe->set_probe("tcp");
      *probe->mutable_position_m() = frame.tcp_m();
      ASSERT_TRUE(stream->Write(reply));
    }
  }
  ASSERT_TRUE(event.has_run_ended());
  Finish(*stream);
  ASSERT_EQ(replayed.size(), stored.size());
  for (size_t i = 0; i < stored.size(); ++i) {
    ASSERT_TRUE(MessageDifferencer::Equals(replayed[i], stored[i])) << "frame " << i;
  }

  grpc::ClientContext list_context;
  v1::ListProbeSetsRequest list;
  list.set_run_id(run.id());
  v1::ListProbeSetsResponse sets;
  ASSERT_TRUE(stub().ListProbeSets(&list_context, list, &sets).ok());
  ASSERT_EQ(sets.sets_size(), 1);
  EXPECT_EQ(sets.sets(0).id(), state.probe_set());
  EXPECT_EQ(sets.sets(0).viewer(), "test-viewer");
  EXPECT_EQ(sets.sets(0).scene(), "seed scene");
  EXPECT_EQ(sets.sets(0).reports(), 401);

  grpc::ClientContext result_context;
  v1::GetResultRequest request;
  request.set_run_id(run.id());
  request.set_probe_set(state.probe_set());
  auto reader = stub().GetResult(&result_context, request);
  v1::ResultChunk chunk;
  std::vector<v1::ProbeReport> probes;
  while (reader->Read(&chunk))
    probes.insert(probes.end(), chunk.probes().begin(), chunk.probes().end());
  ASSERT_TRUE(reader->Finish().ok());
  ASSERT_EQ(probes.size(), 401u);
  for (const v1::ProbeReport& probe : probes) {
    EXPECT_EQ(probe.run_id(), run.id());
    EXPECT_EQ(probe.t_s(), stored.at(probe.seq()).t_s());
    EXPECT_EQ(probe.position_m().z(), stored.at(probe.seq()).tcp_m().z());
  }
  // The live run's own probes are untouched (no viewer answered it).
  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  std::vector<v1::ProbeReport> live;
  ASSERT_TRUE(Result(run.id(), &info, &frames, &live).ok());
  EXPECT_TRUE(live.empty());
}

// Unpaced, the server runs ahead of a viewer only as far as its probe answers allow, so
// that every answer is accepted however slow the viewer is (20,001 frames, a slow reader).
TEST_F(ReplayServiceTest, UnpacedReplayKeepsPaceWithAViewerThatAnswersProbes) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_output_interval_s(1e-3);
  const v1::RunInfo run = EndedRun("irb1600", spec);
  ASSERT_EQ(run.frames(), 20'001);
  grpc::ClientContext context;
  v1::Replay replay;
  replay.set_speed(0.0);
  replay.set_wait_for_probes(true);
  v1::ReplayState state;
  std::unique_ptr<Stream> stream = Replay(&context, run.id(), replay, &state, 64);
  v1::SubscribeEvent event;
  int64_t answered = 0;
  while (stream->Read(&event) && !event.has_run_ended()) {
    for (const v1::Frame& frame : event.frames().frames()) {
      v1::SubscribeRequest reply;
      reply.mutable_probe()->set_seq(frame.seq());
      reply.mutable_probe()->set_probe("tcp");
      *reply.mutable_probe()->mutable_position_m() = frame.tcp_m();
      ASSERT_TRUE(stream->Write(reply));
      ++answered;
    }
  }
  Finish(*stream);
  EXPECT_EQ(answered, 20'001);
  grpc::ClientContext list_context;
  v1::ListProbeSetsRequest list;
  list.set_run_id(run.id());
  v1::ListProbeSetsResponse sets;
  ASSERT_TRUE(stub().ListProbeSets(&list_context, list, &sets).ok());
  ASSERT_EQ(sets.sets_size(), 1);
  EXPECT_EQ(sets.sets(0).reports(), 20'001);  // none refused as too old
}

TEST_F(ReplayServiceTest, SeekPauseAndStepLandOnTheRequestedFrames) {
  const v1::RunInfo run = EndedRun("irb1600", SceneSpec("seed-run.json"));
  grpc::ClientContext context;
  v1::Replay replay;
  replay.set_from_seq(123);
  replay.set_paused(true);
  replay.set_speed(1.0);
  v1::ReplayState state;
  std::unique_ptr<Stream> stream = Replay(&context, run.id(), replay, &state);
  EXPECT_TRUE(state.paused());
  // Paused at the start: frame 123 comes, then nothing until a control.
  v1::SubscribeEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_EQ(event.frames().frames_size(), 1);
  EXPECT_EQ(event.frames().frames(0).seq(), 123);
  std::vector<v1::Frame> frames;
  Control(*stream, [](v1::ReplayControl& c) { c.set_step(1); });
  event = NextNonFrame(*stream, &frames);
  ASSERT_TRUE(event.has_replay_state());
  EXPECT_EQ(event.replay_state().seq(), 124);
  EXPECT_TRUE(event.replay_state().paused());
  ASSERT_EQ(frames.size(), 1u);  // one step and nothing else: the pause held
  EXPECT_EQ(frames[0].seq(), 124);

  frames.clear();
  Control(*stream, [](v1::ReplayControl& c) { c.set_step(-2); });
  event = NextNonFrame(*stream, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].seq(), 122);
  EXPECT_EQ(event.replay_state().seq(), 122);

  frames.clear();
  Control(*stream, [](v1::ReplayControl& c) { c.set_seek_seq(300); });
  event = NextNonFrame(*stream, &frames);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].seq(), 300);
  EXPECT_DOUBLE_EQ(frames[0].t_s(), 15.0);
  EXPECT_TRUE(event.replay_state().paused());

  Control(*stream, [](v1::ReplayControl& c) { c.set_seek_seq(401); });
  event = NextNonFrame(*stream, &frames);
  EXPECT_THAT(event.replay_state().error(), HasSubstr("give 0 to 400"));

  frames.clear();
  Control(*stream, [](v1::ReplayControl& c) { c.set_speed(0.0); });
  Control(*stream, [](v1::ReplayControl& c) { c.set_resume(true); });
  event = NextNonFrame(*stream, &frames);  // the speed's state
  event = NextNonFrame(*stream, &frames);  // the resume's state
  EXPECT_FALSE(event.replay_state().paused());
  event = NextNonFrame(*stream, &frames);
  EXPECT_TRUE(event.has_run_ended());
  ASSERT_EQ(frames.size(), 100u);  // 301 .. 400
  EXPECT_EQ(frames.front().seq(), 301);
  EXPECT_EQ(frames.back().seq(), 400);
  Finish(*stream);
}

TEST_F(ReplayServiceTest, BadReplaysAreRefusedWithTheirStatus) {
  const v1::RunInfo run = EndedRun("single_pendulum", v1::RunSpec());
  v1::Replay replay;
  EXPECT_EQ(Refusal("r-nosuch", replay).error_code(), grpc::StatusCode::NOT_FOUND);
  replay.set_from_seq(run.frames());
  grpc::Status status = Refusal(run.id(), replay);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("from_seq is 401"));
  EXPECT_THAT(status.error_message(), HasSubstr("give 0 to 400"));
  replay.set_from_seq(0);
  replay.set_speed(-1.0);
  status = Refusal(run.id(), replay);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("speed"));

  v1::RunSpec slow = SceneSpec("seed-run.json");
  slow.set_realtime(0.5);  // 40 s: still running while the test asks
  const v1::RunInfo running = StartRunOk("irb1600", slow);
  v1::Replay seek;
  seek.set_from_seq(10);
  status = Refusal(running.id(), seek);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("has not ended"));
  // Without replay options, a running run is served live.
  {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = stub().Subscribe(&context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(running.id());
    start.mutable_start()->mutable_replay()->set_speed(1.0);
    ASSERT_TRUE(stream->Write(start));
    v1::SubscribeEvent event;
    ASSERT_TRUE(stream->Read(&event));
    EXPECT_EQ(event.subscribed(), running.id());
    context.TryCancel();
    stream->Finish();
  }
  CancelRunOk(running.id());
}

TEST_F(ReplayServiceTest, ComparisonSendsTheGhostsFramesOnTheCommonGrid) {
  v1::RunSpec coarse = SceneSpec("seed-servo.json");
  coarse.set_duration_s(2.0);
  coarse.set_output_interval_s(0.05);
  v1::RunSpec fine = coarse;
  fine.set_output_interval_s(0.01);
  fine.set_rtol(1e-4);
  const v1::RunInfo a = EndedRun("irb1600", coarse);
  const v1::RunInfo b = EndedRun("irb1600", fine);
  const std::vector<v1::Frame> frames_b = Frames(b.id());
  const std::vector<v1::Frame> frames_a = Frames(a.id());

  grpc::ClientContext context;
  v1::Replay replay;
  replay.set_speed(0.0);
  replay.set_compare_run_id(b.id());
  v1::ReplayState state;
  std::unique_ptr<Stream> stream = Replay(&context, a.id(), replay, &state);
  EXPECT_EQ(state.compare_run_id(), b.id());
  EXPECT_EQ(state.stride(), 1);
  EXPECT_EQ(state.ghost_stride(), 5);
  EXPECT_EQ(state.grid_frames(), 41);
  int64_t k = 0;
  v1::SubscribeEvent event;
  while (stream->Read(&event) && !event.has_run_ended()) {
    ASSERT_EQ(event.frames().ghost_frames_size(), event.frames().frames_size());
    for (int i = 0; i < event.frames().frames_size(); ++i, ++k) {
      const v1::Frame& ghost = event.frames().ghost_frames(i);
      EXPECT_TRUE(MessageDifferencer::Equals(ghost, frames_b.at(5 * k))) << "grid step " << k;
      EXPECT_TRUE(MessageDifferencer::Equals(event.frames().frames(i), frames_a.at(k)));
      EXPECT_NEAR(ghost.t_s(), event.frames().frames(i).t_s(), 1e-12);
    }
  }
  EXPECT_EQ(k, 41);
  Finish(*stream);

  // The other way round: the ghost is the coarser run.
  grpc::ClientContext reverse_context;
  replay.set_compare_run_id(a.id());
  stream = Replay(&reverse_context, b.id(), replay, &state);
  EXPECT_EQ(state.stride(), 5);
  EXPECT_EQ(state.ghost_stride(), 1);
  Finish(*stream);

  v1::RunSpec odd = coarse;
  odd.set_output_interval_s(0.03);
  const v1::RunInfo c = EndedRun("irb1600", odd);
  replay.set_compare_run_id(c.id());
  grpc::Status status = Refusal(a.id(), replay);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("time grids cannot be aligned"));
  EXPECT_THAT(status.error_message(), HasSubstr("--output-interval 0.05"));

  const v1::RunInfo pendulum = EndedRun("single_pendulum", v1::RunSpec());
  replay.set_compare_run_id(pendulum.id());
  status = Refusal(a.id(), replay);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("joints differ"));
}

TEST_F(ReplayServiceTest, ReplayRunStreamsAStoredRunToTheFollowersAsIfLive) {
  const v1::RunInfo run = EndedRun("single_pendulum", v1::RunSpec());
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = stub().Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_follow(true);
  ASSERT_TRUE(stream->Write(start));
  v1::SubscribeEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_EQ(event.subscribed(), "follow");

  grpc::ClientContext replay_context;
  v1::ReplayRunRequest request;
  request.set_run_id(run.id());
  request.set_speed(1000.0);  // 20 s in 20 ms
  v1::RunInfo info;
  ASSERT_TRUE(stub().ReplayRun(&replay_context, request, &info).ok());
  EXPECT_EQ(info.frames(), 401);
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_TRUE(event.has_run_started());
  EXPECT_EQ(event.run_started().run().id(), run.id());
  const std::vector<v1::Frame> stored = Frames(run.id());
  int64_t frames = 0, missed = 0;
  while (stream->Read(&event) && !event.has_run_ended()) {
    missed += event.frames().missed();
    for (const v1::Frame& frame : event.frames().frames()) {
      EXPECT_TRUE(MessageDifferencer::Equals(frame, stored.at(frame.seq())));
      ++frames;
    }
  }
  EXPECT_EQ(event.run_ended().id(), run.id());
  EXPECT_EQ(frames + missed, 401);
  context.TryCancel();
  stream->Finish();

  auto refused = [&](const std::string& run_id, double speed) {
    grpc::ClientContext refused_context;
    v1::ReplayRunRequest bad;
    bad.set_run_id(run_id);
    bad.set_speed(speed);
    return stub().ReplayRun(&refused_context, bad, &info).error_code();
  };
  EXPECT_EQ(refused("r-nosuch", 1.0), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(refused(run.id(), -2.0), grpc::StatusCode::INVALID_ARGUMENT);
  v1::RunSpec slow = SceneSpec("seed-run.json");
  slow.set_realtime(0.5);
  const v1::RunInfo running = StartRunOk("irb1600", slow);
  EXPECT_EQ(refused(running.id(), 1.0), grpc::StatusCode::FAILED_PRECONDITION);
}

// A 1,000,001-frame run: the replay starts at once from any frame, and the server holds at
// most one stored chunk of frames for it at any time (the bound, not wall time, is tested;
// bench/replay_bench.cc times it).
TEST_F(ReplayServiceTest, MillionFrameReplayHoldsOneChunkAtATime) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_output_interval_s(2e-5);  // 20 s: 1,000,001 frames
  const v1::RunInfo run = EndedRun("irb1600", spec);
  ASSERT_EQ(run.frames(), 1'000'001);
  ResetReplayFramesPeak();
  ASSERT_EQ(replay_frames_held(), 0);
  grpc::ClientContext context;
  v1::Replay replay;
  replay.set_speed(0.0);
  replay.set_from_seq(900'000);
  v1::ReplayState state;
  std::unique_ptr<Stream> stream = Replay(&context, run.id(), replay, &state, 4096);
  int64_t frames = 0, next = 900'000;
  v1::SubscribeEvent event;
  while (stream->Read(&event) && !event.has_run_ended()) {
    for (const v1::Frame& frame : event.frames().frames()) {
      ASSERT_EQ(frame.seq(), next++);
      ++frames;
    }
    if (frames > 5'000 && frames < 5'000 + 4'096) {  // a seek back to the start, mid-stream
      Control(*stream, [](v1::ReplayControl& c) { c.set_seek_seq(0); });
      next = -1;
      break;
    }
  }
  // Frames already in flight come first; then frame 0 and on.
  while (next == -1 && stream->Read(&event) && !event.has_run_ended()) {
    if (event.has_frames() && event.frames().frames(0).seq() == 0) next = 1;
  }
  context.TryCancel();
  stream->Finish();
  EXPECT_LE(replay_frames_peak(), static_cast<int64_t>(kFramesPerChunk));
  EXPECT_EQ(next, 1);
}

}  // namespace
}  // namespace mbstream::testing
