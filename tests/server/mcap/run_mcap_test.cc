// RunMcapWriter's topics as bytes (uncompressed): the probe reports and stats as JSON
// messages; --mcap-start's forms and its error.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "server/mcap/run_mcap.h"
#include "shared/common/check.h"
#include "tests/common/test_models.h"

namespace mbstream::mcap {
namespace {

TEST(RunMcapTest, StartTimeAsUtcOrEpochSeconds) {
  EXPECT_EQ(ParseStartTime("2026-11-26T12:00:00.25Z", "--mcap-start"), 1795694400250000000ull);
  EXPECT_EQ(ParseStartTime("1795694400.25", "--mcap-start"), 1795694400250000000ull);
  EXPECT_EQ(ParseStartTime("1970-01-01T00:00:00Z", "--mcap-start"), 0ull);
  for (const char* bad : {"2026-11-26T12:00:00", "2026-13-01T00:00:00Z", "2026-02-30T00:00:00Z",
                          "2040-01-01T00:00:00Z", "3e9", "-1", "", "now"}) {
    try {
      ParseStartTime(bad, "--mcap-start");
      ADD_FAILURE() << bad << ": no error";
    } catch (const InputError& error) {
      EXPECT_EQ(
          std::string(error.what()),
          "--mcap-start \"" + std::string(bad) +
              "\": give a UTC time as 2026-11-26T12:00:00Z (fractions of a second "
              "allowed) or seconds since the Unix epoch (1970 to 2038, ROS 2's int32 stamps)");
    }
  }
}

TEST(RunMcapTest, ProbesAndStatsAreJsonMessages) {
  const Model model = testing::SinglePendulum(1.0, 0.5, 0.01);
  const auto path = std::filesystem::temp_directory_path() /
                    ("mbstream_run_mcap-" + std::to_string(getpid()) + ".mcap");
  RunResult result;
  result.num_dofs = 1;
  result.joint_names = {"joint1"};
  result.t = {0.5};
  result.q = {0.25};
  result.qd = {-1.0};
  {
    RunMcapWriter writer(path.string(), model, "<robot name=\"p\"/>",
                         {.compression = Compression::kNone, .start_time_ns = 1000000000});
    writer.OnFrame(result, 0);
    writer.Finish({ProbeRecord{7, 0.5, "tip", 0.1, 0.2, 0.3, 12}}, "{\"status\": \"FINISHED\"}",
                  0.5);
    EXPECT_EQ(writer.frames(), 1);
  }
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  std::filesystem::remove(path);
  const std::string file = bytes.str();
  EXPECT_NE(file.find(R"({"latency_us":12,"name":"tip","seq":7,"t":0.5,"x":0.1,"y":0.2,"z":0.3})"),
            std::string::npos);
  EXPECT_NE(file.find("{\"status\": \"FINISHED\"}"), std::string::npos);
  EXPECT_NE(file.find("<robot name=\"p\"/>"), std::string::npos);
  EXPECT_NE(file.find("/mbstream/probes"), std::string::npos);
  EXPECT_NE(file.find("sensor_msgs/msg/JointState"), std::string::npos);
}

}  // namespace
}  // namespace mbstream::mcap
