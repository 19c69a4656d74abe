// A contact run's results (docs/contact.md): contacts.csv, one row per contact per output
// frame, byte-identical from the whole result and from the stream writer of `mbstream
// simulate`; stats.json's largest penetration and peak contact count.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "server/engine/engine.h"
#include "server/model/model_builder.h"
#include "server/parse/sdf_import.h"
#include "server/results/results_files.h"
#include "server/results/results_stream.h"
#include "server/sim/run_validation.h"

namespace mbstream {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

class ContactResultsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mbstream-contact-" + std::to_string(getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ContactResultsTest, ContactsCsvAndSummaryFromBothWriters) {
  const Model model =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/box_on_plane.sdf")
          .model;
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.duration = 0.5;
  config.output_interval = 0.1;
  config.drives.resize(static_cast<size_t>(model.nv()));
  config.contact.dissipation = 20.0;
  ValidateRun(model, config);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.contacts.active);
  EXPECT_EQ(result.contacts.count_peak, 4);  // the box's bottom corners
  EXPECT_GT(result.contacts.depth_max, 0.0);
  // Frames 0.1 .. 0.5 s (at t = 0 the box just touches: no overlap, no contact).
  ASSERT_EQ(result.contacts.records.size(), 4u * 5);

  WriteResultsDirectory(result, {"box_on_plane", "box_on_plane.sdf", "", "", ""},
                        (dir_ / "whole").string());
  const std::string csv = Read(dir_ / "whole" / "contacts.csv");
  std::istringstream lines(csv);
  std::string header, row;
  std::getline(lines, header);
  EXPECT_EQ(header,
            "t,link_a,collision_a,link_b,collision_b,px,py,pz,nx,ny,nz,depth,normal_force,"
            "friction_x,friction_y,friction_z");
  std::getline(lines, row);
  EXPECT_EQ(row.rfind("0.1,ground::floor,plane,box::body,cube,-0.1,-0.1,", 0), 0u) << row;
  const std::string stats = Read(dir_ / "whole" / "stats.json");
  EXPECT_NE(stats.find("\"penetration_max_m\""), std::string::npos);
  EXPECT_NE(stats.find("\"contacts_peak\": 4"), std::string::npos) << stats;

  ResultsStreamWriter writer((dir_ / "stream").string());
  const RunResult streamed = Simulate(model, config, &writer);
  writer.Finish(streamed, {"box_on_plane", "box_on_plane.sdf", "", "", ""});
  EXPECT_EQ(Read(dir_ / "stream" / "contacts.csv"), csv);
  EXPECT_TRUE(streamed.contacts.active);
  EXPECT_NE(Read(dir_ / "stream" / "stats.json").find("\"contacts_peak\": 4"), std::string::npos);
}

// Formulation body-baumgarte (server/body/body_contact.h) logs its frames' contacts as the
// joint formulation does: the pendulum's tip on the floor, in both writers, byte for byte.
TEST_F(ContactResultsTest, BodyBaumgarteWritesItsContactsFromBothWriters) {
  const Model model =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/pendulum_on_floor.sdf")
          .model;
  RunConfig config;
  config.formulation = Formulation::kBodyBaumgarte;
  config.duration = 1.0;
  config.output_interval = 0.05;
  config.drives.resize(static_cast<size_t>(model.nv()));
  config.contact.dissipation = 2.0;
  ValidateRun(model, config);
  const RunResult result = Simulate(model, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.contacts.active);
  EXPECT_EQ(result.contacts.count_peak, 1);
  ASSERT_FALSE(result.contacts.records.empty());
  WriteResultsDirectory(result, {"pendulum_on_floor", "pendulum_on_floor.sdf", "", "", ""},
                        (dir_ / "whole").string());
  const std::string csv = Read(dir_ / "whole" / "contacts.csv");
  EXPECT_NE(csv.find(",ground::floor,plane,pendulum::arm,tip,"), std::string::npos) << csv;
  EXPECT_NE(Read(dir_ / "whole" / "stats.json").find("\"dissipated_work_j\""), std::string::npos);

  ResultsStreamWriter writer((dir_ / "stream").string());
  const RunResult streamed = Simulate(model, config, &writer);
  writer.Finish(streamed, {"pendulum_on_floor", "pendulum_on_floor.sdf", "", "", ""});
  EXPECT_EQ(Read(dir_ / "stream" / "contacts.csv"), csv);
}

TEST_F(ContactResultsTest, NoContactsCsvWithoutGeometry) {
  ModelBuilder builder("pendulum", "world");
  Joint joint;
  joint.name = "j";
  RigidInertia inertia;
  inertia.mass = 1.0;
  inertia.com = Vector3d(0, 0, -0.5);
  inertia.inertia_com = Matrix3d::Identity() * 0.01;
  builder.AddMovingLink("bob", "world", joint, inertia);
  const Model model = builder.Build();
  RunConfig config;
  config.duration = 0.2;
  config.output_interval = 0.1;
  config.drives.resize(1);
  const RunResult result = Simulate(model, config);
  EXPECT_FALSE(result.contacts.active);
  WriteResultsDirectory(result, {"pendulum", "", "", "", ""}, dir_.string());
  EXPECT_FALSE(fs::exists(dir_ / "contacts.csv"));
  EXPECT_EQ(Read(dir_ / "stats.json").find("penetration_max_m"), std::string::npos);
}

}  // namespace
}  // namespace mbstream
