// Sampled drives (zero-order hold): pd_servo with period_s, and external drives commanded by a
// ControlLaw, integrated period by period (server/sim/sampled_joint_run.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "server/engine/engine.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_stop.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

// s: the seed servo's wrist (joint 6: about 0.004 kg m^2 about its axis, kd 40 N m s/rad) keeps
// a sampled PD stable only for h < 2 I / kd, about 2e-4 s.
constexpr double kPeriod = 1e-4;

// The seed servo (models/irb1600/seed-servo.json) over 0.5 s, its servos sampled every kPeriod.
RunConfig SampledServo() {
  RunConfig config = Scene("seed-servo");
  config.duration = 0.5;
  for (DriveConfig& drive : config.drives) drive.period = kPeriod;
  return config;
}

// The seed servo's law, computed outside the engine: effort = kp (q_ref - q) + kd (qd_ref - qd)
// with q_ref = a sin(w t), qd_ref = (a w) cos(w t), term by term as DriveSet sums them.
class SeedServoLaw : public ControlLaw {
 public:
  explicit SeedServoLaw(const RunConfig& servo) : servo_(servo) {}
  bool Command(const ControlState& state, double* commands, RunStats*) override {
    ++calls;
    last_t = state.t;
    for (size_t i = 0; i < servo_.drives.size(); ++i) {
      const DriveConfig& drive = servo_.drives[i];
      double value = drive.trajectory.offset, rate = 0.0;
      for (size_t k = 0; k < drive.trajectory.amplitude.size(); ++k) {
        const double a = drive.trajectory.amplitude[k], w = drive.trajectory.omega[k];
        const double arg = w * state.t + drive.trajectory.phase[k];
        value += a * std::sin(arg);
        rate += (a * w) * std::cos(arg);
      }
      commands[i] = drive.kp * (value - (*state.q)(static_cast<Eigen::Index>(i))) +
                    drive.kd * (rate - (*state.qd)(static_cast<Eigen::Index>(i)));
    }
    return true;
  }
  void Final(const ControlState& state) override { final_t = state.t; }
  long calls = 0;
  double last_t = -1.0, final_t = -1.0;

 private:
  const RunConfig servo_;
};

RunConfig ExternalEffort(const RunConfig& servo) {
  RunConfig config = servo;
  for (DriveConfig& drive : config.drives) {
    drive = DriveConfig{};
    drive.kind = DriveConfig::Kind::kExternal;
    drive.command = DriveConfig::Command::kEffort;
    drive.period = kPeriod;
  }
  return config;
}

TEST(SampledDriveTest, ExternalSeedServoEqualsSampledPdServo) {
  const RunConfig servo = SampledServo();
  ValidateRun(Irb1600(), servo);
  const RunResult builtin = Simulate(Irb1600(), servo);
  ASSERT_EQ(builtin.stats.status, RunStatus::kFinished) << builtin.stats.message;
  const RunConfig external = ExternalEffort(servo);
  ValidateRun(Irb1600(), external);
  SeedServoLaw law(servo);
  const RunResult controlled = Simulate(Irb1600(), {}, external, nullptr, nullptr, &law);
  ASSERT_EQ(controlled.stats.status, RunStatus::kFinished) << controlled.stats.message;
  EXPECT_EQ(law.calls, 5000);  // t = 0, 1e-4, ..., 0.4999: none at the end
  EXPECT_NEAR(law.last_t, 0.4999, 1e-12);
  EXPECT_EQ(law.final_t, 0.5);
  ASSERT_EQ(controlled.num_frames(), builtin.num_frames());
  double worst = 0.0;
  for (size_t k = 0; k < builtin.q.size(); ++k) {
    worst = std::max(worst, std::abs(builtin.q[k] - controlled.q[k]));
    worst = std::max(worst, std::abs(builtin.qd[k] - controlled.qd[k]));
  }
  EXPECT_LE(worst, 1e-12);
  EXPECT_EQ(builtin.stats.solver.steps, controlled.stats.solver.steps);
}

