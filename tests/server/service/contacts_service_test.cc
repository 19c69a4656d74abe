// Contacts on the wire (issue 44): Frame.contacts for the subscribers that ask
// (SubscribeRequest.Start.contacts), none for the others; kept with the stored frames (results,
// replays) and summarised in RunStats.contact. The scene: a 2 kg box resting on a plane.
#include <gmock/gmock.h>

#include "server/wire/frame_conversion.h"
#include "server/wire/model_bundle_files.h"
#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using Stream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;

constexpr double kWeight = 2.0 * 9.81;  // N, the box's

class ContactsServiceTest : public ServerTest {
 protected:
  void SetUp() override {
    StartServer();
    model_ = SubmitOk(ReadModelBundle(
                          std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/box_resting.sdf",
                          "", {}, ""))
                 .id();
    spec_.set_duration_s(1.0);
    spec_.set_output_interval_s(0.05);
  }

  std::unique_ptr<Stream> Subscribe(grpc::ClientContext* context, bool contacts,
                                    const v1::Replay* replay = nullptr,
                                    const std::string& run_id = "") {
    std::unique_ptr<Stream> stream = stub().Subscribe(context);
    v1::SubscribeRequest start;
    if (run_id.empty()) {
      start.mutable_start()->set_follow(true);
    } else {
      start.mutable_start()->set_run_id(run_id);
    }
    if (replay != nullptr) *start.mutable_start()->mutable_replay() = *replay;
    start.mutable_start()->set_contacts(contacts);
    EXPECT_TRUE(stream->Write(start));
    v1::SubscribeEvent acknowledgement;
    EXPECT_TRUE(stream->Read(&acknowledgement));
    EXPECT_FALSE(acknowledgement.subscribed().empty());
    return stream;
  }

  // Every frame of the stream's (first) run, until it ended.
  static std::vector<v1::Frame> ReadRun(Stream& stream) {
    std::vector<v1::Frame> frames;
    v1::SubscribeEvent event;
    while (stream.Read(&event)) {
      if (event.has_frames()) {
        frames.insert(frames.end(), event.frames().frames().begin(), event.frames().frames().end());
      } else if (event.has_run_ended()) {
        stream.WritesDone();
      }
    }
    return frames;
  }

  static double NormalForceSum(const v1::Frame& frame) {
    double sum = 0.0;
    // The force on a (the floor) is the box's weight, downwards.
    for (const v1::FrameContact& c : frame.contacts()) sum -= c.normal_force_n() * c.normal().z();
    return sum;
  }

  std::string model_;
  v1::RunSpec spec_;
};

TEST_F(ContactsServiceTest, SubscribersThatAskGetEachFramesContactsAndTheOthersNone) {
  grpc::ClientContext with_context, without_context;
  std::unique_ptr<Stream> with = Subscribe(&with_context, true);
  std::unique_ptr<Stream> without = Subscribe(&without_context, false);
  WaitForSubscribers(2);
  const v1::RunInfo run = StartRunOk(model_, spec_);
  const std::vector<v1::Frame> shown = ReadRun(*with);
  const std::vector<v1::Frame> plain = ReadRun(*without);
  ASSERT_TRUE(with->Finish().ok());
  ASSERT_TRUE(without->Finish().ok());
  ASSERT_EQ(shown.size(), 21u);
  ASSERT_EQ(plain.size(), 21u);
  for (const v1::Frame& frame : plain) EXPECT_EQ(frame.contacts_size(), 0);
  // Resting on its four bottom corners: their normal forces carry its weight; the floor is a,
  // the box b, the normal from the box toward the floor, the points on the bottom face.
  const v1::Frame& last = shown.back();
  ASSERT_EQ(last.contacts_size(), 4);
  EXPECT_NEAR(NormalForceSum(last), kWeight, 1e-3 * kWeight);
  for (const v1::FrameContact& c : last.contacts()) {
    EXPECT_EQ(c.link_a(), "ground::floor");
    EXPECT_EQ(c.collision_a(), "plane");
    EXPECT_EQ(c.link_b(), "box::body");
    EXPECT_EQ(c.collision_b(), "cube");
    EXPECT_NEAR(c.normal().z(), -1.0, 1e-12);
    EXPECT_NEAR(std::abs(c.point_m().x()), 0.1, 1e-6);
    EXPECT_NEAR(std::abs(c.point_m().y()), 0.1, 1e-6);
    EXPECT_GT(c.depth_m(), 0.0);
    EXPECT_LT(c.depth_m(), 1e-3);
  }
  const v1::RunInfo ended = WaitForEnd(run.id());
  ASSERT_EQ(ended.state(), v1::FINISHED);
  ASSERT_TRUE(ended.stats().has_contact());
  EXPECT_EQ(ended.stats().contact().contacts_peak(), 4);
  EXPECT_GT(ended.stats().contact().penetration_max_m(), 0.0);
  EXPECT_GT(ended.stats().contact().penetration_relative_max(), 0.0);

  // The stored frames keep them: the result's frames are the ones the first subscriber got,
  // and the result rebuilt from them has contacts.csv's rows.
  v1::RunInfo info;
  std::vector<v1::Frame> stored;
  ASSERT_TRUE(Result(run.id(), &info, &stored, nullptr).ok());
  ASSERT_EQ(stored.size(), shown.size());
  for (size_t k = 0; k < stored.size(); ++k) {
    ASSERT_EQ(stored[k].contacts_size(), shown[k].contacts_size()) << "frame " << k;
    for (int i = 0; i < stored[k].contacts_size(); ++i) {
      EXPECT_EQ(stored[k].contacts(i).normal_force_n(), shown[k].contacts(i).normal_force_n());
    }
  }
  const RunResult result = ResultFromFrames(info, stored);
  ASSERT_TRUE(result.contacts.active);
  EXPECT_EQ(result.contacts.count_peak, 4);
  EXPECT_EQ(result.contacts.link, (std::vector<std::string>{"ground::floor", "box::body"}));
}

