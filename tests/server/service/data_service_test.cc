// DeleteRuns and DeleteModel through a real server: a running run cancelled then deleted, every
// read of a deleted run NOT_FOUND, a model refused while it has runs, and a result read while
// its run is deleted either whole or NOT_FOUND, never part of it.
#include <gmock/gmock.h>

#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class DataServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  grpc::Status DeleteRuns(const std::vector<std::string>& ids, v1::DeleteRunsResponse* response) {
    grpc::ClientContext context;
    v1::DeleteRunsRequest request;
    for (const std::string& id : ids) request.add_run_ids(id);
    return stub().DeleteRuns(&context, request, response);
  }
  grpc::Status DeleteModel(const std::string& model, bool with_runs,
                           v1::DeleteModelResponse* response) {
    grpc::ClientContext context;
    v1::DeleteModelRequest request;
    request.set_model(model);
    request.set_with_runs(with_runs);
    return stub().DeleteModel(&context, request, response);
  }
  grpc::StatusCode GetRunCode(const std::string& id) {
    grpc::ClientContext context;
    v1::GetRunRequest request;
    request.set_run_id(id);
    v1::RunInfo info;
    return stub().GetRun(&context, request, &info).error_code();
  }
  // A run that lasts until cancelled (1,000 s of simulated time at real time).
  v1::RunInfo StartLongRun(const std::string& model) {
    v1::RunSpec spec = SceneSpec("seed-run.json");
    spec.set_duration_s(1000.0);
    spec.set_realtime(1.0);
    return StartRunOk(model, spec);
  }
};

TEST_F(DataServiceTest, EveryReadOfADeletedRunIsNotFound) {
  const v1::RunInfo ended = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  ASSERT_EQ(WaitForEnd(ended.id()).state(), v1::FINISHED);
  const v1::RunInfo running = StartLongRun("irb1600");
  const v1::RunInfo kept = StartRunOk("irb1600", SceneSpec("seed-run.json"));
  ASSERT_EQ(WaitForEnd(kept.id()).state(), v1::FINISHED);

  v1::DeleteRunsResponse response;
  ASSERT_TRUE(DeleteRuns({ended.id(), running.id()}, &response).ok());
  ASSERT_EQ(response.runs_size(), 2);
  EXPECT_EQ(response.runs(0).state(), v1::FINISHED);
  EXPECT_EQ(response.runs(1).state(), v1::CANCELLED);  // cancelled first

  for (const std::string& id : {ended.id(), running.id()}) {
    SCOPED_TRACE(id);
    EXPECT_EQ(GetRunCode(id), grpc::StatusCode::NOT_FOUND);
    v1::RunInfo info;
    std::vector<v1::Frame> frames;
    EXPECT_EQ(Result(id, &info, &frames, nullptr).error_code(), grpc::StatusCode::NOT_FOUND);
    EXPECT_TRUE(frames.empty());
    grpc::ClientContext context;
    v1::ListProbeSetsRequest sets;
    sets.set_run_id(id);
    v1::ListProbeSetsResponse listed;
    EXPECT_EQ(stub().ListProbeSets(&context, sets, &listed).error_code(),
              grpc::StatusCode::NOT_FOUND);
    grpc::ClientContext replay_context;
    v1::ReplayRunRequest replay;
    replay.set_run_id(id);
    v1::RunInfo replayed;
    EXPECT_EQ(stub().ReplayRun(&replay_context, replay, &replayed).error_code(),
              grpc::StatusCode::NOT_FOUND);
  }
  grpc::ClientContext context;
  v1::ListRunsResponse listed;
  ASSERT_TRUE(stub().ListRuns(&context, v1::ListRunsRequest(), &listed).ok());
  ASSERT_EQ(listed.runs_size(), 1);
  EXPECT_EQ(listed.runs(0).id(), kept.id());
  // Unknown ids: NOT_FOUND naming it, and nothing deleted.
  const grpc::Status unknown = DeleteRuns({kept.id(), "r-nothing"}, &response);
  EXPECT_EQ(unknown.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(unknown.error_message(), HasSubstr("r-nothing"));
  EXPECT_EQ(GetRunCode(kept.id()), grpc::StatusCode::OK);
  EXPECT_EQ(DeleteRuns({}, &response).error_code(), grpc::StatusCode::INVALID_ARGUMENT);
}

TEST_F(DataServiceTest, AResultReadWhileItsRunIsDeletedIsWholeOrNotFound) {
  v1::RunSpec spec = SceneSpec("seed-run.json");
  spec.set_duration_s(1000.0);  // 20,001 frames: five stored chunks, several messages
  const v1::RunInfo started = StartRunOk("irb1600", spec);
  const v1::RunInfo ended = WaitForEnd(started.id());
  ASSERT_EQ(ended.state(), v1::FINISHED) << ended.message();

  grpc::ClientContext context;
  v1::GetResultRequest request;
  request.set_run_id(started.id());
  auto reader = stub().GetResult(&context, request);
  v1::ResultChunk chunk;
  ASSERT_TRUE(reader->Read(&chunk));  // the first message: the result is being read
  int64_t frames = chunk.frames_size();
  v1::DeleteRunsResponse response;
  ASSERT_TRUE(DeleteRuns({started.id()}, &response).ok());
  while (reader->Read(&chunk)) frames += chunk.frames_size();
  const grpc::Status status = reader->Finish();
  if (status.ok()) {
    EXPECT_EQ(frames, ended.frames());
  } else {
    EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND) << status.error_message();
    EXPECT_THAT(status.error_message(), HasSubstr("was deleted while its result"));
  }
  EXPECT_EQ(GetRunCode(started.id()), grpc::StatusCode::NOT_FOUND);
}

TEST_F(DataServiceTest, AModelWithRunsNeedsWithRuns) {
  v1::ModelBundle bundle = IrbBundle();
  bundle.set_name("mine");
  bundle.set_urdf(bundle.urdf() + "<!-- my own copy -->\n");
  const v1::ModelInfo model = SubmitOk(bundle);
  const v1::RunInfo ended = StartRunOk(model.id(), SceneSpec("seed-run.json"));
  ASSERT_EQ(WaitForEnd(ended.id()).state(), v1::FINISHED);
  const v1::RunInfo running = StartLongRun(model.id());

  v1::DeleteModelResponse response;
  grpc::Status status = DeleteModel("mine", false, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("still has 2 runs"));
  EXPECT_THAT(status.error_message(), HasSubstr("--with-runs"));
  EXPECT_EQ(GetRunCode(ended.id()), grpc::StatusCode::OK);

  ASSERT_TRUE(DeleteModel("mine", true, &response).ok());
  EXPECT_EQ(response.model().id(), model.id());
  EXPECT_EQ(response.runs_size(), 2);
  EXPECT_EQ(GetRunCode(ended.id()), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(GetRunCode(running.id()), grpc::StatusCode::NOT_FOUND);
  v1::RunInfo info;
  EXPECT_EQ(StartRun(model.id(), SceneSpec("seed-run.json"), &info).error_code(),
            grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(DeleteModel(model.id(), true, &response).error_code(), grpc::StatusCode::NOT_FOUND);

  // A built-in model comes back at every start: refused, saying so.
  status = DeleteModel("irb1600", true, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("built in"));

  // After a restart the model and its runs are still gone.
  StartServer();
  EXPECT_EQ(GetRunCode(ended.id()), grpc::StatusCode::NOT_FOUND);
  EXPECT_EQ(StartRun(model.id(), SceneSpec("seed-run.json"), &info).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace mbstream::testing
