// Hostile and heavy use through a real server (issue 13): slow readers lose nothing
// unreported, probe reports cannot write into other runs, oversized or absurd requests are
// refused at the door, lists page, idle streams are bounded, tokens own their runs.
#include <gmock/gmock.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <thread>

#include "server/runs/run_manager.h"
#include "server/wire/stats_conversion.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;
using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;

class HostileUseTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // A fast kinematic run of the seed experiment with `frames` output frames.
  static v1::RunSpec FastRun(int frames) {
    v1::RunSpec spec = SceneSpec("seed-run.json");
    spec.set_output_interval_s(20.0 / (frames - 1));
    spec.set_realtime(0.0);
    return spec;
  }
};

// Counts of one stream: every frame of the run delivered or reported missed, in order. The
// frames pushed to a subscriber are contiguous from the latest one at its attach; the oldest
// queued are dropped first, so the seq gap before each batch equals the batch's `missed`
// (the first batch's `missed` counts the frames before its first frame).
struct Tally {
  int64_t frames = 0, missed = 0, first_pushed = -1, last_seq = -1;
  bool gaps_match = true;
  void Add(const v1::FrameBatch& batch) {
    missed += batch.missed();
    if (batch.frames().empty()) return;
    if (first_pushed < 0) {
      first_pushed = batch.frames(0).seq() - batch.missed();
    } else {
      const int64_t gap =
          batch.frames(batch.frames_size() - 1).seq() - last_seq - batch.frames_size();
      if (gap != batch.missed()) gaps_match = false;
    }
    for (const v1::Frame& f : batch.frames()) {
      if (f.seq() <= last_seq) gaps_match = false;
      last_seq = f.seq();
      ++frames;
    }
  }
};

TEST_F(HostileUseTest, ASlowWatcherGetsEveryFrameOrItsCountBeforeTheFinalState) {
  ServerLimits limits;
  limits.subscriber_queue_frames = 16;
  StartServer(limits);
  const v1::RunInfo started = StartRunOk("irb1600", FastRun(40001));
  grpc::ClientContext context;
  v1::WatchRunRequest request;
  request.set_run_id(started.id());
  request.set_frames(true);
  auto reader = stub().WatchRun(&context, request);
  v1::WatchEvent event;
  ASSERT_TRUE(reader->Read(&event));  // the first progress event: the watch is attached
  ASSERT_TRUE(event.has_progress());
  ASSERT_EQ(WaitForEnd(started.id()).state(), v1::FINISHED);  // read nothing until then
  Tally tally;
  v1::RunInfo last;
  bool frame_after_final = false;
  while (reader->Read(&event)) {
    if (event.has_progress()) {
      last = event.progress();
    } else {
      if (IsFinalState(last.state())) frame_after_final = true;
      tally.Add(event.frames());
    }
  }
  ASSERT_TRUE(reader->Finish().ok());
  EXPECT_EQ(last.state(), v1::FINISHED);
  EXPECT_FALSE(frame_after_final);
  EXPECT_TRUE(tally.gaps_match);
  ASSERT_GE(tally.first_pushed, 0);
  EXPECT_EQ(tally.last_seq, 40000);
  EXPECT_EQ(tally.frames + tally.missed, 40001 - tally.first_pushed);
}

TEST_F(HostileUseTest, ASlowViewerGetsEveryFrameOrItsCountBeforeTheRunEnded) {
  ServerLimits limits;
  limits.subscriber_queue_frames = 16;
  StartServer(limits);
  const v1::RunInfo started = StartRunOk("irb1600", FastRun(40001));
  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = stub().Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_run_id(started.id());
  ASSERT_TRUE(stream->Write(start));
  v1::SubscribeEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_EQ(event.subscribed(), started.id());
  ASSERT_EQ(WaitForEnd(started.id()).state(), v1::FINISHED);  // read nothing until then
  Tally tally;
  bool ended = false, frame_after_end = false;
  while (stream->Read(&event)) {
    if (event.has_frames()) {
      if (ended) frame_after_end = true;
      tally.Add(event.frames());
    } else if (event.has_run_ended()) {
      ended = true;
      stream->WritesDone();
    }
  }
  ASSERT_TRUE(stream->Finish().ok());
  EXPECT_TRUE(ended);
  EXPECT_FALSE(frame_after_end);
  EXPECT_TRUE(tally.gaps_match);
  if (tally.first_pushed >= 0) {  // it attached while frames were still coming
    EXPECT_EQ(tally.last_seq, 40000);
    EXPECT_EQ(tally.frames + tally.missed, 40001 - tally.first_pushed);
  }
}

