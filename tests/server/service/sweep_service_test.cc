// Sweeps the server feeds, through a real server: StartSweep stores the sweep and queues its
// first window, the server queues the rest as runs end (at most a window queued or running),
// GetSweep counts it and pages its runs with their values, CancelSweep ends it, a point the
// model refuses becomes a FAILED run of the sweep, and a server started again on the same data
// goes on with the points not queued (and the queued ones it left).
#include <gmock/gmock.h>

#include <chrono>
#include <thread>

#include "tests/server/service/server_fixture.h"

namespace mbstream::testing {
namespace {

using ::testing::HasSubstr;

class SweepServiceTest : public ServerTest {
 protected:
  void SetUp() override { StartServer(); }

  // A sweep of the servo scene over duration_s (the values given), at most `window` runs
  // queued or running at once; paced sweeps keep their frames.
  grpc::Status Start(const std::vector<std::string>& durations, double realtime, int window,
                     v1::StartSweepResponse* response) {
    v1::StartSweepRequest request;
    request.set_model("irb1600");
    *request.mutable_base() = SceneSpec("seed-servo.json");
    request.mutable_base()->set_keep(realtime > 0 ? "all" : "summary");
    request.mutable_base()->set_realtime(realtime);
    v1::SweepAxis& axis = *request.add_grid();
    axis.set_path("duration_s");
    for (const std::string& value : durations) axis.add_values(value);
    request.set_window(window);
    grpc::ClientContext context;
    return stub().StartSweep(&context, request, response);
  }

  grpc::Status GetSweep(const std::string& sweep_id, v1::SweepProgress* progress, int from = 0,
                        int max_runs = 0) {
    v1::GetSweepRequest request;
    request.set_sweep_id(sweep_id);
    request.set_runs_from(from);
    request.set_max_runs(max_runs);
    grpc::ClientContext context;
    return stub().GetSweep(&context, request, progress);
  }

