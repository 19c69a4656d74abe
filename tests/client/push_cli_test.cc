// The IRB 1600's tool pushes a box along the floor (issue 44, "Manipulation";
// models/worlds/irb1600_push/): the arm's motion is prescribed, the box is free, the tool a
// 4 cm sphere at the TCP. Checked through `mbstream simulate` and a live server: the box stays
// where it stands (bit for bit) until the tool reaches it, moves from the first frame after, is
// pushed along the tool's way and comes to rest upright on the floor; the energy balance,
// contact work included, closes.
#include <gmock/gmock.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "tests/common/cli_server_test.h"
#include "tests/common/csv_rows.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;

constexpr char kWorld[] = "models/worlds/irb1600_push/world.sdf";
constexpr char kSpec[] = "models/worlds/irb1600_push/push.json";
constexpr double kToolRadius = 0.04;  // m, the tool sphere's (generate.py --push)
constexpr double kHalfEdge = 0.05;    // m, the box's

struct Table {
  std::map<std::string, size_t> column;
  std::vector<std::vector<std::string>> rows;
  double At(size_t row, const std::string& name) const {
    return std::stod(rows.at(row).at(column.at(name)));
  }
};

Table Read(const fs::path& csv) {
  Table table;
  std::stringstream line(FirstLine(ReadFile(csv)));
  size_t k = 0;
  for (std::string name; std::getline(line, name, ',');) table.column[name] = k++;
  table.rows = ReadCsv(csv);
  return table;
}

// The distance from point p (world) to the box at its pose of row 0 (m): 0 inside.
double DistanceToBox(const Table& joints, const Eigen::Vector3d& p) {
  const Eigen::Vector3d c(joints.At(0, "box::link.x"), joints.At(0, "box::link.y"),
                          joints.At(0, "box::link.z"));
  const Eigen::Quaterniond q(joints.At(0, "box::link.qw"), joints.At(0, "box::link.qx"),
                             joints.At(0, "box::link.qy"), joints.At(0, "box::link.qz"));
  const Eigen::Vector3d local = q.conjugate() * (p - c);
  const Eigen::Vector3d outside = (local.cwiseAbs().array() - kHalfEdge).max(0.0).matrix();
  return outside.norm();
}

void ExpectThePush(const fs::path& out) {
  const Table joints = Read(out / "joints.csv");
  const Table tcp = Read(out / "tcp.csv");
  const Table velocities = Read(out / "velocities.csv");
  ASSERT_EQ(joints.rows.size(), 151u);
  ASSERT_EQ(tcp.rows.size(), joints.rows.size());
  // The first frame at which the tool sphere (centred on the TCP) reaches the box standing
  // where it started: from the prescribed motion alone.
  size_t touch = 0;
  for (size_t k = 0; k < tcp.rows.size() && touch == 0; ++k) {
    const Eigen::Vector3d p(tcp.At(k, "x"), tcp.At(k, "y"), tcp.At(k, "z"));
    if (DistanceToBox(joints, p) <= kToolRadius) touch = k;
  }
  ASSERT_GT(touch, 10u) << "the tool starts clear of the box";
  std::cout << "the tool reaches the box between t = " << joints.At(touch - 1, "t") << " and "
            << joints.At(touch, "t") << " s\n";
  // Still (settling on the floor by its 0.1 mm only) until the frame before; moved by then.
  for (size_t k = 0; k + 1 < touch; ++k) {
    EXPECT_EQ(joints.At(k, "box::link.x"), joints.At(0, "box::link.x")) << "frame " << k;
    EXPECT_EQ(joints.At(k, "box::link.y"), joints.At(0, "box::link.y")) << "frame " << k;
  }
  const double moved = std::hypot(joints.At(touch, "box::link.x") - joints.At(0, "box::link.x"),
                                  joints.At(touch, "box::link.y") - joints.At(0, "box::link.y"));
  EXPECT_GT(moved, 1e-4) << "the box has not moved at the frame the tool reached it";
  // Pushed along the tool's way (+y here), far; at rest, upright on the floor at the end.
  const size_t last = joints.rows.size() - 1;
  EXPECT_GT(joints.At(last, "box::link.y") - joints.At(0, "box::link.y"), 0.3);
  EXPECT_NEAR(joints.At(last, "box::link.z"), kHalfEdge, 1e-3);
  const double tilt = 2 * std::asin(std::min(1.0, std::hypot(joints.At(last, "box::link.qx"),
                                                             joints.At(last, "box::link.qy"))));
  EXPECT_LT(tilt, 0.01) << "the box tipped over";
  EXPECT_LT(std::hypot(velocities.At(last, "box::link.vx"), velocities.At(last, "box::link.vy")),
            1e-3);
  // The tool's contact with the box pushes: in every frame with it, its force on the box has a
  // positive component along the tool's velocity.
  const Table contacts = Read(out / "contacts.csv");
  int pushing = 0;
  for (size_t r = 0; r < contacts.rows.size(); ++r) {
    const auto& row = contacts.rows[r];
    if (row[1] != "irb1600::link6" || row[3] != "box::link") continue;
    ++pushing;
    // On a (the tool) along the normal from b (the box) toward a; the box gets the opposite.
    const Eigen::Vector3d normal(std::stod(row[8]), std::stod(row[9]), std::stod(row[10]));
    const Eigen::Vector3d on_box = -std::stod(row[12]) * normal;
    const size_t k = static_cast<size_t>(std::lround(std::stod(row[0]) / 0.02));
    const size_t before = k - 1, after = std::min(k + 1, last);  // k > touch > 10
    const Eigen::Vector3d a(tcp.At(before, "x"), tcp.At(before, "y"), 0.0);
    const Eigen::Vector3d b(tcp.At(after, "x"), tcp.At(after, "y"), 0.0);
    EXPECT_GT(on_box.dot(b - a), 0.0) << "t = " << row[0];
  }
  EXPECT_GT(pushing, 5);
}