v1::SubscribeRequest Probe(const std::string& run_id, int64_t seq, const std::string& name,
                           double x = 1.0) {
  v1::SubscribeRequest request;
  v1::ProbeReport* probe = request.mutable_probe();
  probe->set_run_id(run_id);
  probe->set_seq(seq);
  probe->set_t_s(123.0);  // the server takes the frame's own time
  probe->set_probe(name);
  probe->mutable_position_m()->set_x(x);
  probe->set_frame("World");
  return request;
}

TEST_F(HostileUseTest, ProbeReportsAreKeptOnlyForFramesSentOnTheirStream) {
  ServerLimits limits;
  limits.probe_grace_s = 60.0;  // the run waits for the report of its last frame
  StartServer(limits);
  const v1::RunInfo other = StartRunOk("single_pendulum", v1::RunSpec());
  ASSERT_EQ(WaitForEnd(other.id()).state(), v1::FINISHED);

  grpc::ClientContext context;
  std::unique_ptr<Stream> stream = stub().Subscribe(&context);
  v1::SubscribeRequest start;
  start.mutable_start()->set_follow(true);
  ASSERT_TRUE(stream->Write(start));
  v1::SubscribeEvent event;
  ASSERT_TRUE(stream->Read(&event));
  ASSERT_EQ(event.subscribed(), "follow");
  WaitForSubscribers(1);
  const v1::RunInfo run = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  int64_t last_seq = -1;
  while (stream->Read(&event) && !event.has_run_ended()) {
    for (const v1::Frame& f : event.frames().frames()) {
      last_seq = f.seq();
      if (f.seq() == 400) continue;  // answered last, below
      ASSERT_TRUE(stream->Write(Probe(run.id(), f.seq(), "tcp")));
    }
    if (last_seq == 400) break;
  }
  ASSERT_EQ(last_seq, 400);
  const std::string nan_x = "nan";
  for (const v1::SubscribeRequest& bad :
       {Probe(other.id(), 5, "fake"),                // another run's id
        Probe(run.id(), 99999, "tcp"),               // a frame never sent
        Probe(run.id(), 5, "tcp"),                   // tcp of frame 5 again
        Probe(run.id(), 6, std::string(4096, 'p')),  // an oversized name
        Probe(run.id(), 7, "x", std::nan("")),       // not finite
        Probe(run.id(), 8, "far", 1e300)}) {         // absurd
    ASSERT_TRUE(stream->Write(bad));
  }
  for (int k = 0; k < 20; ++k) {  // 15 more probes on frame 9 are kept, then no more
    ASSERT_TRUE(stream->Write(Probe(run.id(), 9, "p" + std::to_string(k))));
  }
  ASSERT_TRUE(stream->Write(Probe(run.id(), 400, "tcp")));  // the run may now be stored
  ASSERT_EQ(WaitForEnd(run.id()).state(), v1::FINISHED);
  context.TryCancel();
  stream->Finish();

  v1::RunInfo info;
  std::vector<v1::Frame> frames;
  std::vector<v1::ProbeReport> probes;
  ASSERT_TRUE(Result(run.id(), &info, &frames, &probes).ok());
  EXPECT_EQ(probes.size(), 401u + 15u);
  std::set<std::pair<int64_t, std::string>> seen;
  for (const v1::ProbeReport& p : probes) {
    EXPECT_EQ(p.run_id(), run.id());
    EXPECT_TRUE(seen.insert({p.seq(), p.probe()}).second) << p.seq() << " " << p.probe();
    EXPECT_EQ(p.t_s(), frames.at(p.seq()).t_s());
    EXPECT_TRUE(std::isfinite(p.position_m().x()));
    EXPECT_GE(p.latency_us(), 0);
  }
  std::vector<v1::ProbeReport> other_probes;
  frames.clear();
  ASSERT_TRUE(Result(other.id(), &info, &frames, &other_probes).ok());
  EXPECT_TRUE(other_probes.empty());
}

