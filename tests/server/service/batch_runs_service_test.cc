// StartRuns and GetResults: a sweep's runs queued in one call (all or none) and their results
// fetched in one stream, through a real server.
#include <gmock/gmock.h>

#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class BatchRunsServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  grpc::Status StartRuns(const std::vector<v1::RunSpec>& specs, v1::StartRunsResponse* response) {
    grpc::ClientContext context;
    v1::StartRunsRequest request;
    request.set_model("irb1600");
    for (const v1::RunSpec& spec : specs) *request.add_specs() = spec;
    return stub().StartRuns(&context, request, response);
  }

  int StoredRuns() {
    grpc::ClientContext context;
    v1::ListRunsResponse response;
    EXPECT_TRUE(stub().ListRuns(&context, v1::ListRunsRequest(), &response).ok());
    return response.runs_size();
  }

  // One run's part of a GetResults stream.
  struct Fetched {
    v1::RunInfo info;
    std::vector<v1::Frame> frames;
  };
  grpc::Status Results(const std::vector<std::string>& run_ids, std::vector<Fetched>* fetched) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
    v1::GetResultsRequest request;
    for (const std::string& id : run_ids) request.add_run_ids(id);
    request.set_wait(true);
    auto reader = stub().GetResults(&context, request);
    v1::ResultChunk chunk;
    while (reader->Read(&chunk)) {
      if (chunk.has_info()) fetched->push_back({chunk.info(), {}});
      EXPECT_FALSE(fetched->empty()) << "frames before any run's info";
      if (fetched->empty()) continue;
      for (const v1::Frame& frame : chunk.frames()) fetched->back().frames.push_back(frame);
    }
    return reader->Finish();
  }

  static v1::RunSpec Short(double duration_s) {
    v1::RunSpec spec = SceneSpec("seed-servo.json");
    spec.set_duration_s(duration_s);
    return spec;
  }
};

TEST_F(BatchRunsServiceTest, QueuesEverySpecInOrderAndStreamsEachResultWhole) {
  const std::vector<v1::RunSpec> specs = {Short(0.5), Short(1.0), Short(0.25)};
  v1::StartRunsResponse started;
  const grpc::Status status = StartRuns(specs, &started);
  ASSERT_TRUE(status.ok()) << status.error_message();
  ASSERT_EQ(started.runs_size(), 3);
  std::vector<std::string> ids;
  for (int i = 0; i < 3; ++i) {
    const v1::RunInfo& info = started.runs(i);
    EXPECT_EQ(info.state(), v1::QUEUED);
    EXPECT_DOUBLE_EQ(info.duration_s(), specs[i].duration_s());
    EXPECT_EQ(info.expected_frames(), static_cast<int64_t>(specs[i].duration_s() / 0.05) + 1);
    ids.push_back(info.id());
  }
  EXPECT_NE(ids[0], ids[1]);
  EXPECT_NE(ids[1], ids[2]);
  EXPECT_NE(ids[0], ids[2]);

  // Asked in another order than they run: each arrives whole, in the order asked.
  const std::vector<std::string> asked = {ids[2], ids[0], ids[1]};
  std::vector<Fetched> fetched;
  const grpc::Status fetched_status = Results(asked, &fetched);
  ASSERT_TRUE(fetched_status.ok()) << fetched_status.error_message();
  ASSERT_EQ(fetched.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(fetched[k].info.id(), asked[k]);
    EXPECT_EQ(fetched[k].info.state(), v1::FINISHED) << fetched[k].info.message();
    ASSERT_EQ(static_cast<int64_t>(fetched[k].frames.size()), fetched[k].info.expected_frames());
    EXPECT_EQ(fetched[k].frames.back().seq(), fetched[k].info.expected_frames() - 1);
  }
  // The same frames as GetResult sends for that run, bit for bit.
  v1::RunInfo info;
  std::vector<v1::Frame> single;
  ASSERT_TRUE(Result(ids[1], &info, &single, nullptr).ok());
  ASSERT_EQ(single.size(), fetched[2].frames.size());
  for (size_t f = 0; f < single.size(); ++f) {
    EXPECT_EQ(single[f].SerializeAsString(), fetched[2].frames[f].SerializeAsString()) << f;
  }
}

TEST_F(BatchRunsServiceTest, ABadSpecIsNamedAndNothingIsQueued) {
  v1::RunSpec bad = Short(1.0);
  bad.set_output_interval_s(-0.1);
  v1::StartRunsResponse started;
  grpc::Status status = StartRuns({Short(1.0), bad, Short(1.0)}, &started);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("specs[1]: "));
  EXPECT_THAT(status.error_message(), HasSubstr("output_interval_s"));
  EXPECT_EQ(StoredRuns(), 0);

  status = StartRuns({}, &started);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(status.error_message(), HasSubstr("at least one"));

  std::vector<Fetched> fetched;
  EXPECT_EQ(Results({}, &fetched).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(BatchRunsServiceTest, MoreRunsThanTheQueueTakesAreRefusedWhole) {
  ServerLimits limits;
  limits.workers = 1;
  limits.max_queued_runs = 3;
  StartServer(limits);
  v1::StartRunsResponse started;
  grpc::Status status = StartRuns(std::vector<v1::RunSpec>(4, Short(0.5)), &started);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("batches of at most 3"));
  EXPECT_EQ(StoredRuns(), 0);

  // A slow run holds the worker and two wait: a batch of two more does not fit, whole.
  v1::RunSpec slow = Short(20.0);
  slow.set_realtime(1.0);
  status = StartRuns({slow, slow, slow}, &started);
  ASSERT_TRUE(status.ok()) << status.error_message();
  v1::StartRunsResponse refused;
  status = StartRuns({Short(0.5), Short(0.5)}, &refused);
  // Until the worker claims the first, the queue holds three; after, two: either way two
  // more do not fit.
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_THAT(status.error_message(), HasSubstr("of these 2 runs"));
  EXPECT_EQ(StoredRuns(), 3);
  for (const v1::RunInfo& run : started.runs()) CancelRunOk(run.id());
}

TEST_F(BatchRunsServiceTest, AnUnknownRunEndsTheStreamAfterTheRunsBeforeIt) {
  v1::StartRunsResponse started;
  ASSERT_TRUE(StartRuns({Short(0.25)}, &started).ok());
  std::vector<Fetched> fetched;
  const grpc::Status status = Results({started.runs(0).id(), "r-nosuch"}, &fetched);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND);
  ASSERT_EQ(fetched.size(), 1u);
  EXPECT_EQ(fetched[0].info.state(), v1::FINISHED);
  EXPECT_EQ(static_cast<int64_t>(fetched[0].frames.size()), fetched[0].info.expected_frames());
}

}  // namespace
}  // namespace mbstream::testing
