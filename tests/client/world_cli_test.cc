// An SDFormat world as a user runs it (issue 43, docs/worlds.md): models/worlds/irb1600_table/
// through `mbstream simulate` and through a live server (`mbstream submit` of the world's
// folder, which sends the included models written into the world, then `run`): the three
// boxes fall freely, each centre of mass on its parabola, orientation kept; both give the
// same files.
#include <gmock/gmock.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>

#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr char kWorld[] = "models/worlds/irb1600_table/world.sdf";
constexpr char kSpec[] = "models/worlds/irb1600_table/boxes-fall.json";
constexpr double kG = 9.81;  // m/s^2, the spec's

struct Box {
  std::string name;
  double x, y, z;         // m, the <include>'s pose
  double qw, qx, qy, qz;  // its rotation
};

std::vector<Box> Boxes() {
  const double b = 0.25, c = 0.15;  // half the yaw of box_b, half the roll of box_c
  return {{"box_a::link", 1.0, -0.15, 0.9, 1, 0, 0, 0},
          {"box_b::link", 1.1, 0.1, 1.0, std::cos(b), 0, 0, std::sin(b)},
          {"box_c::link", 1.25, -0.05, 1.1, std::cos(c), std::sin(c), 0, 0}};
}

std::vector<std::string> Header(const fs::path& csv) {
  std::vector<std::string> names;
  std::stringstream line(FirstLine(ReadFile(csv)));
  for (std::string name; std::getline(line, name, ',');) names.push_back(name);
  return names;
}

// The largest distance of a box's centre of mass from its parabola over the run (m), and the
// largest change of its quaternion's components.
struct Deviation {
  double position_m = 0, quaternion = 0;
};

Deviation FallDeviation(const fs::path& out, const Box& box) {
  const std::vector<std::string> names = Header(out / "joints.csv");
  std::map<std::string, size_t> column;
  for (size_t k = 0; k < names.size(); ++k) column[names[k]] = k;
  const std::vector<std::vector<std::string>> rows = ReadCsv(out / "joints.csv");
  EXPECT_GT(rows.size(), 10u);
  Deviation deviation;
  for (const auto& row : rows) {
    const auto value = [&](const char* suffix) {
      return std::stod(row.at(column.at(box.name + suffix)));
    };
    const double t = std::stod(row[0]);
    const double dz = value(".z") - (box.z - 0.5 * kG * t * t);
    deviation.position_m =
        std::max(deviation.position_m, std::hypot(value(".x") - box.x, value(".y") - box.y, dz));
    for (const auto& [suffix, expected] : std::map<const char*, double>{
             {".qw", box.qw}, {".qx", box.qx}, {".qy", box.qy}, {".qz", box.qz}}) {
      deviation.quaternion = std::max(deviation.quaternion, std::abs(value(suffix) - expected));
    }
  }
  return deviation;
}

class WorldCliTest : public CliServerTest {};

