// The streamed results directory (`mbstream simulate`) is byte for byte the one written
// from a whole result, while it only ever sees the latest frame.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "server/results/results_files.h"
#include "server/results/results_stream.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

// A two-joint result of `frames` frames with torques and energies, values unlike each other.
RunResult WholeResult(int frames) {
  RunResult result;
  result.num_dofs = 2;
  result.joint_names = {"shoulder", "el,bow"};  // a name CSV must quote
  result.has_torques = true;
  result.has_energy = true;
  for (int k = 0; k < frames; ++k) {
    const double t = 0.05 * k;
    result.t.push_back(t);
    for (int j = 0; j < 2; ++j) {
      result.q.push_back(1.0 / (3.0 + k + j));
      result.qd.push_back(-0.1 * k * (j + 1));
      result.tau.push_back(1e-300 * (k + j));
    }
    for (int axis = 0; axis < 3; ++axis) result.tcp.push_back(t * (axis + 0.5));
    result.kinetic.push_back(0.5 * k);
    result.potential.push_back(-9.81 * k);
  }
  result.stats.t_reached = 0.05 * (frames - 1);
  return result;
}

// Frame k of `whole` as the only frame of a result (what Simulate hands a sink that keeps
// the frames itself).
RunResult LatestOnly(const RunResult& whole, int k) {
  RunResult latest = whole;
  const auto pick = [k](std::vector<double>& v, int width) {
    v = std::vector<double>(v.begin() + k * width, v.begin() + (k + 1) * width);
  };
  pick(latest.t, 1);
  pick(latest.q, 2);
  pick(latest.qd, 2);
  pick(latest.tau, 2);
  pick(latest.tcp, 3);
  pick(latest.kinetic, 1);
  pick(latest.potential, 1);
  latest.first_seq = k;
  return latest;
}

class ResultsStreamTest : public ::testing::Test {
 protected:
  void SetUp() override {
    base_ = fs::temp_directory_path() / ("mbstream-stream-test-" + std::to_string(::getpid()));
    fs::remove_all(base_);
  }
  void TearDown() override { fs::remove_all(base_); }
  std::string Read(const std::string& dir, const std::string& file) {
    return testing::ReadTextFile((base_ / dir / file).string());
  }
  fs::path base_;
};

TEST_F(ResultsStreamTest, StreamedFilesAreTheWholeResultsByteForByte) {
  const RunResult whole = WholeResult(25);
  const RunProvenance provenance{"arm", "arm.urdf", "", "", ""};
  WriteResultsDirectory(whole, provenance, (base_ / "whole").string());

  ResultsStreamWriter writer((base_ / "streamed").string());
  RunResult latest;
  for (int k = 0; k < whole.num_frames(); ++k) {
    latest = LatestOnly(whole, k);
    writer.OnFrame(latest, 0);
    // Nothing is in place before Finish: a reader never sees a half-written file.
    EXPECT_FALSE(fs::exists(base_ / "streamed" / "joints.csv"));
  }
  EXPECT_EQ(writer.frames(), 25);
  writer.Finish(latest, provenance);
  for (const char* file :
       {"joints.csv", "velocities.csv", "tcp.csv", "torques.csv", "energy.csv"}) {
    SCOPED_TRACE(file);
    EXPECT_FALSE(Read("whole", file).empty());
    EXPECT_EQ(Read("streamed", file), Read("whole", file));
  }
  EXPECT_NE(Read("streamed", "stats.json").find("\"frames\": 25"), std::string::npos);
  EXPECT_FALSE(fs::exists(base_ / "streamed" / "joints.csv.tmp"));
}

TEST_F(ResultsStreamTest, ARunWithoutFramesGetsHeaderOnlyFilesAndNoStaleOnes) {
  fs::create_directories(base_ / "empty");
  testing::RunCommand("echo stale > " + (base_ / "empty" / "torques.csv").string());
  RunResult none = WholeResult(0);
  none.has_torques = false;
  ResultsStreamWriter writer((base_ / "empty").string());
  writer.Finish(none, RunProvenance{"arm", "arm.urdf", "", "", ""});
  EXPECT_EQ(Read("empty", "joints.csv"), "t,shoulder,\"el,bow\"\n");
  EXPECT_FALSE(fs::exists(base_ / "empty" / "torques.csv"));
  EXPECT_NE(Read("empty", "stats.json").find("\"frames\": 0"), std::string::npos);
}

}  // namespace
}  // namespace mbstream
