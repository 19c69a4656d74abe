// `mbstream simulate` of SDFormat linkages with closed loops, as a user runs it: a real
// process, the shipped models and specs, the results files and the summary line.
#include <gtest/gtest.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Runs simulate on models/linkages/MODEL.sdf with SPEC.json; returns the exit code.
int Simulate(const std::string& model, const std::string& spec, const fs::path& out) {
  fs::remove_all(out);
  const std::string command = std::string(MBSTREAM_CLI) + " simulate models/linkages/" + model +
                              ".sdf --spec models/linkages/" + spec + ".json --out " +
                              out.string() + " > " + out.string() + ".log 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path OutDir(const std::string& name) {
  return fs::temp_directory_path() / ("mbstream_loops_" + name + "-" + std::to_string(getpid()));
}

TEST(SimulateLoopsCliTest, DrivenFourBarIsKinematicWithItsLoopReported) {
  const fs::path out = OutDir("four_bar");
  ASSERT_EQ(Simulate("four_bar", "four_bar-driven", out), 0) << Read(out.string() + ".log");
  const nlohmann::json stats = nlohmann::json::parse(Read(out / "stats.json"));
  EXPECT_EQ(stats["formulation"], "kinematic");
  EXPECT_EQ(stats["loops"]["cut_joints"], nlohmann::json::array({"loop_joint (revolute)"}));
  EXPECT_EQ(stats["loops"]["equations"], 5);
  EXPECT_EQ(stats["loops"]["redundant"], 3);
  EXPECT_EQ(stats["loops"]["mobility"], 1);
  EXPECT_LT(stats["loops"]["position_residual_max_m"].get<double>(), 1e-12);
  EXPECT_EQ(stats["trust"], "ok");
  std::ifstream joints(out / "joints.csv");
  std::string header;
  std::getline(joints, header);
  EXPECT_EQ(header, "t,crank_joint,rocker_joint,coupler_joint,loop_joint");  // the cut joint last
  EXPECT_TRUE(fs::exists(out / "torques.csv"));
  EXPECT_NE(Read(out.string() + ".log").find("loop residual"), std::string::npos);
}

TEST(SimulateLoopsCliTest, PassiveSliderCrankKeepsItsEnergyAndLoop) {
  const fs::path out = OutDir("slider_crank");
  ASSERT_EQ(Simulate("slider_crank", "slider_crank-passive", out), 0)
      << Read(out.string() + ".log");
  const nlohmann::json stats = nlohmann::json::parse(Read(out / "stats.json"));
  EXPECT_EQ(stats["formulation"], "joint");
  EXPECT_EQ(stats["integrator"], "CVODE BDF with projection");
  EXPECT_LT(stats["accuracy"]["energy_error_max_rel"].get<double>(), 1e-6);
  EXPECT_LT(stats["accuracy"]["drift_position_max_m"].get<double>(), 1e-10);
}

}  // namespace