TEST(SampledDriveTest, EffortIsHeldOverEachPeriod) {
  RunConfig servo = SampledServo();
  servo.duration = 0.1;
  servo.output_interval = kPeriod / 2;  // two frames per period
  const RunResult result = Simulate(Irb1600(), servo);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  ASSERT_TRUE(result.has_torques);
  const int n = result.num_dofs;
  for (int k = 0; k + 1 < result.num_frames(); k += 2) {  // frames 2m and 2m+1: one period
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(result.tau[static_cast<size_t>(k * n + i)],
                result.tau[static_cast<size_t>((k + 1) * n + i)])
          << "t = " << result.t[static_cast<size_t>(k)] << ", joint " << i;
    }
  }
  // ... and changes at each control instant.
  EXPECT_NE(result.tau[static_cast<size_t>(2 * n)], result.tau[0]);
}

TEST(SampledDriveTest, ShortPeriodApproachesTheContinuousServo) {
  RunConfig servo = SampledServo();
  RunConfig continuous = servo;
  for (DriveConfig& drive : continuous.drives) drive.period = 0.0;
  const RunResult sampled = Simulate(Irb1600(), servo);
  const RunResult exact = Simulate(Irb1600(), continuous);
  ASSERT_EQ(sampled.stats.status, RunStatus::kFinished) << sampled.stats.message;
  ASSERT_EQ(sampled.q.size(), exact.q.size());
  double worst = 0.0;
  for (size_t k = 0; k < exact.q.size(); ++k) {
    worst = std::max(worst, std::abs(sampled.q[k] - exact.q[k]));
  }
  EXPECT_LT(worst, 5e-3);  // rad: a delay of about h / 2
  EXPECT_GT(worst, 0.0);
}

TEST(SampledDriveTest, PositionCommandIsTheServersPd) {
  // An external position drive with a constant setpoint is a continuous PD to that setpoint:
  // the same as pd_servo with a constant reference (offset only), run period by period.
  RunConfig servo = SampledServo();
  servo.rtol = 1e-10;
  servo.atol = 1e-12;
  RunConfig external = ExternalEffort(servo);
  for (DriveConfig& drive : servo.drives) {
    drive.trajectory = Trajectory{};
    drive.trajectory.offset = 0.3;
    drive.period = 0.0;
  }
  for (size_t i = 0; i < external.drives.size(); ++i) {
    external.drives[i].command = DriveConfig::Command::kPosition;
    external.drives[i].kp = servo.drives[i].kp;
    external.drives[i].kd = servo.drives[i].kd;
  }
  struct Hold : ControlLaw {
    bool Command(const ControlState&, double* commands, RunStats*) override {
      for (int i = 0; i < 6; ++i) commands[i] = 0.3;
      return true;
    }
  } hold;
  const RunResult continuous = Simulate(Irb1600(), servo);
  const RunResult controlled = Simulate(Irb1600(), {}, external, nullptr, nullptr, &hold);
  ASSERT_EQ(controlled.stats.status, RunStatus::kFinished) << controlled.stats.message;
  double worst = 0.0;
  for (size_t k = 0; k < continuous.q.size(); ++k) {
    worst = std::max(worst, std::abs(continuous.q[k] - controlled.q[k]));
  }
  EXPECT_LT(worst, 1e-6);  // rad: the same ODE, restarted every period (rtol 1e-10)
}

