// The README kept true (issue 42, item 11): its by-hand command blocks run as written, from
// a fresh directory, against a fresh server on port 0 (the blocks' build/client/mbstream lines
// reach it through MBSTREAM_SERVER), and what the README shows is checked against what they
// print and write: the server's start-up lines, the seed run's end and files, the runs table,
// the stored result, and the sweep's table row by row.
#include <gmock/gmock.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/common/csv_rows.h"
#include "tests/common/server_process.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

// The README's ```sh blocks, each as its lines (a trailing backslash joins the next).
std::vector<std::vector<std::string>> ShellBlocks(const std::string& readme) {
  std::vector<std::vector<std::string>> blocks;
  std::istringstream in(readme);
  std::string line;
  bool inside = false;
  std::string pending;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      inside = !inside && line == "```sh";
      if (inside) blocks.emplace_back();
      continue;
    }
    if (!inside) continue;
    if (!line.empty() && line.back() == '\\') {
      pending += line.substr(0, line.size() - 1);
      continue;
    }
    blocks.back().push_back(pending + line);
    pending.clear();
  }
  return blocks;
}

// The command of a line, without its trailing "# comment".
std::string CommandOf(const std::string& line) {
  const size_t hash = line.find("  #");
  return hash == std::string::npos ? line : line.substr(0, hash);
}

class ReadmeDocTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::temp_directory_path() / ("mbstream-readme-" + std::to_string(std::random_device()()));
    fs::create_directories(dir_);
    fs::create_directory_symlink(fs::path(MBSTREAM_SOURCE_DIR) / "models", dir_ / "models");
    // build/client/mbstream as the README writes it, from the test's folder.
    fs::create_directories(dir_ / "build" / "client");
    fs::create_symlink(MBSTREAM_CLI, dir_ / "build" / "client" / "mbstream");
    std::ifstream file(fs::path(MBSTREAM_SOURCE_DIR) / "README.md");
    std::stringstream text;
    text << file.rdbuf();
    readme_ = text.str();
    server_ = std::make_unique<testing::ServerProcess>(MBSTREAM_SERVER, (dir_ / "data").string());
  }
  void TearDown() override {
    server_.reset();
    fs::remove_all(dir_);
  }
  // Runs a README line in the test's folder against the test's server.
  testing::CommandOutcome Run(const std::string& command) {
    return testing::RunCommand("cd " + dir_.string() + " && MBSTREAM_SERVER=" + server_->address() +
                               " " + command + " 2>&1");
  }
  // The block holding a line that starts with `start`.
  std::vector<std::string> BlockWith(const std::string& start) {
    for (const auto& block : ShellBlocks(readme_)) {
      for (const std::string& line : block) {
        if (line.rfind(start, 0) == 0) return block;
      }
    }
    ADD_FAILURE() << "README.md has no block with a line starting " << start;
    return {};
  }

  fs::path dir_;
  std::string readme_;
  std::unique_ptr<testing::ServerProcess> server_;
};

