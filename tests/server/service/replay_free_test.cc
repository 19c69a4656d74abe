// Replay and comparison of a run with free bodies (issue 43): a world of two free boxes, one
// thrown tumbling by initial_bodies, stored, then replayed: the replayed frames are the stored
// ones bit for bit, q with every position coordinate (a free joint's 7) and unit quaternions;
// comparing it with a second run of the world sends that run's frames as the ghost's. A
// world run and a run of another model are refused a comparison, naming both joint lists.
#include <gmock/gmock.h>

#include <google/protobuf/util/message_differencer.h>

#include <cmath>
#include <cstring>

#include "server/spec/run_spec_json.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;
using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;
using google::protobuf::util::MessageDifferencer;

constexpr char kTwoBoxes[] = R"(<?xml version="1.0"?>
<sdf version="1.8">
  <world name="two_boxes">
    <model name="box_a">
      <pose>0 0 1 0 0 0</pose>
      <link name="link">
        <inertial><mass>1</mass>
          <inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.3</izz></inertia></inertial>
      </link>
    </model>
    <model name="box_b">
      <pose>1 0 2 0.3 0 0.5</pose>
      <link name="link">
        <inertial><mass>2</mass>
          <inertia><ixx>0.2</ixx><iyy>0.3</iyy><izz>0.5</izz></inertia></inertial>
      </link>
    </model>
  </world>
</sdf>
)";

// box_b thrown up and spun near its intermediate axis, so that every quaternion component moves.
constexpr char kThrown[] = R"({"duration_s": 1, "output_interval_s": 0.01, "method": "bdf",
  "rtol": 1e-9, "atol": 1e-11, "initial_bodies": [{"name": "box_b::link",
  "linearVelocityMPerS": {"z": 3}, "angularVelocityRadPerS": {"x": 0.1, "y": 4, "z": 0.2}}]})";

class ReplayFreeTest : public ServerTest {
 protected:
  void SetUp() override {
    StartServer();
    v1::ModelBundle bundle;
    bundle.set_name("two_boxes");
    bundle.set_urdf(kTwoBoxes);
    bundle.set_urdf_file_name("two_boxes.sdf");
    const v1::ModelInfo model = SubmitOk(bundle);
    ASSERT_EQ(model.positions(), 14);
  }
  v1::RunInfo EndedRun(const v1::RunSpec& spec) {
    const v1::RunInfo ended = WaitForEnd(StartRunOk("two_boxes", spec).id());
    EXPECT_EQ(ended.state(), v1::FINISHED) << ended.message();
    return ended;
  }
  std::vector<v1::Frame> Frames(const std::string& run_id) {
    v1::RunInfo info;
    std::vector<v1::Frame> frames;
    EXPECT_TRUE(Result(run_id, &info, &frames, nullptr).ok());
    return frames;
  }
  // Replays `run_id` unpaced (compared with `ghost_id` when given) to its end: the frames and
  // the ghost's frames as the stream sends them.
  void ReplayAll(const std::string& run_id, const std::string& ghost_id,
                 std::vector<v1::Frame>* frames, std::vector<v1::Frame>* ghosts) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = stub().Subscribe(&context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(run_id);
    start.mutable_start()->mutable_replay()->set_speed(0.0);
    start.mutable_start()->mutable_replay()->set_compare_run_id(ghost_id);
    ASSERT_TRUE(stream->Write(start));
    v1::SubscribeEvent event;
    while (stream->Read(&event) && !event.has_run_ended()) {
      if (event.has_replay_state()) {
        EXPECT_EQ(event.replay_state().compare_run_id(), ghost_id);
      }
      if (!event.has_frames()) continue;
      frames->insert(frames->end(), event.frames().frames().begin(), event.frames().frames().end());
      ghosts->insert(ghosts->end(), event.frames().ghost_frames().begin(),
                     event.frames().ghost_frames().end());
    }
    EXPECT_TRUE(event.has_run_ended());
    stream->WritesDone();
    while (stream->Read(&event)) {
    }
    EXPECT_TRUE(stream->Finish().ok());
  }
  // Rejects the comparison of run_id with ghost_id; its status.
  grpc::Status CompareRefusal(const std::string& run_id, const std::string& ghost_id) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = stub().Subscribe(&context);
    v1::SubscribeRequest start;
    start.mutable_start()->set_run_id(run_id);
    start.mutable_start()->mutable_replay()->set_compare_run_id(ghost_id);
    EXPECT_TRUE(stream->Write(start));
    v1::SubscribeEvent event;
    while (stream->Read(&event)) {
    }
    return stream->Finish();
  }
};

