// GetSweep and CancelSweep: a sweep as a whole, through a real server (its runs found by
// their sweep id in the store).
#include <gmock/gmock.h>

#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class SweepServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // A sweep of the servo scene over duration_s (the values given), started `max_runs` at a
  // time (0 = all) from `first`, under `sweep_id` (empty: a new sweep).
  grpc::Status StartSlice(const std::vector<std::string>& durations, double realtime, int first,
                          int max_runs, const std::string& sweep_id,
                          v1::StartSweepResponse* response) {
    v1::StartSweepRequest request;
    request.set_model("irb1600");
    *request.mutable_base() = SceneSpec("seed-servo.json");
    // Pacing paces the frames kept: a paced sweep keeps them.
    request.mutable_base()->set_keep(realtime > 0 ? "all" : "summary");
    request.mutable_base()->set_realtime(realtime);
    v1::SweepAxis& axis = *request.add_grid();
    axis.set_path("duration_s");
    for (const std::string& value : durations) axis.add_values(value);
    request.set_first_point(first);
    request.set_max_runs(max_runs);
    request.set_sweep_id(sweep_id);
    grpc::ClientContext context;
    return stub().StartSweep(&context, request, response);
  }

  grpc::Status GetSweep(const std::string& sweep_id, v1::SweepProgress* progress) {
    v1::GetSweepRequest request;
    request.set_sweep_id(sweep_id);
    grpc::ClientContext context;
    return stub().GetSweep(&context, request, progress);
  }

  static int CountIn(const v1::SweepProgress& progress, v1::RunState state) {
    for (const v1::SweepStateCount& entry : progress.states()) {
      if (entry.state() == state) return entry.runs();
    }
    return 0;
  }
};

TEST_F(SweepServiceTest, ReportsTheWholeSweepStartedInSlices) {
  const std::vector<std::string> durations = {"0.1", "0.2", "0.15", "0.05"};
  v1::StartSweepResponse first, second;
  ASSERT_TRUE(StartSlice(durations, 0, 0, 2, "", &first).ok());
  const std::string id = first.sweep_id();

  v1::SweepProgress progress;
  ASSERT_TRUE(GetSweep(id, &progress).ok());
  EXPECT_EQ(progress.sweep_id(), id);
  EXPECT_EQ(progress.total_points(), 4);
  EXPECT_EQ(progress.started_runs(), 2);  // the second slice is not started yet
  EXPECT_FALSE(progress.cancelled());

  ASSERT_TRUE(StartSlice(durations, 0, 2, 0, id, &second).ok());
  std::vector<std::string> ids;
  for (const auto* slice : {&first, &second}) {
    for (const v1::RunInfo& run : slice->runs()) {
      EXPECT_EQ(run.sweep_id(), id);
      EXPECT_EQ(run.sweep_points(), 4);
      EXPECT_EQ(run.sweep_point(), static_cast<int>(ids.size()));
      ids.push_back(run.id());
    }
  }
  for (const std::string& run : ids) EXPECT_EQ(WaitForEnd(run).state(), v1::FINISHED);

  ASSERT_TRUE(GetSweep(id, &progress).ok());
  EXPECT_EQ(progress.started_runs(), 4);
  EXPECT_EQ(progress.ended_runs(), 4);
  EXPECT_EQ(CountIn(progress, v1::FINISHED), 4);
  EXPECT_EQ(progress.model_id(), first.runs(0).model_id());
  EXPECT_THAT(progress.run_ids(), ::testing::ElementsAreArray(ids));  // in point order

  const grpc::Status unknown = GetSweep("s-nosuch", &progress);
  EXPECT_EQ(unknown.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(unknown.error_message(), HasSubstr("s-nosuch"));
}

TEST_F(SweepServiceTest, CancellingASweepEndsItsRunsAndRefusesItsLaterSlices) {
  // Paced at wall-clock speed: 20 s each unless cancelled; more runs than workers, so some
  // are running and some queued when the sweep is cancelled.
  const std::vector<std::string> durations = {"20", "20", "20", "20", "20", "20"};
  v1::StartSweepResponse first;
  ASSERT_TRUE(StartSlice(durations, 1.0, 0, 4, "", &first).ok());
  const std::string id = first.sweep_id();

  v1::CancelSweepRequest request;
  request.set_sweep_id(id);
  v1::SweepProgress progress;
  {
    grpc::ClientContext context;
    const grpc::Status status = stub().CancelSweep(&context, request, &progress);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  EXPECT_TRUE(progress.cancelled());
  EXPECT_EQ(progress.started_runs(), 4);
  EXPECT_EQ(progress.ended_runs(), 4);  // it returns once its runs have ended
  EXPECT_EQ(CountIn(progress, v1::CANCELLED), 4);
  for (const v1::RunInfo& run : first.runs()) {
    EXPECT_EQ(WaitForEnd(run.id()).state(), v1::CANCELLED);
  }

  // The rest of the sweep is not started; GetSweep still says it was cancelled.
  v1::StartSweepResponse second;
  const grpc::Status later = StartSlice(durations, 1.0, 4, 0, id, &second);
  EXPECT_EQ(later.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(later.error_message(), HasSubstr("cancelled"));
  ASSERT_TRUE(GetSweep(id, &progress).ok());
  EXPECT_TRUE(progress.cancelled());
  EXPECT_EQ(progress.started_runs(), 4);
  EXPECT_EQ(progress.total_points(), 6);

  request.set_sweep_id("s-nosuch");
  grpc::ClientContext context;
  EXPECT_EQ(stub().CancelSweep(&context, request, &progress).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace mbstream::testing
