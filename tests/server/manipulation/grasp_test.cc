// A two-finger gripper holding a box against gravity (issue 44, "Manipulation"): prismatic
// fingers on PD drives squeeze a free box between friction pads (tests/data/manipulation/
// gripper_box.sdf). A firm grip holds it for 5 s: its slip at most 1 mm, each pad's normal
// force what the finger's PD gives at rest, kp (q_ref - q), and the pads' friction carrying
// the box's weight inside the friction cone. A grip too weak for static friction lets it
// slide with a = g - 2 mu_d N / m, the closed form of Coulomb friction at both pads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "server/engine/engine.h"
#include "server/model/coordinate_names.h"
#include "server/parse/sdf_import.h"
#include "server/sim/run_validation.h"
#include "tests/server/contact/contact_scene.h"

namespace mbstream {
namespace {

using contact_testing::Q;

constexpr double kG = 9.81;
constexpr double kBoxMass = 0.1;  // kg (gripper_box.sdf)
constexpr double kKp = 1000.0;    // N/m, each finger's PD
constexpr double kKd = 10.0;      // N s/m

int IndexEndingWith(const std::vector<std::string>& names, const std::string& suffix) {
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    if (name.size() >= suffix.size() &&
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
      return static_cast<int>(i);
    }
  }
  ADD_FAILURE() << "no coordinate named ..." << suffix;
  return 0;
}

struct Grasp {
  Model model;
  RunConfig config;
  int left_q = 0, right_q = 0, box_z = 0;  // position indices
};

// The gripper squeezing the box: each finger's setpoint `squeeze` (m) past the box's face.
Grasp MakeGrasp(double squeeze, double duration, double output_interval) {
  Grasp grasp;
  grasp.model =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/manipulation/gripper_box.sdf")
          .model;
  const Model& model = grasp.model;
  const std::vector<std::string> positions = PositionNames(model);
  const std::vector<std::string> velocities = VelocityNames(model);
  grasp.left_q = IndexEndingWith(positions, "left_slide");
  grasp.right_q = IndexEndingWith(positions, "right_slide");
  grasp.box_z = IndexEndingWith(positions, "box.z");
  RunConfig& config = grasp.config;
  config.formulation = Formulation::kJoint;
  config.duration = duration;
  config.output_interval = output_interval;
  config.rtol = 1e-9;
  config.atol =
      1e-10;  // 1e-12 asks the creeping velocities for what roundoff in the pads' depths hides
  config.want_torques = false;
  config.contact.stiffness = 1e5;  // each surface: 5e4 N/m the pair
  config.contact.dissipation = 0.2;
  config.contact.mu_static = 0.6;
  config.contact.mu_dynamic = 0.5;
  config.drives.resize(static_cast<size_t>(model.nv()));  // the box passive
  for (const std::string finger : {"left_slide", "right_slide"}) {
    DriveConfig& drive = config.drives[static_cast<size_t>(IndexEndingWith(velocities, finger))];
    drive.kind = DriveConfig::Kind::kPdServo;
    drive.trajectory.kind = Trajectory::Kind::kSine;  // no terms: q_ref = offset
    drive.trajectory.offset = squeeze;
    drive.kp = kKp;
    drive.kd = kKd;
  }
  ValidateRun(model, config);
  return grasp;
}

// The pads' contacts with the box at the last output frame: normal forces and the vertical
// friction on the box, summed over each pad's contact points.
struct PadForces {
  double normal[2] = {0, 0};  // left, right (N)
  double friction_up = 0.0;   // N, on the box, +z
  double friction_norm[2] = {0, 0};
};

PadForces LastFramePads(const RunResult& r) {
  PadForces pads;
  const ContactLog& log = r.contacts;
  const double t_last = r.t.back();
  for (const ContactRecord& c : log.records) {
    if (c.t != t_last) continue;
    const std::string& a = log.collision[static_cast<size_t>(c.geometry_a)];
    const std::string& b = log.collision[static_cast<size_t>(c.geometry_b)];
    const bool box_is_a = a.find("box") != std::string::npos;
    const std::string& pad = box_is_a ? b : a;
    const int side = pad.find("left") != std::string::npos ? 0 : 1;
    pads.normal[side] += c.normal_force;
    const double fz = box_is_a ? c.friction[2] : -c.friction[2];
    pads.friction_up += fz;
    pads.friction_norm[side] += std::hypot(c.friction[0], c.friction[1], c.friction[2]);
  }
  return pads;
}

RunResult RunGrasp(const Grasp& grasp) {
  RunResult result = Simulate(grasp.model, grasp.config);
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_TRUE(result.contacts.active);
  return result;
}

TEST(GraspTest, AFirmGripHoldsTheBoxForFiveSeconds) {
  // 2 mm past the faces: about 2 N a pad, where the box's weight needs 0.98 / (2 mu_s) =
  // 0.82 N with static friction.
  const Grasp grasp = MakeGrasp(0.002, 5.0, 0.01);
  const RunResult r = RunGrasp(grasp);
  ASSERT_GE(r.t.size(), 2u);
  const size_t last = r.t.size() - 1;
  // Slip: the box's fall over the 5 s (the regularised friction creeps below v_s).
  const double slip = Q(r, 0, grasp.box_z) - Q(r, last, grasp.box_z);
  EXPECT_LT(std::abs(slip), 1e-3) << "the box slipped " << slip << " m";
  EXPECT_LT(std::abs(slip), grasp.config.contact.stiction_tolerance * 5.0);
  // At rest each pad presses with the finger's PD force, kp (q_ref - q).
  const PadForces pads = LastFramePads(r);
  const double pd_left = kKp * (0.002 - Q(r, last, grasp.left_q));
  const double pd_right = kKp * (0.002 - Q(r, last, grasp.right_q));
  EXPECT_GT(pads.normal[0], 1.5);
  EXPECT_NEAR(pads.normal[0], pd_left, 1e-4 * pd_left);
  EXPECT_NEAR(pads.normal[1], pd_right, 1e-4 * pd_right);
  // The pads' friction carries the weight, each pad inside its static cone.
  EXPECT_NEAR(pads.friction_up, kBoxMass * kG, 1e-4 * kBoxMass * kG);
  for (int side = 0; side < 2; ++side) {
    EXPECT_LE(pads.friction_norm[side], grasp.config.contact.mu_static * pads.normal[side]);
  }
}

TEST(GraspTest, AWeakGripLetsTheBoxSlideWithCoulombsDeceleration) {
  // 0.4 mm past the faces: about 0.4 N a pad, below the 0.82 N static friction needs; the
  // box slides down with a = g - 2 mu_d N / m (N steady: the fingers are at rest), about
  // 5.8 m/s^2: over 0.1 s it falls 29 mm of the 50 mm the pads hold it over.
  const Grasp grasp = MakeGrasp(0.0004, 0.1, 0.002);
  const RunResult r = RunGrasp(grasp);
  const size_t last = r.t.size() - 1;
  const PadForces pads = LastFramePads(r);
  const double normal = 0.5 * (pads.normal[0] + pads.normal[1]);
  EXPECT_LT(2.0 * grasp.config.contact.mu_static * normal, kBoxMass * kG);  // it must slip
  const double expected_a =
      kG - 2.0 * grasp.config.contact.mu_dynamic * normal / kBoxMass;  // m/s^2, downward
  // The acceleration from three late frames (after the start's transient), by differences.
  const size_t k = last - 10;
  const double h = r.t[k + 10] - r.t[k];
  const double z0 = Q(r, k - 10, grasp.box_z), z1 = Q(r, k, grasp.box_z),
               z2 = Q(r, k + 10, grasp.box_z);
  const double a = -(z2 - 2 * z1 + z0) / (h * h);
  EXPECT_NEAR(a, expected_a, 1e-3 * expected_a) << "normal force " << normal << " N";
  // The friction it feels: mu_d N a pad, opposing the slide.
  EXPECT_NEAR(pads.friction_up, 2.0 * grasp.config.contact.mu_dynamic * normal,
              1e-3 * 2.0 * grasp.config.contact.mu_dynamic * normal);
}

}  // namespace
}  // namespace mbstream