TEST_F(ReplayFreeTest, AReplayedWorldRunIsTheStoredOneBitForBit) {
  const v1::RunInfo run = EndedRun(ParseRunSpecJson(kThrown, "thrown.json"));
  EXPECT_EQ(run.num_positions(), 14);
  const std::vector<v1::Frame> stored = Frames(run.id());
  ASSERT_EQ(stored.size(), 101u);
  // The stored run tumbles: box_b's quaternion (q[10..13]) moves in every component.
  for (int k = 10; k < 14; ++k) {
    EXPECT_GT(std::abs(stored.back().q(k) - stored.front().q(k)), 1e-3) << "q[" << k << "]";
  }
  std::vector<v1::Frame> replayed, ghosts;
  ReplayAll(run.id(), "", &replayed, &ghosts);
  EXPECT_TRUE(ghosts.empty());
  ASSERT_EQ(replayed.size(), stored.size());
  for (size_t i = 0; i < stored.size(); ++i) {
    ASSERT_EQ(replayed[i].q_size(), 14) << "frame " << i;
    ASSERT_EQ(replayed[i].qd_size(), 12) << "frame " << i;
    for (int k = 0; k < 14; ++k) {  // bit for bit (the message comparison below does too)
      ASSERT_EQ(std::memcmp(&replayed[i].q()[k], &stored[i].q()[k], sizeof(double)), 0)
          << "frame " << i << " q[" << k << "]";
    }
    for (const int k : {3, 10}) {
      const double norm = std::sqrt(replayed[i].q(k) * replayed[i].q(k) +
                                    replayed[i].q(k + 1) * replayed[i].q(k + 1) +
                                    replayed[i].q(k + 2) * replayed[i].q(k + 2) +
                                    replayed[i].q(k + 3) * replayed[i].q(k + 3));
      EXPECT_NEAR(norm, 1.0, 1e-15) << "frame " << i << " quaternion at q[" << k << "]";
    }
    ASSERT_TRUE(MessageDifferencer::Equals(replayed[i], stored[i])) << "frame " << i;
  }
}

TEST_F(ReplayFreeTest, AWorldRunIsComparedWithAnotherRunOfTheWorld) {
  const v1::RunInfo a = EndedRun(ParseRunSpecJson(kThrown, "thrown.json"));
  v1::RunSpec coarse = ParseRunSpecJson(kThrown, "thrown.json");
  coarse.set_output_interval_s(0.05);
  coarse.set_rtol(1e-5);
  const v1::RunInfo b = EndedRun(coarse);
  const std::vector<v1::Frame> frames_a = Frames(a.id()), frames_b = Frames(b.id());
  ASSERT_EQ(frames_b.size(), 21u);
  std::vector<v1::Frame> frames, ghosts;
  ReplayAll(a.id(), b.id(), &frames, &ghosts);
  ASSERT_EQ(frames.size(), 21u);  // the common grid: every fifth frame of a
  ASSERT_EQ(ghosts.size(), frames.size());
  double apart = 0;
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_TRUE(MessageDifferencer::Equals(frames[k], frames_a.at(5 * k))) << "grid step " << k;
    EXPECT_TRUE(MessageDifferencer::Equals(ghosts[k], frames_b.at(k))) << "grid step " << k;
    EXPECT_EQ(ghosts[k].q_size(), 14);
    for (int i = 0; i < 14; ++i) apart = std::max(apart, std::abs(ghosts[k].q(i) - frames[k].q(i)));
  }
  EXPECT_GT(apart, 0.0);  // two runs, at two tolerances: the ghost is another pose

  v1::ModelInfo irb = SubmitOk(IrbBundle());
  const v1::RunInfo arm = WaitForEnd(StartRunOk(irb.id(), SceneSpec("seed-run.json")).id());
  const grpc::Status status = CompareRefusal(a.id(), arm.id());
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("their models' joints differ (box_a::link.vx,"));
  EXPECT_THAT(status.error_message(), HasSubstr("compare two runs of the same model"));
}

}  // namespace
}  // namespace mbstream::testing
