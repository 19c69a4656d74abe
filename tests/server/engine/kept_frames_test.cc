// Which frames a run keeps (RunSpec.keep) and its summary over all of them: the engine's
// SummarySink, checked on the IRB 1600's servo scene against the same run keeping every frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "server/drives/trajectory.h"
#include "server/engine/engine.h"
#include "server/engine/summary_sink.h"
#include "server/sim/frame_keep.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

FrameKeep Parsed(const std::string& text) {
  FrameKeep keep;
  std::string why;
  EXPECT_TRUE(ParseFrameKeep(text, &keep, &why)) << text << ": " << why;
  return keep;
}

TEST(FrameKeepTest, NamesParseAndCountTheKeptFrames) {
  for (const std::string name : {"all", "every:10", "final", "summary"}) {
    EXPECT_EQ(FrameKeepName(Parsed(name)), name);
  }
  EXPECT_EQ(FrameKeepName(Parsed("")), "all");
  EXPECT_EQ(FrameKeepName(Parsed("every:1")), "all");
  for (const std::string bad : {"every:0", "every:-3", "every:", "every:2x", "some", "ALL"}) {
    FrameKeep keep;
    std::string why;
    EXPECT_FALSE(ParseFrameKeep(bad, &keep, &why)) << bad;
    EXPECT_FALSE(why.empty()) << bad;
  }
  EXPECT_EQ(KeptFrameCount(Parsed("all"), 401), 401);
  EXPECT_EQ(KeptFrameCount(Parsed("every:10"), 401), 41);  // 0, 10, ..., 400
  EXPECT_EQ(KeptFrameCount(Parsed("every:10"), 405), 42);  // and 404, the last
  EXPECT_EQ(KeptFrameCount(Parsed("every:10"), 1), 1);
  EXPECT_EQ(KeptFrameCount(Parsed("final"), 401), 1);
  EXPECT_EQ(KeptFrameCount(Parsed("summary"), 401), 0);
  EXPECT_EQ(KeptFrameCount(Parsed("final"), 0), 0);
}

// Records what reaches it: the frames' times, as a sink that keeps every frame itself.
class TimesSink : public FrameSink {
 public:
  explicit TimesSink(bool keeps) : keeps_(keeps) {}
  void OnFrame(const RunResult& result, int frame) override {
    times.push_back(result.t[static_cast<size_t>(frame)]);
    q.push_back(result.q[static_cast<size_t>(frame * result.num_dofs)]);
  }
  bool KeepsFrames() const override { return keeps_; }
  std::vector<double> times, q;

 private:
  bool keeps_;
};

RunConfig ServoScene(const std::string& keep) {
  RunConfig config = Scene("seed-servo");
  config.duration = 2.0;  // 41 frames at 0.05 s
  config.keep = Parsed(keep);
  return config;
}

TEST(KeptFramesTest, EveryNthFrameAndTheLastAreTheSameBitsAsInTheFullRun) {
  const RunResult all = Simulate(Irb1600(), ServoScene("all"));
  ASSERT_EQ(all.num_frames(), 41);
  for (const bool streamed : {false, true}) {
    SCOPED_TRACE(streamed ? "a sink that keeps the frames" : "the frames in the result");
    RunConfig config = ServoScene("every:7");  // 0, 7, ..., 35 and 40
    TimesSink sink(streamed);
    const RunResult kept = Simulate(Irb1600(), config, &sink);
    const std::vector<int> expected = {0, 7, 14, 21, 28, 35, 40};
    ASSERT_EQ(sink.times.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_EQ(sink.times[i], all.t[static_cast<size_t>(expected[i])]);
      EXPECT_EQ(sink.q[i], all.q[static_cast<size_t>(expected[i] * all.num_dofs)]);
    }
    if (!streamed) {
      ASSERT_EQ(kept.num_frames(), 7);
      for (size_t i = 0; i < expected.size(); ++i) {
        const size_t n = static_cast<size_t>(all.num_dofs), k = static_cast<size_t>(expected[i]);
        EXPECT_TRUE(std::equal(kept.qd.begin() + i * n, kept.qd.begin() + (i + 1) * n,
                               all.qd.begin() + k * n));
        EXPECT_TRUE(std::equal(kept.tau.begin() + i * n, kept.tau.begin() + (i + 1) * n,
                               all.tau.begin() + k * n));
        EXPECT_EQ(kept.tcp[3 * i + 2], all.tcp[3 * k + 2]);
      }
    }
    EXPECT_EQ(kept.stats.summary.keep, "every:7");
    EXPECT_EQ(kept.stats.summary.frames_computed, 41);
    EXPECT_EQ(kept.stats.summary.frames_kept, 7);
    EXPECT_EQ(kept.stats.summary, [&] {
      RunSummary s = all.stats.summary;
      s.keep = "every:7";
      s.frames_kept = 7;
      return s;
    }()) << "the summary covers every frame computed, kept or not";
  }
}