// Formulation body-baumgarte (server/body/body_contact.h) through the server: its frames carry
// their contacts into the store as the joint formulation's do. A frictionless pendulum comes to
// rest on its tip: the floor carries half its weight (the moments about the hinge).
TEST_F(ContactsServiceTest, ABodyBaumgarteRunStoresItsContacts) {
  const std::string pendulum =
      SubmitOk(ReadModelBundle(
                   std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/pendulum_on_floor.sdf",
                   "", {}, ""))
          .id();
  v1::RunSpec spec;
  spec.set_duration_s(5.0);
  spec.set_output_interval_s(0.1);
  spec.set_formulation("body-baumgarte");
  spec.mutable_contact()->set_dissipation_s_per_m(2.0);
  spec.mutable_contact()->set_mu_static(0.0);
  spec.mutable_contact()->set_mu_dynamic(0.0);
  const v1::RunInfo run = StartRunOk(pendulum, spec);
  const v1::RunInfo ended = WaitForEnd(run.id());
  ASSERT_EQ(ended.state(), v1::FINISHED) << ended.message();
  EXPECT_EQ(ended.stats().formulation(), "body-baumgarte");
  EXPECT_THAT(ended.stats().formulation_reason(), ::testing::HasSubstr("contact on"));
  ASSERT_TRUE(ended.stats().has_contact());
  EXPECT_EQ(ended.stats().contact().contacts_peak(), 1);
  v1::RunInfo info;
  std::vector<v1::Frame> stored;
  ASSERT_TRUE(Result(run.id(), &info, &stored, nullptr).ok());
  ASSERT_EQ(stored.size(), 51u);
  ASSERT_EQ(stored.back().contacts_size(), 1);
  const v1::FrameContact& tip = stored.back().contacts(0);
  EXPECT_EQ(tip.link_a(), "ground::floor");
  EXPECT_EQ(tip.link_b(), "pendulum::arm");
  EXPECT_NEAR(NormalForceSum(stored.back()), 0.5 * 9.81, 1e-3 * 9.81);
}

TEST_F(ContactsServiceTest, AReplayCarriesTheStoredContactsWhenAsked) {
  const v1::RunInfo run = StartRunOk(model_, spec_);
  ASSERT_EQ(WaitForEnd(run.id()).state(), v1::FINISHED);
  v1::Replay replay;
  replay.set_speed(0.0);
  for (const bool contacts : {true, false}) {
    grpc::ClientContext context;
    std::unique_ptr<Stream> stream = Subscribe(&context, contacts, &replay, run.id());
    std::vector<v1::Frame> frames;
    v1::SubscribeEvent event;
    while (stream->Read(&event)) {
      if (event.has_frames()) {
        frames.insert(frames.end(), event.frames().frames().begin(), event.frames().frames().end());
      }
      if (static_cast<int>(frames.size()) == 21) break;
    }
    context.TryCancel();
    ASSERT_EQ(frames.size(), 21u) << "contacts " << contacts;
    EXPECT_EQ(frames.back().contacts_size(), contacts ? 4 : 0);
    if (contacts) {
      EXPECT_NEAR(NormalForceSum(frames.back()), kWeight, 1e-3 * kWeight);
    }
  }
}

}  // namespace
}  // namespace mbstream::testing
