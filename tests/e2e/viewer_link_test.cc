// Real server + real offscreen viewer (Xvfb) + CLI: the viewer answers every frame of a run
// with a probe equal to the server's TCP; its errors name what is wrong.
#include <gmock/gmock.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

std::vector<std::vector<std::string>> ReadCsv(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream cellstream(line);
    for (std::string cell; std::getline(cellstream, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

class ViewerLinkTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mbstream-e2e-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
    server_ = std::make_unique<ServerProcess>(MBSTREAM_SERVER, (dir_ / "data").string());
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(dir_);
  }
  CommandOutcome Cli(const std::string& args) {
    return RunCommand(std::string(MBSTREAM_CLI) + " --server " + server_->address() + " " + args);
  }
  std::string Viewer(const std::string& args) {
    return "xvfb-run -a " + std::string(MBSTREAM_VIEWER) + " --server " + server_->address() +
           " --offscreen --size 320x240 " + args;
  }
  fs::path dir_;
  std::unique_ptr<ServerProcess> server_;
};

TEST_F(ViewerLinkTest, EveryFrameGetsAProbeEqualToTheTcp) {
  const CommandOutcome started =
      Cli("run irb1600 --spec models/irb1600/seed-run.json --realtime 5");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  // --run: joins the run (possibly late), answers, exits when it ended.
  const CommandOutcome viewer = RunCommand(Viewer("--run " + run));
  ASSERT_EQ(viewer.exit_code, 0) << viewer.output;
  EXPECT_THAT(viewer.output, HasSubstr("showing scene 'IRB1600'"));
  const CommandOutcome result = Cli("result " + run + " --out " + (dir_ / "out").string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto tcp = ReadCsv(dir_ / "out" / "tcp.csv");
  const auto probes = ReadCsv(dir_ / "out" / "probes.csv");
  ASSERT_EQ(tcp.size(), 401u);
  ASSERT_FALSE(probes.empty());
  int64_t first_seq = std::stoll(probes.front()[0]);
  EXPECT_LT(first_seq, 20);  // joined within a second of the run's start
  for (const auto& probe : probes) {
    const auto& frame = tcp.at(std::stoul(probe[0]));
    EXPECT_EQ(probe[1], frame[0]);  // same simulated time
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(std::stod(probe[3 + i]), std::stod(frame[1 + i]), 1e-6) << "seq " << probe[0];
    }
    EXPECT_GE(std::stoll(probe[6]), 0);
  }
  // From the first answered frame on, none is missing.
  EXPECT_EQ(static_cast<int64_t>(probes.size()), 401 - first_seq);
}

TEST_F(ViewerLinkTest, SceneThatDoesNotFitTheModelIsAnErrorNamingBoth) {
  const CommandOutcome started = Cli("run single_pendulum --realtime 2");
  ASSERT_EQ(started.exit_code, 0) << started.output;
  const std::string run = started.output.substr(0, started.output.find('\n'));
  const CommandOutcome viewer =
      RunCommand(Viewer("--run " + run + " --scene models/irb1600/irb1600.scene"));
  EXPECT_EQ(viewer.exit_code, 1);
  EXPECT_THAT(viewer.output, HasSubstr("scene 'IRB1600' has 6 joints but model 'single_pendulum'"));
  EXPECT_THAT(viewer.output, HasSubstr("has 1"));
  Cli("cancel " + run);
}

TEST_F(ViewerLinkTest, UnknownRunIsAClearError) {
  const CommandOutcome viewer = RunCommand(Viewer("--run r-nosuch"));
  EXPECT_EQ(viewer.exit_code, 1);
  EXPECT_THAT(viewer.output, HasSubstr("no run 'r-nosuch'"));
}

TEST_F(ViewerLinkTest, WithoutADisplayItSaysToUseXvfb) {
  const CommandOutcome viewer = RunCommand("env -u DISPLAY " + std::string(MBSTREAM_VIEWER) +
                                           " --server " + server_->address() + " --follow");
  EXPECT_EQ(viewer.exit_code, 2);
  EXPECT_THAT(viewer.output, HasSubstr("xvfb-run"));
}

}  // namespace
}  // namespace mbstream::testing