TEST(KeptFramesTest, FinalAndSummaryKeepTheLastFrameOrNone) {
  const RunResult all = Simulate(Irb1600(), ServoScene("all"));
  TimesSink final_sink(true);
  const RunResult final_run = Simulate(Irb1600(), ServoScene("final"), &final_sink);
  ASSERT_EQ(final_sink.times.size(), 1u);
  EXPECT_EQ(final_sink.times[0], all.t.back());
  EXPECT_EQ(Simulate(Irb1600(), ServoScene("final")).num_frames(), 1);
  TimesSink none(true);
  const RunResult summary = Simulate(Irb1600(), ServoScene("summary"), &none);
  EXPECT_TRUE(none.times.empty());
  EXPECT_EQ(Simulate(Irb1600(), ServoScene("summary")).num_frames(), 0);
  EXPECT_EQ(summary.stats.summary.frames_computed, 41);
  EXPECT_EQ(summary.stats.summary.frames_kept, 0);
  EXPECT_EQ(final_run.stats.summary.frames_kept, 1);
}

// The summary's figures, computed again here from the full run's frames.
TEST(KeptFramesTest, TheSummaryHoldsTheFinalStateAndEachJointsEffortAndTracking) {
  const RunConfig config = ServoScene("summary");
  const RunResult all = Simulate(Irb1600(), ServoScene("all"));
  const RunSummary& s = Simulate(Irb1600(), config).stats.summary;
  const size_t n = static_cast<size_t>(all.num_dofs);
  const size_t last = static_cast<size_t>(all.num_frames() - 1);
  ASSERT_EQ(s.q_final.size(), n);
  ASSERT_EQ(s.joints.size(), n);
  EXPECT_EQ(s.t_final, all.t[last]);
  for (size_t j = 0; j < n; ++j) {
    SCOPED_TRACE("joint " + all.joint_names[j]);
    EXPECT_EQ(s.q_final[j], all.q[last * n + j]);
    EXPECT_EQ(s.qd_final[j], all.qd[last * n + j]);
    double peak = 0.0, squares = 0.0, tracking = 0.0;
    const TrajectoryEvaluator reference(config.drives[j].trajectory);
    for (size_t k = 0; k <= last; ++k) {
      peak = std::max(peak, std::abs(all.tau[k * n + j]));
      squares += all.tau[k * n + j] * all.tau[k * n + j];
      tracking = std::max(tracking, std::abs(reference.At(all.t[k]).q - all.q[k * n + j]));
    }
    EXPECT_EQ(s.joints[j].effort_peak, peak);
    EXPECT_DOUBLE_EQ(s.joints[j].effort_rms, std::sqrt(squares / (last + 1)));
    ASSERT_EQ(config.drives[j].kind, DriveConfig::Kind::kPdServo);
    EXPECT_EQ(s.joints[j].tracking_error_max, tracking);
    EXPECT_GT(tracking, 0.0) << "a servo lags its reference";
  }
}

TEST(KeptFramesTest, APassiveJointHasNoTrackingErrorAndARunWithoutEffortsNoEffort) {
  RunConfig config = ServoScene("summary");
  config.drives[2] = DriveConfig{};  // passive
  config.want_torques = false;
  const RunSummary& s = Simulate(Irb1600(), config).stats.summary;
  ASSERT_EQ(s.joints.size(), 6u);
  EXPECT_LT(s.joints[2].tracking_error_max, 0.0);
  EXPECT_GE(s.joints[1].tracking_error_max, 0.0);
  for (const JointSummary& joint : s.joints) {
    EXPECT_LT(joint.effort_peak, 0.0);
    EXPECT_LT(joint.effort_rms, 0.0);
  }
}

}  // namespace
}  // namespace mbstream