TEST_F(WorldCliTest, SimulatedBoxesFallOnTheirParabolas) {
  const CommandOutcome run = RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kWorld +
                                        " --spec " + kSpec + " --out " + Out("local"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<std::string> names = Header(dir_ / "local" / "joints.csv");
  ASSERT_GE(names.size(), 1u + 6 + 21) << FirstLine(ReadFile(dir_ / "local" / "joints.csv"));
  EXPECT_EQ(names[1], "irb1600::joint1");
  EXPECT_EQ(names[7], "box_a::link.x");
  EXPECT_EQ(names[13], "box_a::link.qz");
  for (const Box& box : Boxes()) {
    const Deviation deviation = FallDeviation(dir_ / "local", box);
    std::cout << box.name << ": centre of mass off its parabola by at most " << deviation.position_m
              << " m, quaternion changed by at most " << deviation.quaternion << "\n";
    EXPECT_LT(deviation.position_m, 1e-8) << box.name;
    EXPECT_LT(deviation.quaternion, 1e-10) << box.name;
  }
}

// The server's run of the world finishes and its results, downloaded (`run --out`), name the
// free bodies' seven coordinates (RunInfo.num_positions, position_names) and hold the same
// falls as the simulation in the CLI.
TEST_F(WorldCliTest, TheWorldsFolderIsSubmittedWithItsModelsAndRuns) {
  StartServer();
  const CommandOutcome submit = Cli("submit models/worlds/irb1600_table --name irb1600_table");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("model 'irb1600_table'"));
  EXPECT_THAT(submit.output, HasSubstr("253 kg"));  // the robot's 250 kg and three boxes
  EXPECT_THAT(submit.output, HasSubstr("TCP irb1600::tcp"));
  const CommandOutcome model = Cli("models");
  EXPECT_THAT(model.output, HasSubstr("irb1600_table"));
  const CommandOutcome run =
      Cli(std::string("run irb1600_table --spec ") + kSpec + " --watch --out " + Out("served"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, HasSubstr("FINISHED t = 0.400/0.400 s"));
  const std::vector<std::string> names = Header(dir_ / "served" / "joints.csv");
  ASSERT_EQ(names.size(), 1u + 6 + 21) << FirstLine(ReadFile(dir_ / "served" / "joints.csv"));
  EXPECT_EQ(names[7], "box_a::link.x");
  EXPECT_EQ(Header(dir_ / "served" / "velocities.csv").size(), 1u + 6 + 18);
  for (const Box& box : Boxes()) {
    const Deviation deviation = FallDeviation(dir_ / "served", box);
    EXPECT_LT(deviation.position_m, 1e-8) << box.name;
    EXPECT_LT(deviation.quaternion, 1e-10) << box.name;
  }
  // The same world as a file: its includes found beside it, the same model id.
  const CommandOutcome again = Cli(std::string("submit ") + kWorld + " --name irb1600_table");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(FirstLine(again.output), FirstLine(submit.output));
}

// A world whose included models are drawn from mesh files (tests/data/worlds/mesh_world/):
// its folder is submitted with the three meshes attached (STL, OBJ and Collada, named
// relative to their model.sdf or by model://, docs/worlds.md), none missing, and the server
// runs it: the free crate falls on its parabola, the post's hinge stays where it is.
TEST_F(WorldCliTest, AWorldOfMeshedModelsIsSubmittedWithItsMeshesAndRuns) {
  StartServer();
  const CommandOutcome submit = Cli("submit tests/data/worlds/mesh_world --name mesh_world");
  ASSERT_EQ(submit.exit_code, 0) << submit.output;
  EXPECT_THAT(submit.output, HasSubstr("model 'mesh_world'"));
  EXPECT_THAT(submit.output, HasSubstr("3 assets"));
  EXPECT_THAT(submit.output, ::testing::Not(HasSubstr("not found")));
  const CommandOutcome run =
      Cli("run mesh_world --duration 0.3 --output-interval 0.05 --watch --out " + Out("meshes"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<std::string> names = Header(dir_ / "meshes" / "joints.csv");
  ASSERT_EQ(names, (std::vector<std::string>{"t", "post::hinge", "crate::body.x", "crate::body.y",
                                             "crate::body.z", "crate::body.qw", "crate::body.qx",
                                             "crate::body.qy", "crate::body.qz"}));
  const std::vector<std::vector<std::string>> rows = ReadCsv(dir_ / "meshes" / "joints.csv");
  ASSERT_EQ(rows.size(), 7u);
  for (const auto& row : rows) {
    const double t = std::stod(row[0]);
    EXPECT_NEAR(std::stod(row[1]), 0.0, 1e-12) << "t = " << t;
    EXPECT_NEAR(std::stod(row[4]), 0.5 - 0.5 * kG * t * t, 1e-5) << "t = " << t;
  }
}

// A thrown box through a live server: the spec's initial_q has the model's 27 position
// coordinates (a free joint's 7 each) and initial_qd its 24 velocities; box_a leaves at
// 1 m/s along x (world frame) spinning at 2 rad/s about its own z axis.
TEST_F(WorldCliTest, AServedRunTakesEachFreeBodysPoseAndTwist) {
  StartServer();
  ASSERT_EQ(Cli("submit models/worlds/irb1600_table --name irb1600_table").exit_code, 0);
  std::string q = "0, 0, 0, 0, 0, 0";
  for (const Box& box : Boxes()) {
    q += ", " + std::to_string(box.x) + ", " + std::to_string(box.y) + ", " +
         std::to_string(box.z) + ", " + std::to_string(box.qw) + ", " + std::to_string(box.qx) +
         ", " + std::to_string(box.qy) + ", " + std::to_string(box.qz);
  }
  std::string qd = "0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 2";
  for (int k = 0; k < 12; ++k) qd += ", 0";
  const fs::path spec = dir_ / "thrown.json";
  std::ofstream(spec) << R"({"duration_s": 0.4, "output_interval_s": 0.02, "formulation": "joint",
    "method": "bdf", "rtol": 1e-10, "atol": 1e-12, "gravity": {"z": -9.81},
    "initial_q": [)" << q
                      << R"(], "initial_qd": [)" << qd << "]}";
  const CommandOutcome run =
      Cli("run irb1600_table --spec " + spec.string() + " --watch --out " + Out("thrown"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<std::string> names = Header(dir_ / "thrown" / "joints.csv");
  std::map<std::string, size_t> column;
  for (size_t k = 0; k < names.size(); ++k) column[names[k]] = k;
  const std::vector<std::vector<std::string>> rows = ReadCsv(dir_ / "thrown" / "joints.csv");
  ASSERT_EQ(rows.size(), 21u);
  double off_line = 0, off_spin = 0;
  for (const auto& row : rows) {
    const double t = std::stod(row[0]);
    const auto at = [&](const char* name) { return std::stod(row.at(column.at(name))); };
    off_line = std::max(off_line, std::abs(at("box_a::link.x") - (1.0 + t)));
    // A spin about the body's z axis, from the identity: q = (cos t, 0, 0, sin t).
    off_spin = std::max({off_spin, std::abs(at("box_a::link.qw") - std::cos(t)),
                         std::abs(at("box_a::link.qz") - std::sin(t))});
  }
  EXPECT_LT(off_line, 1e-8);
  EXPECT_LT(off_spin, 1e-7);
  // A quaternion that is not unit is refused at the edge, with the norm it has.
  std::string bad_q = "0, 0, 0, 0, 0, 0, 1, 0, 1, 1, 1, 0, 0";  // box_a's qw = qx = 1
  for (int k = 0; k < 14; ++k) bad_q += ", 0";
  std::ofstream(dir_ / "bad.json") << R"({"initial_q": [)" << bad_q << "]}";
  const CommandOutcome bad = Cli("run irb1600_table --spec " + (dir_ / "bad.json").string());
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.output, HasSubstr("free joint 'box_a::link'"));
  EXPECT_THAT(bad.output, HasSubstr("has norm 1.41421356"));
}

// A box dropped from a pose and thrown with a twist given by its name (RunSpec.initial_bodies),
// over the world's own poses (no initial_q): through `simulate` and a live server, box_b
// starts where the spec puts it, turned by its rpy, and flies on its parabola from there;
// box_a keeps the world's pose. A name that is no free body is refused (INVALID_ARGUMENT on
// the server), naming it and the free bodies.
TEST_F(WorldCliTest, ABoxFallsFromAPoseGivenByItsName) {
  const fs::path spec = dir_ / "dropped.json";
  std::ofstream(spec) << R"({"duration_s": 0.4, "output_interval_s": 0.02, "formulation": "joint",
    "method": "bdf", "rtol": 1e-10, "atol": 1e-12, "gravity": {"z": -9.81},
    "initialBodies": [{"name": "box_b::link", "positionM": {"x": 0.3, "y": -0.4, "z": 1.7},
                       "rpy": {"roll": 0.4, "yaw": -1.0},
                       "linearVelocityMPerS": {"x": 0.5, "z": 2.0}}]})";
  // R_WB = Rz(-1) Rx(0.4): the product of the axis quaternions.
  const double cy = std::cos(-0.5), sy = std::sin(-0.5), cr = std::cos(0.2), sr = std::sin(0.2);
  const Box turned{"box_b::link", 0, 0, 0, cy * cr, cy * sr, sy * sr, sy * cr};
  const auto check = [&](const std::string& out) {
    const std::vector<std::string> names = Header(dir_ / out / "joints.csv");
    std::map<std::string, size_t> column;
    for (size_t k = 0; k < names.size(); ++k) column[names[k]] = k;
    const std::vector<std::vector<std::string>> rows = ReadCsv(dir_ / out / "joints.csv");
    ASSERT_EQ(rows.size(), 21u);
    double off_parabola = 0, off_turn = 0;
    for (const auto& row : rows) {
      const double t = std::stod(row[0]);
      const auto at = [&](const std::string& suffix) {
        return std::stod(row.at(column.at("box_b::link" + suffix)));
      };
      off_parabola =
          std::max({off_parabola, std::abs(at(".x") - (0.3 + 0.5 * t)), std::abs(at(".y") + 0.4),
                    std::abs(at(".z") - (1.7 + 2.0 * t - 0.5 * kG * t * t))});
      off_turn =
          std::max({off_turn, std::abs(at(".qw") - turned.qw), std::abs(at(".qx") - turned.qx),
                    std::abs(at(".qy") - turned.qy), std::abs(at(".qz") - turned.qz)});
    }
    std::cout << out << ": box_b off its parabola by at most " << off_parabola
              << " m, off its turn by " << off_turn << "\n";
    EXPECT_LT(off_parabola, 1e-8) << out;
    EXPECT_LT(off_turn, 1e-10) << out;
    EXPECT_NEAR(std::stod(rows.front().at(column.at("box_b::link.x"))), 0.3, 1e-15) << out;
    const Deviation a = FallDeviation(dir_ / out, Boxes()[0]);  // box_a: the world's pose
    EXPECT_LT(a.position_m, 1e-8) << out;
  };
  const CommandOutcome local = RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kWorld +
                                          " --spec " + spec.string() + " --out " + Out("local"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  check("local");
  StartServer();
  ASSERT_EQ(Cli("submit models/worlds/irb1600_table --name irb1600_table").exit_code, 0);
  const CommandOutcome served =
      Cli("run irb1600_table --spec " + spec.string() + " --watch --out " + Out("served"));
  ASSERT_EQ(served.exit_code, 0) << served.output;
  check("served");
  EXPECT_EQ(ReadFile(dir_ / "served" / "joints.csv"), ReadFile(dir_ / "local" / "joints.csv"));

  std::ofstream(dir_ / "typo.json") << R"({"initial_bodies": [{"name": "box_b::lnk"}]})";
  const std::string typo = " --spec " + (dir_ / "typo.json").string();
  const CommandOutcome refused_local = RunCommand(std::string(MBSTREAM_CLI) + " simulate " +
                                                  kWorld + typo + " --out " + Out("typo"));
  EXPECT_NE(refused_local.exit_code, 0);
  const CommandOutcome refused = Cli("run irb1600_table" + typo);
  EXPECT_EQ(refused.exit_code, 2);  // INVALID_ARGUMENT
  for (const CommandOutcome* outcome : {&refused_local, &refused}) {
    EXPECT_THAT(outcome->output, HasSubstr("initial_bodies[0].name: 'box_b::lnk' is no free body "
                                           "of the model; did you mean 'box_b::link'?"));
    EXPECT_THAT(outcome->output, HasSubstr("box_a::link, box_b::link, box_c::link"));
  }
}

// A sweep of a free body's initial pose by its coordinate's name (sweep_coordinates.h): the
// base spec has no initial_q, so every other coordinate keeps the world's own pose; each
// run's box_a starts at its swept height and falls from there.
TEST_F(WorldCliTest, ASweepMovesOneFreeBodyByItsCoordinatesName) {
  StartServer();
  ASSERT_EQ(Cli("submit models/worlds/irb1600_table --name irb1600_table").exit_code, 0);
  const CommandOutcome sweep =
      Cli(std::string("sweep irb1600_table --spec ") + kSpec +
          " --grid 'initial_q[box_a::link.z]=0.5,2' --keep all --out " + Out("heights"));
  ASSERT_EQ(sweep.exit_code, 0) << sweep.output;
  int runs = 0;
  std::vector<double> heights;
  for (const fs::directory_entry& run : fs::directory_iterator(dir_ / "heights" / "runs")) {
    ++runs;
    const std::vector<std::string> names = Header(run.path() / "joints.csv");
    const size_t z =
        static_cast<size_t>(std::find(names.begin(), names.end(), "box_a::link.z") - names.begin());
    const size_t other =
        static_cast<size_t>(std::find(names.begin(), names.end(), "box_b::link.z") - names.begin());
    ASSERT_LT(z, names.size());
    const std::vector<std::vector<std::string>> rows = ReadCsv(run.path() / "joints.csv");
    heights.push_back(std::stod(rows.front().at(z)));
    EXPECT_NEAR(std::stod(rows.front().at(other)), 1.0, 1e-12);  // box_b's own pose
    const double t = std::stod(rows.back()[0]);
    EXPECT_NEAR(std::stod(rows.back().at(z)), heights.back() - 0.5 * kG * t * t, 1e-8);
  }
  EXPECT_EQ(runs, 2);
  std::sort(heights.begin(), heights.end());
  EXPECT_EQ(heights, std::vector<double>({0.5, 2.0}));
  const CommandOutcome bad = Cli(std::string("sweep irb1600_table --spec ") + kSpec +
                                 " --grid 'initial_q[box_a::link.zz]=1' --out " + Out("bad"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_THAT(bad.output, HasSubstr("did you mean 'box_a::link.z'?"));
}

// A world's <gravity> (the Moon's) is the run's when the spec gives none, in `simulate` and on
// a server; a spec's gravity wins. The box's centre of mass falls on the Moon's parabola.
TEST_F(WorldCliTest, AWorldsGravityIsTheRunsUnlessTheSpecGivesOne) {
  const fs::path world = dir_ / "moon.sdf";
  std::ofstream(world) << R"(<?xml version="1.0"?>
<sdf version="1.8">
  <world name="moon">
    <gravity>0 0 -1.62</gravity>
    <model name="probe">
      <pose>0 0 2 0 0 0</pose>
      <link name="body">
        <inertial><mass>3</mass>
          <inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.3</izz></inertia></inertial>
      </link>
    </model>
  </world>
</sdf>
)";
  const fs::path spec = dir_ / "drop.json";
  std::ofstream(spec) << R"({"duration_s": 1, "output_interval_s": 0.1, "rtol": 1e-10,
    "atol": 1e-12})";
  const auto largest_fall_error = [&](const std::string& out, double g) {
    const std::vector<std::string> names = Header(dir_ / out / "joints.csv");
    const size_t z =
        static_cast<size_t>(std::find(names.begin(), names.end(), "body.z") - names.begin());
    EXPECT_LT(z, names.size()) << FirstLine(ReadFile(dir_ / out / "joints.csv"));
    double error = 0;
    for (const auto& row : ReadCsv(dir_ / out / "joints.csv")) {
      const double t = std::stod(row[0]);
      error = std::max(error, std::abs(std::stod(row.at(z)) - (2.0 - 0.5 * g * t * t)));
    }
    return error;
  };
  const CommandOutcome local =
      RunCommand(std::string(MBSTREAM_CLI) + " simulate " + world.string() + " --spec " +
                 spec.string() + " --out " + Out("local"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  EXPECT_LT(largest_fall_error("local", 1.62), 1e-9);
  StartServer();
  ASSERT_EQ(Cli("submit " + world.string() + " --name moon").exit_code, 0);
  const CommandOutcome served =
      Cli("run moon --spec " + spec.string() + " --watch --out " + Out("served"));
  ASSERT_EQ(served.exit_code, 0) << served.output;
  EXPECT_LT(largest_fall_error("served", 1.62), 1e-9);
  std::ofstream(spec) << R"({"duration_s": 1, "output_interval_s": 0.1, "rtol": 1e-10,
    "atol": 1e-12, "gravity": {"z": -9.81}})";
  const CommandOutcome earth =
      Cli("run moon --spec " + spec.string() + " --watch --out " + Out("earth"));
  ASSERT_EQ(earth.exit_code, 0) << earth.output;
  EXPECT_LT(largest_fall_error("earth", 9.81), 1e-9);
}

// A kinematic run of the world (models/worlds/irb1600_table/box-carried.json): the robot's
// joints on their trajectories and each box on its pose drive (run_spec.proto Drive.Pose),
// box_a carried along splines in x and z while it turns about z, box_b rocking about x from
// its own yaw, box_c held where the world puts it. Through `simulate` and a live server: the
// same files, the poses as their closed forms give them.
TEST_F(WorldCliTest, AKinematicRunCarriesEachBoxAlongItsPose) {
  constexpr char kCarried[] = "models/worlds/irb1600_table/box-carried.json";
  const CommandOutcome local = RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kWorld +
                                          " --spec " + kCarried + " --out " + Out("local"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const std::vector<std::string> names = Header(dir_ / "local" / "joints.csv");
  std::map<std::string, size_t> column;
  for (size_t k = 0; k < names.size(); ++k) column[names[k]] = k;
  const std::vector<std::vector<std::string>> rows = ReadCsv(dir_ / "local" / "joints.csv");
  ASSERT_EQ(rows.size(), 41u);
  double knots = 0, turn = 0, rock = 0, held = 0;
  for (const auto& row : rows) {
    const double t = std::stod(row[0]);
    const auto at = [&](const std::string& name) { return std::stod(row.at(column.at(name))); };
    if (t == 0.0 || t == 1.0 || t == 2.0) {  // the splines' knots
      const int k = static_cast<int>(t);
      knots = std::max({knots, std::abs(at("box_a::link.x") - (1.0 - 0.2 * k)),
                        std::abs(at("box_a::link.z") - std::vector<double>{0.9, 1.4, 1.2}[k])});
    }
    const double yaw = 1.2 * std::sin(2.0 * t);  // box_a: a turn about z, from the identity
    turn = std::max({turn, std::abs(at("box_a::link.y") + 0.15),
                     std::abs(at("box_a::link.qw") - std::cos(yaw / 2)),
                     std::abs(at("box_a::link.qz") - std::sin(yaw / 2))});
    // box_b: Rz(0.5) Rx(roll), the product of (cos 0.25, 0, 0, sin 0.25) and (cos r/2, sin r/2,
    // 0, 0).
    const double r = 0.15 * std::sin(4.0 * t), c = std::cos(0.25), s = std::sin(0.25);
    rock = std::max({rock, std::abs(at("box_b::link.qw") - c * std::cos(r)),
                     std::abs(at("box_b::link.qx") - c * std::sin(r)),
                     std::abs(at("box_b::link.qy") - s * std::sin(r)),
                     std::abs(at("box_b::link.qz") - s * std::cos(r))});
    held =
        std::max({held, std::abs(at("box_c::link.x") - 1.25), std::abs(at("box_c::link.z") - 1.1),
                  std::abs(at("box_c::link.qx") - std::sin(0.15))});
  }
  EXPECT_LT(knots, 1e-15);
  EXPECT_LT(turn, 1e-15);
  EXPECT_LT(rock, 1e-15);
  EXPECT_LT(held, 1e-15);
  StartServer();
  ASSERT_EQ(Cli("submit models/worlds/irb1600_table --name irb1600_table").exit_code, 0);
  const CommandOutcome served =
      Cli(std::string("run irb1600_table --spec ") + kCarried + " --watch --out " + Out("served"));
  ASSERT_EQ(served.exit_code, 0) << served.output;
  for (const char* file : {"joints.csv", "velocities.csv", "torques.csv"}) {
    EXPECT_EQ(ReadFile(dir_ / "served" / file), ReadFile(dir_ / "local" / file)) << file;
  }
}

}  // namespace
}  // namespace mbstream::testing
