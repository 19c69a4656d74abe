// `mbstream result RUN --mcap FILE` against a live server: the stored run (its frames, probe
// reports and stats) as MCAP, the links' poses from the model the server sends back, read by
// @mcap/core and compared bit for bit with the same run's results files.
#include <gmock/gmock.h>

#include <filesystem>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

class McapResultCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device random;
    dir_ = fs::temp_directory_path() / ("mbstream-mcap-cli-" + std::to_string(random()));
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
  std::string Out(const std::string& name) { return (dir_ / name).string(); }

  fs::path dir_;
  std::unique_ptr<ServerProcess> server_;
};

TEST_F(McapResultCliTest, StoredServoRunExportsWithEffortsBitForBit) {
  ASSERT_EQ(Cli("submit models/irb1600").exit_code, 0);
  const CommandOutcome run =
      Cli("run irb1600 --spec models/irb1600/seed-servo.json --duration 2 --watch --out " +
          Out("results"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string run_id = run.output.substr(0, run.output.find('\n'));

  const CommandOutcome result = Cli("result " + run_id + " --mcap " + Out("run.mcap") +
                                    " --mcap-compression lz4 --mcap-start 1795694400.25");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("MCAP in " + Out("run.mcap")));
  EXPECT_FALSE(fs::exists(Out("run.mcap") + ".tmp"));

  const CommandOutcome read =
      RunCommand("node tests/server/mcap/reader/read_mcap.js " + Out("run.mcap") + " " +
                 Out("results") + " 1795694400250000000 models/irb1600/irb1600.urdf tcp");
  ASSERT_EQ(read.exit_code, 0) << read.output;
  const nlohmann::json summary = nlohmann::json::parse(read.output);
  EXPECT_EQ(summary["frames"], 41);
  EXPECT_EQ(summary["compression"], "lz4");
  EXPECT_TRUE(summary["has_effort"].get<bool>());
  EXPECT_EQ(summary["tf"].size(), 6u);
  EXPECT_LT(summary["tcp_error_max_m"].get<double>(), 1e-12);
}

TEST_F(McapResultCliTest, NothingToWriteIsSaidBeforeAnyCall) {
  const CommandOutcome result = Cli("result r-none");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output,
              HasSubstr("nothing to write: give --out DIR (the results files), --mcap FILE, or "
                        "both"));
  const CommandOutcome bad = Cli("result r-none --mcap x.mcap --mcap-compression gzip");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("unknown MCAP compression \"gzip\": use zstd, lz4 or none"));
}

}  // namespace
}  // namespace mbstream::testing