TEST(SampledDriveTest, ASampledServoTooSlowForItsJointIsWarned) {
  RunConfig servo = SampledServo();
  servo.duration = 0.01;
  for (DriveConfig& drive : servo.drives) drive.period = 1e-3;  // the wrist needs < 2e-4 s
  const RunResult result = Simulate(Irb1600(), servo);
  bool warned = false;
  for (const std::string& warning : result.stats.warnings) {
    warned |= warning.find("pd_servo.period_s = 0.001 s on joint 6 'joint6': kd h / inertia") !=
              std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(SampledDriveTest, ExternalDrivesWithoutControllerFail) {
  const RunResult result = Simulate(Irb1600(), ExternalEffort(SampledServo()));
  EXPECT_EQ(result.stats.status, RunStatus::kFailed);
  EXPECT_NE(result.stats.message.find("no controller"), std::string::npos) << result.stats.message;
}

TEST(SampledDriveTest, ControllerStopsTheRun) {
  struct Stop : ControlLaw {
    bool Command(const ControlState& state, double* commands, RunStats* stats) override {
      for (int i = 0; i < 6; ++i) commands[i] = 0.0;
      if (state.step < 3) return true;
      StopRun(stats, RunStatus::kFailed, "stopped by the controller");
      return false;
    }
  } stop;
  const RunResult result =
      Simulate(Irb1600(), {}, ExternalEffort(SampledServo()), nullptr, nullptr, &stop);
  EXPECT_EQ(result.stats.status, RunStatus::kFailed);
  EXPECT_EQ(result.stats.message, "stopped by the controller");
  EXPECT_LT(result.t.back(), 0.05);
}

// Each state's sensor points are where forward kinematics puts them: a point on link6 (the
// flange) off its origin, and one on the base.
TEST(SampledDriveTest, SensorPointsAreWhereForwardKinematicsPutsThem) {
  RunConfig config = ExternalEffort(SampledServo());
  config.duration = 0.02;
  config.sensor_points = {{"tip", "link6", Eigen::Vector3d(0.1, -0.2, 0.3)},
                          {"origin", Irb1600().frames[0].name, Eigen::Vector3d(0.0, 0.0, 0.5)}};
  ValidateRun(Irb1600(), config);
  struct Law : ControlLaw {
    Data data{Irb1600()};
    int checked = 0;
    double worst = 0.0;
    bool Command(const ControlState& state, double* commands, RunStats*) override {
      for (int i = 0; i < 6; ++i) commands[i] = 20.0 * std::sin(100.0 * state.t + i);
      EXPECT_EQ(state.sensors->size(), 2u);
      ForwardKinematics(Irb1600(), data, *state.q);
      const Pose& flange = data.frame_world[static_cast<size_t>(Irb1600().FindFrame("link6"))];
      const Eigen::Vector3d tip = flange.R * Eigen::Vector3d(0.1, -0.2, 0.3) + flange.p;
      const Pose& base = data.frame_world[0];
      const Eigen::Vector3d origin = base.R * Eigen::Vector3d(0.0, 0.0, 0.5) + base.p;
      worst = std::max(
          {worst, ((*state.sensors)[0] - tip).norm(), ((*state.sensors)[1] - origin).norm()});
      ++checked;
      return true;
    }
  } law;
  const RunResult result = Simulate(Irb1600(), {}, config, nullptr, nullptr, &law);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(law.checked, 200);
  EXPECT_LE(law.worst, 1e-12);  // m
}

TEST(SampledDriveTest, ASensorPointOnAnUnknownLinkIsRefusedNamingTheField) {
  RunConfig config = ExternalEffort(SampledServo());
  config.sensor_points = {{"tip", "link6", Eigen::Vector3d::Zero()},
                          {"oops", "link7", Eigen::Vector3d::Zero()}};
  try {
    ValidateRun(Irb1600(), config);
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("sensor_points[1].link"), std::string::npos)
        << error.what();
    EXPECT_NE(std::string(error.what()).find("'link7'"), std::string::npos) << error.what();
  }
  config.sensor_points.clear();
  config.sensor_points.push_back({"tip", "link6", Eigen::Vector3d::Zero()});
  for (DriveConfig& drive : config.drives) drive = DriveConfig{};  // no external drive
  EXPECT_THROW(ValidateRun(Irb1600(), config), InputError);
}

// A controlled run of a box dropped on the floor: its slider commanded 0 N in the air and a
// damper's effort, -c qd, while the state reports contacts (the contact alone would ring for
// seconds: Hunt-Crossley's damping is light at rest). Once it rests, each state reports its
// four corners on the floor, whose normal forces add up to its weight.
TEST(SampledDriveTest, AControlledBoxOnTheFloorReportsItsWeightAsContactForce) {
  const Model box =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/contact/box_on_slider.sdf")
          .model;
  ASSERT_EQ(box.nv(), 2);  // carriage (x), drop (z)
  RunConfig config;
  config.formulation = Formulation::kJoint;
  config.duration = 1.5;
  config.output_interval = 0.1;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  config.contact.stiffness = 1e5;
  config.drives.resize(2);
  for (DriveConfig& drive : config.drives) {
    drive.kind = DriveConfig::Kind::kExternal;
    drive.command = DriveConfig::Command::kEffort;
    drive.period = 1e-3;
  }
  ValidateRun(box, config);
  struct Law : ControlLaw {
    double first_contact_t = -1.0, normal_sum = 0.0, friction = 0.0, point_z = 1.0;
    double normal_z = 0.0;
    size_t count = 0;
    std::string link_a, link_b;
    bool Command(const ControlState& state, double* commands, RunStats*) override {
      commands[0] = commands[1] = 0.0;
      if (state.contacts == nullptr) return true;
      if (!state.contacts->empty()) commands[1] = -300.0 * (*state.qd)(1);  // N s/m
      if (!state.contacts->empty() && first_contact_t < 0.0) first_contact_t = state.t;
      count = state.contacts->size();
      normal_sum = friction = 0.0;
      for (const ContactPoint& c : *state.contacts) {
        normal_sum += c.normal_force;
        friction = std::max(friction, c.friction_force.norm());
        point_z = c.point.z();
        normal_z = c.normal.z();
        link_a = state.model->collisions[static_cast<size_t>(c.geometry_a)].link;
        link_b = state.model->collisions[static_cast<size_t>(c.geometry_b)].link;
      }
      return true;
    }
  } law;
  const RunResult result = Simulate(box, {}, config, nullptr, nullptr, &law);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  // Free fall of 0.05 m: t = sqrt(2 h / g) = 0.101 s.
  EXPECT_GE(law.first_contact_t, 0.1);
  EXPECT_LE(law.first_contact_t, 0.103);
  EXPECT_EQ(law.count, 4u);  // a box resting flat: its four bottom corners
  EXPECT_NEAR(law.normal_sum, 2.0 * 9.81, 1e-3 * 2.0 * 9.81);  // N: its weight
  EXPECT_LE(law.friction, 1e-6);                               // N: nothing pushes it sideways
  EXPECT_NEAR(std::abs(law.normal_z), 1.0, 1e-12);
  EXPECT_NEAR(law.point_z, 0.0, 1e-3);  // m: at the floor (midway, a fraction of a mm deep)
  EXPECT_NE((law.link_a + law.link_b).find("floor"), std::string::npos) << law.link_a;
  EXPECT_NE((law.link_a + law.link_b).find("body"), std::string::npos) << law.link_b;
  EXPECT_TRUE(result.contacts.active);  // and contacts.csv's log has them at the frames
  EXPECT_FALSE(result.contacts.records.empty());
  EXPECT_TRUE(result.stats.contact.active);
  EXPECT_EQ(result.stats.contact.contacts_peak, 4);
}

TEST(SampledDriveTest, ValidationRefusesWhatDoesNotRunSampledDrives) {
  RunConfig config = ExternalEffort(SampledServo());
  config.formulation = Formulation::kBodyBaumgarte;
  try {
    ValidateRun(Irb1600(), config);
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("formulation joint"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace mbstream