TEST_F(HostileUseTest, OversizedOrAbsurdSpecsAreRefusedAndListsStillWork) {
  v1::RunInfo info;
  v1::RunSpec table = SceneSpec("seed-run.json");
  table.set_erk_table(std::string(25 << 20, 'x'));
  grpc::Status status = StartRun("irb1600", table, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_LT(status.error_message().size(), 1000u);

  v1::RunSpec name = SceneSpec("seed-run.json");
  name.set_method(std::string(1 << 20, 'm'));
  status = StartRun("irb1600", name, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("method"));
  EXPECT_LT(status.error_message().size(), 1000u);

  v1::RunSpec tiny = SceneSpec("seed-run.json");
  tiny.set_output_interval_s(1e-300);
  status = StartRun("irb1600", tiny, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("output_interval_s"));

  v1::RunSpec slow = SceneSpec("seed-run.json");
  slow.set_realtime(1e-9);
  status = StartRun("irb1600", slow, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("realtime"));

  v1::RunSpec paced = SceneSpec("seed-run.json");
  paced.set_realtime(1e-3);  // 20 s simulated over 20,000 s of wall time
  ServerLimits limits;
  limits.max_duration_s = 3600.0;
  StartServer(limits);
  status = StartRun("irb1600", paced, &info);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("realtime"));

  // Unknown fields (a newer client, or padding) are not kept in the run's info.
  v1::RunSpec padded = SceneSpec("seed-run.json");
  padded.GetReflection()->MutableUnknownFields(&padded)->AddLengthDelimited(
      999, std::string(2 << 20, 'u'));
  const v1::RunInfo kept = StartRunOk("irb1600", padded);
  EXPECT_LT(kept.spec().ByteSizeLong(), 10000u);
  WaitForEnd(kept.id());

  for (double interval : {std::numeric_limits<double>::infinity(), 1e300, 1e-9, -1.0}) {
    grpc::ClientContext context;
    v1::WatchRunRequest request;
    request.set_run_id(kept.id());
    request.set_progress_interval_s(interval);
    auto reader = stub().WatchRun(&context, request);
    v1::WatchEvent event;
    while (reader->Read(&event)) {
    }
    status = reader->Finish();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << interval;
    EXPECT_THAT(status.error_message(), HasSubstr("progress_interval_s"));
  }
}