  // Follows the sweep as a client does: each point's run, in point order, waited for
  // (GetResult wait). Returns the runs' final infos.
  std::vector<v1::RunInfo> Follow(const std::string& sweep_id) {
    std::vector<v1::RunInfo> ended;
    v1::SweepProgress page;
    for (;;) {
      EXPECT_TRUE(GetSweep(sweep_id, &page, static_cast<int>(ended.size()), 3).ok());
      if (page.run_ids_size() == 0) {
        if (static_cast<int>(ended.size()) >= page.total_points() || page.cancelled()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // not queued yet
        continue;
      }
      EXPECT_EQ(page.runs_from(), static_cast<int>(ended.size()));
      for (const std::string& id : page.run_ids()) {
        v1::RunInfo info;
        std::vector<v1::Frame> frames;
        std::vector<v1::ProbeReport> probes;
        EXPECT_TRUE(Result(id, &info, &frames, &probes, true, std::chrono::seconds(60)).ok());
        ended.push_back(info);
      }
    }
    return ended;
  }

  static int CountIn(const v1::SweepProgress& progress, v1::RunState state) {
    for (const v1::SweepStateCount& entry : progress.states()) {
      if (entry.state() == state) return entry.runs();
    }
    return 0;
  }
};

TEST_F(SweepServiceTest, TheServerFeedsTheWholeSweepAWindowAtATime) {
  const std::vector<std::string> durations = {"0.1", "0.2", "0.15", "0.05", "0.1", "0.12", "0.07"};
  v1::StartSweepResponse started;
  ASSERT_TRUE(Start(durations, 0, 2, &started).ok());
  const std::string id = started.sweep_id();
  EXPECT_EQ(started.total_points(), 7);
  EXPECT_EQ(started.next_point(), 7);  // an older client starts no slice of its own
  ASSERT_EQ(started.runs_size(), 2);   // the first window
  EXPECT_EQ(started.points(1).values(0), "0.2");

  const std::vector<v1::RunInfo> ended = Follow(id);
  ASSERT_EQ(ended.size(), durations.size());
  for (size_t k = 0; k < ended.size(); ++k) {
    EXPECT_EQ(ended[k].state(), v1::FINISHED) << k;
    EXPECT_EQ(ended[k].sweep_id(), id);
    EXPECT_EQ(ended[k].sweep_point(), static_cast<int>(k));
    EXPECT_EQ(ended[k].sweep_points(), 7);
    EXPECT_DOUBLE_EQ(ended[k].duration_s(), std::stod(durations[k]));
  }

  v1::SweepProgress progress;
  ASSERT_TRUE(GetSweep(id, &progress).ok());
  EXPECT_EQ(progress.total_points(), 7);
  EXPECT_EQ(progress.started_runs(), 7);
  EXPECT_EQ(progress.ended_runs(), 7);
  EXPECT_EQ(progress.window(), 2);
  EXPECT_EQ(CountIn(progress, v1::FINISHED), 7);
  EXPECT_EQ(progress.model_id(), started.runs(0).model_id());
  ASSERT_EQ(progress.run_ids_size(), 7);
  EXPECT_EQ(progress.run_ids(3), ended[3].id());  // in point order
  EXPECT_THAT(progress.paths(), ::testing::ElementsAre("duration_s"));
  ASSERT_EQ(progress.points_size(), 7);
  EXPECT_EQ(progress.points(3).values(0), "0.05");

  ASSERT_TRUE(GetSweep(id, &progress, 5, 1).ok());  // a page
  EXPECT_EQ(progress.runs_from(), 5);
  ASSERT_EQ(progress.run_ids_size(), 1);
  EXPECT_EQ(progress.run_ids(0), ended[5].id());
  EXPECT_EQ(progress.points(0).values(0), "0.12");

  const grpc::Status unknown = GetSweep("s-nosuch", &progress);
  EXPECT_EQ(unknown.error_code(), grpc::StatusCode::NOT_FOUND);
  EXPECT_THAT(unknown.error_message(), HasSubstr("s-nosuch"));
}

TEST_F(SweepServiceTest, CancellingASweepEndsItsRunsAndQueuesNoMorePoints) {
  // Paced at wall-clock speed: 20 s each unless cancelled; a window of 3 of 6 points.
  const std::vector<std::string> durations = {"20", "20", "20", "20", "20", "20"};
  v1::StartSweepResponse started;
  ASSERT_TRUE(Start(durations, 1.0, 3, &started).ok());
  const std::string id = started.sweep_id();
  v1::SweepProgress progress;
  ASSERT_TRUE(GetSweep(id, &progress).ok());
  EXPECT_EQ(progress.started_runs(), 3);  // the window holds the rest back
  EXPECT_EQ(CountIn(progress, v1::QUEUED) + CountIn(progress, v1::RUNNING), 3);

  v1::CancelSweepRequest request;
  request.set_sweep_id(id);
  {
    grpc::ClientContext context;
    const grpc::Status status = stub().CancelSweep(&context, request, &progress);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  EXPECT_TRUE(progress.cancelled());
  EXPECT_EQ(progress.started_runs(), 3);
  EXPECT_EQ(progress.ended_runs(), 3);  // it returns once its runs have ended
  EXPECT_EQ(CountIn(progress, v1::CANCELLED), 3);
  for (const v1::RunInfo& run : started.runs()) {
    EXPECT_EQ(WaitForEnd(run.id()).state(), v1::CANCELLED);
  }
  ASSERT_TRUE(GetSweep(id, &progress).ok());  // no point was queued after the cancel
  EXPECT_TRUE(progress.cancelled());
  EXPECT_EQ(progress.started_runs(), 3);
  EXPECT_EQ(progress.total_points(), 6);

  request.set_sweep_id("s-nosuch");
  grpc::ClientContext context;
  EXPECT_EQ(stub().CancelSweep(&context, request, &progress).error_code(),
            grpc::StatusCode::NOT_FOUND);
}

TEST_F(SweepServiceTest, APointTheModelRefusesIsAFailedRunOfTheSweep) {
  v1::StartSweepRequest request;
  request.set_model("irb1600");
  *request.mutable_base() = SceneSpec("seed-servo.json");
  request.mutable_base()->set_duration_s(0.05);
  request.add_list_paths("rtol");
  for (const char* rtol : {"1e-6", "1e-7", "-1", "1e-6"}) request.add_list()->add_values(rtol);
  request.set_window(2);  // point 2 is checked against the model only when it is queued
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    const grpc::Status status = stub().StartSweep(&context, request, &started);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  const std::vector<v1::RunInfo> ended = Follow(started.sweep_id());
  ASSERT_EQ(ended.size(), 4u);
  EXPECT_EQ(ended[1].state(), v1::FINISHED);
  EXPECT_EQ(ended[2].state(), v1::FAILED);
  EXPECT_THAT(ended[2].message(), HasSubstr("point 2 (rtol=-1)"));
  EXPECT_EQ(ended[3].state(), v1::FINISHED);

  // In the first window: the whole sweep is refused.
  request.set_window(4);
  grpc::ClientContext context;
  const grpc::Status refused = stub().StartSweep(&context, request, &started);
  EXPECT_EQ(refused.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_THAT(refused.error_message(), HasSubstr("point 2 (rtol=-1)"));
}

TEST_F(SweepServiceTest, AHundredThousandPointSweepQueuesOnlyItsWindow) {
  v1::StartSweepRequest request;
  request.set_model("irb1600");
  *request.mutable_base() = SceneSpec("seed-servo.json");
  request.mutable_base()->set_realtime(1.0);  // 20 s each: none ends during the test
  request.mutable_base()->set_keep("all");
  for (const auto& [path, count] : {std::pair<const char*, int>{"drives[1].pd_servo.kp", 1000},
                                    std::pair<const char*, int>{"drives[1].pd_servo.kd", 100}}) {
    v1::SweepAxis& axis = *request.add_grid();
    axis.set_path(path);
    for (int i = 1; i <= count; ++i) axis.add_values(std::to_string(i));
  }
  request.set_window(4);
  v1::StartSweepResponse started;
  {
    grpc::ClientContext context;
    const grpc::Status status = stub().StartSweep(&context, request, &started);
    ASSERT_TRUE(status.ok()) << status.error_message();
  }
  EXPECT_EQ(started.total_points(), 100'000);
  EXPECT_EQ(started.runs_size(), 4);
  v1::SweepProgress progress;
  ASSERT_TRUE(GetSweep(started.sweep_id(), &progress, 0, 10).ok());
  EXPECT_EQ(progress.total_points(), 100'000);
  EXPECT_EQ(progress.started_runs(), 4);  // the store holds 4 runs of it, not 100,000
  EXPECT_EQ(progress.run_ids_size(), 4);
  EXPECT_EQ(progress.points(3).values(1), "4");
  v1::CancelSweepRequest cancel;
  cancel.set_sweep_id(started.sweep_id());
  grpc::ClientContext context;
  ASSERT_TRUE(stub().CancelSweep(&context, cancel, &progress).ok());
  EXPECT_EQ(progress.started_runs(), 4);
  EXPECT_EQ(progress.ended_runs(), 4);
}

TEST_F(SweepServiceTest, ALaterSliceOfAnOlderClientIsRefused) {
  v1::StartSweepRequest request;
  request.set_model("irb1600");
  *request.mutable_base() = SceneSpec("seed-servo.json");
  v1::SweepAxis& axis = *request.add_grid();
  axis.set_path("duration_s");
  axis.add_values("0.05");
  request.set_first_point(1);
  request.set_sweep_id("s-old");
  v1::StartSweepResponse response;
  grpc::ClientContext context;
  const grpc::Status status = stub().StartSweep(&context, request, &response);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_THAT(status.error_message(), HasSubstr("feeds"));
}

TEST_F(SweepServiceTest, AServerStartedAgainGoesOnWithThePointsNotQueued) {
  // Paced, 1 s each, a window of 2 of 4: the server stops with 2 queued or running.
  const std::vector<std::string> durations = {"1", "1", "0.1", "0.1"};
  v1::StartSweepResponse started;
  ASSERT_TRUE(Start(durations, 1.0, 2, &started).ok());
  const std::string id = started.sweep_id();
  StartServer();  // the same data directory
  const std::vector<v1::RunInfo> ended = Follow(id);
  ASSERT_EQ(ended.size(), 4u);
  // A run the stopping server was integrating ends INTERRUPTED; one it had not started runs
  // after the restart; the points not queued are queued by the new server.
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(ended[k].state() == v1::INTERRUPTED || ended[k].state() == v1::FINISHED)
        << k << ": " << v1::RunState_Name(ended[k].state());
  }
  EXPECT_EQ(ended[2].state(), v1::FINISHED);
  EXPECT_EQ(ended[3].state(), v1::FINISHED);
}

}  // namespace
}  // namespace mbstream::testing