TEST_F(ReadmeDocTest, TheByHandBlockRunsAsWritten) {
  const std::vector<std::string> block = BlockWith("build/server/app/mbstream-server");
  ASSERT_FALSE(block.empty());
  // The start-up lines shown: the models listed (built-ins compiled when first asked for),
  // then "listening".
  const std::string log = testing::ReadTextFile(server_->log_path());
  EXPECT_THAT(log, HasSubstr("0 stored and 10 built-in models listed (each compiled when first "
                             "asked for)"));
  EXPECT_THAT(log, HasSubstr("listening on " + server_->address()));
  std::string run_id;
  int ran = 0;
  for (size_t i = 0; i < block.size(); ++i) {
    const std::string& line = block[i];
    if (line.rfind("build/client/mbstream ", 0) != 0) continue;
    std::string command = CommandOf(line);
    // The seed run as written, paced at real time (20 s); the README shows its progress line.
    if (command.find(" run irb1600 ") != std::string::npos) {
      const testing::CommandOutcome run = Run(command);
      ++ran;
      EXPECT_EQ(run.exit_code, 0) << command << "\n" << run.output;
      run_id = run.output.substr(0, run.output.find('\n'));
      EXPECT_TRUE(std::regex_match(run_id, std::regex("r-[0-9]{8}-[0-9]{6}-[0-9a-f]{8}")))
          << run_id;
      // The README's example line has the same shape.
      const std::string shown = i + 1 < block.size() ? block[i + 1] : "";
      EXPECT_TRUE(std::regex_search(
          shown, std::regex("# r-[0-9]{8}-[0-9]{6}-[0-9a-f]{8} RUNNING t = 10.000/20.000 s  50.0%  "
                            "1x real time  ETA 10.0 s")))
          << shown;
      EXPECT_THAT(run.output, HasSubstr("1x real time"));
      EXPECT_THAT(run.output, HasSubstr("FINISHED: 401 frames to t = 20 s"));
      EXPECT_THAT(run.output, HasSubstr("trust: ok"));
      EXPECT_TRUE(fs::exists(dir_ / "out/seed/tcp.csv"));
      continue;
    }
    if (command.find("RUN_ID") != std::string::npos) {
      ASSERT_FALSE(run_id.empty());
      command.replace(command.find("RUN_ID"), 6, run_id);
    }
    const testing::CommandOutcome outcome = Run(command);
    ++ran;
    EXPECT_EQ(outcome.exit_code, 0) << command << "\n" << outcome.output;
    if (command.find(" runs") != std::string::npos) {
      // The run's id fits the table's ID column: a space after it, its model next.
      EXPECT_TRUE(std::regex_search(outcome.output,
                                    std::regex("\n" + run_id + " +irb1600 +FINISHED +20.000 +401")))
          << outcome.output;
    }
  }
  EXPECT_EQ(ran, 3) << "the run, runs and result lines";
  EXPECT_TRUE(fs::exists(dir_ / "out/again/tcp.csv"));
}

// The sweep block as written, and its table in the README against the sweep.csv it writes.
TEST_F(ReadmeDocTest, TheSweepTableIsWhatTheSweepWrites) {
  const std::vector<std::string> block = BlockWith("build/client/mbstream sweep irb1600");
  ASSERT_EQ(block.size(), 1u);
  const testing::CommandOutcome sweep = Run(CommandOf(block[0]));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  const auto rows = testing::ReadCsv(dir_ / "gains" / "sweep.csv");
  ASSERT_EQ(rows.size(), 9u);  // ReadCsv skips the header
  std::ifstream csv(dir_ / "gains" / "sweep.csv");
  std::string header;
  std::getline(csv, header);
  std::map<std::string, size_t> column;
  {
    std::istringstream names(header);
    std::string name;
    for (size_t k = 0; std::getline(names, name, ','); ++k) column[name] = k;
  }
  // The README's rows: | kp | kd | state | tracking_error_max:joint2 | effort_peak:joint2 |
  const std::regex row("\\| ([0-9]+) \\| ([0-9]+) \\| ([A-Z_]+) \\| ([0-9.]+) \\| ([0-9.]+) \\|");
  int checked = 0;
  for (auto it = std::sregex_iterator(readme_.begin(), readme_.end(), row);
       it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    bool found = false;
    for (const auto& r : rows) {
      if (r[column.at("drives[1].pd_servo.kp")] != m[1] ||
          r[column.at("drives[1].pd_servo.kd")] != m[2]) {
        continue;
      }
      found = true;
      EXPECT_EQ(r[column.at("state")], m[3]);
      const double error = std::stod(r[column.at("tracking_error_max:joint2")]);
      const double peak = std::stod(r[column.at("effort_peak:joint2")]);
      EXPECT_NEAR(error, std::stod(m[4]), 0.0006) << "kp " << m[1] << " kd " << m[2];
      EXPECT_NEAR(peak, std::stod(m[5]), 0.6) << "kp " << m[1] << " kd " << m[2];
    }
    EXPECT_TRUE(found) << "no sweep row for kp " << m[1] << " kd " << m[2];
    ++checked;
  }
  EXPECT_EQ(checked, 9);
}

}  // namespace
}  // namespace mbstream