TEST_F(HostileUseTest, ListRunsPagesNewestFirst) {
  std::vector<std::string> ids;
  for (int i = 0; i < 5; ++i) {
    ids.push_back(StartRunOk("single_pendulum", v1::RunSpec()).id());
    WaitForEnd(ids.back());  // distinct creation order
  }
  std::vector<std::string> listed;
  v1::ListRunsRequest request;
  request.set_page_size(2);
  int pages = 0;
  do {
    grpc::ClientContext context;
    v1::ListRunsResponse response;
    ASSERT_TRUE(stub().ListRuns(&context, request, &response).ok());
    EXPECT_LE(response.runs_size(), 2);
    for (const v1::RunInfo& r : response.runs()) listed.push_back(r.id());
    request.set_page_token(response.next_page_token());
    ++pages;
  } while (!request.page_token().empty() && pages < 10);
  EXPECT_EQ(pages, 3);
  EXPECT_EQ(listed, std::vector<std::string>(ids.rbegin(), ids.rend()));

  request.Clear();
  request.set_limit(3);
  request.set_page_size(2);
  listed.clear();
  do {
    grpc::ClientContext context;
    v1::ListRunsResponse response;
    ASSERT_TRUE(stub().ListRuns(&context, request, &response).ok());
    for (const v1::RunInfo& r : response.runs()) listed.push_back(r.id());
    request.set_page_token(response.next_page_token());
  } while (!request.page_token().empty());
  EXPECT_EQ(listed, std::vector<std::string>({ids[4], ids[3], ids[2]}));

  grpc::ClientContext context;
  v1::ListRunsResponse response;
  request.set_page_token("not a token");
  EXPECT_EQ(stub().ListRuns(&context, request, &response).error_code(),
            grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(HostileUseTest, StreamsThatNeverStartAreCountedAndEnded) {
  ServerLimits limits;
  limits.max_subscribers = 3;
  limits.subscribe_start_s = 0.5;
  StartServer(limits);
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  std::vector<std::unique_ptr<Stream>> idle;
  for (int i = 0; i < 3; ++i) {
    contexts.push_back(std::make_unique<grpc::ClientContext>());
    idle.push_back(stub().Subscribe(contexts.back().get()));
  }
  WaitForSubscribers(3);  // counted before they sent anything
  {
    grpc::ClientContext context;
    std::unique_ptr<Stream> one_more = stub().Subscribe(&context);
    v1::SubscribeEvent event;
    EXPECT_FALSE(one_more->Read(&event));
    EXPECT_EQ(one_more->Finish().error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  }
  for (auto& stream : idle) {  // each is ended by the server after its deadline
    v1::SubscribeEvent event;
    EXPECT_FALSE(stream->Read(&event));
    EXPECT_FALSE(stream->Finish().ok());
  }
  WaitForSubscribers(0);
}

TEST_F(HostileUseTest, ARunTokenCancelsOnlyItsOwnRunsAndAdminAny) {
  const std::string file = (data_.path() / "tokens").string();
  std::ofstream(file) << "alice-run-token-0123456789 run,view\n"
                      << "bob-run-token-0123456789ab run,view\n"
                      << "root-admin-token-0123456789 admin\n";
  StartServer(ServerLimits(), file);
  auto call = [&](const std::string& token, auto&& rpc) {
    grpc::ClientContext context;
    context.AddMetadata("authorization", token);
    return rpc(context);
  };
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_realtime(1.0);
  v1::RunInfo run;
  ASSERT_TRUE(call("bearer alice-run-token-0123456789", [&](grpc::ClientContext& c) {
                v1::StartRunRequest request;
                request.set_model("irb1600");
                *request.mutable_spec() = spec;
                return stub().StartRun(&c, request, &run);
              }).ok());  // the scheme name is case-insensitive
  EXPECT_THAT(run.owner(), ::testing::StartsWith("t-"));
  auto cancel = [&](const std::string& token) {
    return call(token, [&](grpc::ClientContext& c) {
      v1::CancelRunRequest request;
      request.set_run_id(run.id());
      v1::RunInfo info;
      return stub().CancelRun(&c, request, &info);
    });
  };
  const grpc::Status bob = cancel("Bearer bob-run-token-0123456789ab");
  EXPECT_EQ(bob.error_code(), grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_THAT(bob.error_message(), HasSubstr("another token"));
  EXPECT_TRUE(cancel("BEARER root-admin-token-0123456789").ok());
}

TEST_F(HostileUseTest, FollowersJoiningWhileRunsStartSeeEachRunOnce) {
  // Followers attach while runs are being started (the race of a follower subscribing
  // between a run's RUNNING and the worker attaching the followers): no run twice.
  constexpr int kFollowers = 12, kRuns = 8;
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_duration_s(0.5);
  std::vector<std::thread> followers;
  std::vector<std::map<std::string, int>> started(kFollowers);
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  for (int i = 0; i < kFollowers; ++i) contexts.push_back(std::make_unique<grpc::ClientContext>());
  for (int i = 0; i < kFollowers; ++i) {
    followers.emplace_back([&, i] {
      std::unique_ptr<Stream> stream = stub().Subscribe(contexts[i].get());
      v1::SubscribeRequest start;
      start.mutable_start()->set_follow(true);
      if (!stream->Write(start)) return;
      v1::SubscribeEvent event;
      while (stream->Read(&event)) {
        if (event.has_run_started()) ++started[i][event.run_started().run().id()];
      }
      stream->Finish();
    });
  }
  std::vector<std::string> ids;
  for (int k = 0; k < kRuns; ++k) ids.push_back(StartRunOk("irb1600", spec).id());
  for (const std::string& id : ids) WaitForEnd(id);
  WaitForSubscribers(kFollowers);
  for (auto& context : contexts) context->TryCancel();
  for (std::thread& follower : followers) follower.join();
  for (const auto& seen : started) {
    for (const auto& [id, count] : seen) EXPECT_EQ(count, 1) << id;
  }
}

TEST(ExposureWarnings, SayWhatIsMissingOnANetworkAddress) {
  ServerConfig config;
  config.listen = "127.0.0.1:0";
  EXPECT_TRUE(ExposureWarnings(config).empty());
  config.listen = "unix:/tmp/x.sock";
  EXPECT_TRUE(ExposureWarnings(config).empty());
  config.listen = "0.0.0.0:50051";
  ASSERT_EQ(ExposureWarnings(config).size(), 2u);
  EXPECT_THAT(ExposureWarnings(config)[0], HasSubstr("TLS"));
  config.tls.cert_file = "cert.pem";
  ASSERT_EQ(ExposureWarnings(config).size(), 1u);
  EXPECT_THAT(ExposureWarnings(config)[0], HasSubstr("token"));
  config.token_file = "tokens";
  EXPECT_TRUE(ExposureWarnings(config).empty());
}

}  // namespace
}  // namespace mbstream::testing