class PushCliTest : public CliServerTest {};

TEST_F(PushCliTest, TheToolPushesTheBoxAlongTheFloor) {
  const CommandOutcome run = RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kWorld +
                                        " --spec " + kSpec + " --out " + Out("local"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, ::testing::HasSubstr("trust: ok")) << run.output;
  ExpectThePush(dir_ / "local");
}

// The box placed exactly on the floor (0 m apart at t = 0, where the shipped world leaves
// 0.1 mm): the box-floor distance is 0, then -1.7e-16 m (round-off) after two steps of 4e-9 s.
// The root finder took the 0 as DBL_MIN, whose product with -1.7e-16 underflows to -0.0, lost
// the sign change, asked the root functions at t = -3.2e-9 s and then at t = inf, and the run
// FAILED at t = 0 (KeepRootsAwayFromZero, sundials_callbacks.h, now floors them at 1e-150).
TEST_F(PushCliTest, ABoxPlacedExactlyOnTheFloorIsPushedAsWell) {
  const fs::path world = dir_ / "touching";
  fs::copy(fs::path(kWorld).parent_path(), world, fs::copy_options::recursive);
  std::string text = ReadFile(world / "world.sdf");
  const std::string shipped = "0.92222 -0.18695 0.0501 ";
  ASSERT_NE(text.find(shipped), std::string::npos);
  text.replace(text.find(shipped), shipped.size(), "0.92222 -0.18695 0.05 ");
  std::ofstream(world / "world.sdf") << text;
  const CommandOutcome run =
      RunCommand(std::string(MBSTREAM_CLI) + " simulate " + (world / "world.sdf").string() +
                 " --spec " + kSpec + " --out " + Out("touching_out"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_THAT(run.output, ::testing::HasSubstr("trust: ok")) << run.output;
  ExpectThePush(dir_ / "touching_out");
}

// Through a live server: the world's folder submitted, the run's results downloaded, their
// contacts.csv rebuilt from the stored frames.
TEST_F(PushCliTest, AServedRunPushesTheSameBox) {
  StartServer();
  ASSERT_EQ(Cli("submit models/worlds/irb1600_push --name irb1600_push").exit_code, 0);
  const CommandOutcome run =
      Cli(std::string("run irb1600_push --spec ") + kSpec + " --watch --out " + Out("served"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ExpectThePush(dir_ / "served");
  // The same contacts, bit for bit, as the same run in the CLI.
  ASSERT_EQ(RunCommand(std::string(MBSTREAM_CLI) + " simulate " + kWorld + " --spec " + kSpec +
                       " --out " + Out("local"))
                .exit_code,
            0);
  EXPECT_EQ(ReadFile(dir_ / "served" / "contacts.csv"), ReadFile(dir_ / "local" / "contacts.csv"));
}

}  // namespace
}  // namespace mbstream::testing
