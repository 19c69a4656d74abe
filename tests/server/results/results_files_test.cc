// The results directory's CSV numbers: each reads back as the very double that was written,
// in its shortest such form (0.1 as "0.1", not printf's "0.10000000000000001").
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "server/results/results_files.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

// The cells of a CSV without quoted fields, header row first.
std::vector<std::vector<std::string>> Cells(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::vector<std::string>& row = rows.emplace_back();
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) row.push_back(cell);
  }
  return rows;
}

class ResultsFilesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ =
        fs::temp_directory_path() / ("mbstream-results-test-" + std::to_string(::getpid()));
    fs::remove_all(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path directory_;
};

TEST_F(ResultsFilesTest, EveryNumberReadsBackAsTheSameDoubleInItsShortestForm) {
  const std::vector<double> values = {0.1,
                                      1.0 / 3.0,
                                      -0.0,
                                      20.0,
                                      -2.5e-310,  // subnormal
                                      std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::min(),
                                      std::nextafter(1.0, 2.0),
                                      -123456789.01234567,
                                      6.02214076e23};
  RunResult result;
  result.num_dofs = 1;
  result.joint_names = {"j1"};
  for (size_t k = 0; k < values.size(); ++k) {
    result.t.push_back(0.05 * static_cast<double>(k));
    result.q.push_back(values[k]);
    result.qd.push_back(-values[k]);
    for (int axis = 0; axis < 3; ++axis) result.tcp.push_back(values[k] * (axis + 1));
  }
  WriteResultsDirectory(result, RunProvenance{"arm", "arm.urdf", "", "", ""}, directory_);

  const auto joints = Cells(testing::ReadTextFile((directory_ / "joints.csv").string()));
  ASSERT_EQ(joints.size(), values.size() + 1);
  EXPECT_EQ(joints[0], (std::vector<std::string>{"t", "j1"}));
  for (size_t k = 0; k < values.size(); ++k) {
    ASSERT_EQ(joints[k + 1].size(), 2u) << "row " << k + 1;
    const double q = std::strtod(joints[k + 1][1].c_str(), nullptr);
    EXPECT_EQ(std::signbit(q), std::signbit(values[k])) << joints[k + 1][1];
    EXPECT_EQ(q, values[k]) << joints[k + 1][1];
    EXPECT_EQ(std::strtod(joints[k + 1][0].c_str(), nullptr), result.t[k]);
  }
  EXPECT_EQ(joints[1][1], "0.1");
  EXPECT_EQ(joints[3][1], "-0");
  EXPECT_EQ(joints[4][1], "20");
  EXPECT_EQ(joints[2][0], "0.05");

  const auto tcp = Cells(testing::ReadTextFile((directory_ / "tcp.csv").string()));
  ASSERT_EQ(tcp.size(), values.size() + 1);
  for (size_t k = 0; k < values.size(); ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(std::strtod(tcp[k + 1][1 + axis].c_str(), nullptr), result.tcp[3 * k + axis]);
    }
  }
  EXPECT_FALSE(fs::exists(directory_ / "torques.csv"));
  EXPECT_TRUE(fs::exists(directory_ / "stats.json"));
}

}  // namespace
}  // namespace mbstream
