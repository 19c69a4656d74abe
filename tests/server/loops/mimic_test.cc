// URDF <mimic> as a coupling of two joints (server/parse/urdf_mimic.h): imported only when
// asked for, with errors naming the joint; the coupling's equation, Jacobian and bias; runs
// that hold it (passive and prescribed), against a model whose follower is welded to its
// leader (multiplier 1, offset 0: the same rigid body) and against energy conservation.
#include <gmock/gmock.h>

#include <cmath>
#include <string>

#include "server/body/body_cuts.h"
#include "server/dynamics/rnea.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/kinematics/loop_constraints.h"
#include "server/parse/urdf_import.h"
#include "server/sim/loop_run.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

using ::testing::HasSubstr;

constexpr char kInertial[] = R"(<inertial><origin xyz="0 0 -0.3"/><mass value="1.5"/>
      <inertia ixx="0.05" iyy="0.05" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial>)";

// Two rods hanging from the base: "ja" moves rod a about y through the origin, and rod b
// hangs from a 0.1 m lower on "jb" about y (whose <mimic> is `mimic`; an empty string:
// none), or is welded to it there, turned by 0.3 rad about y (`weld`).
std::string TwoRods(const std::string& mimic, bool weld = false) {
  std::string jb = weld ? R"(<joint name="jb" type="fixed"><origin xyz="0 0 -0.1" rpy="0 0.3 0"/>)"
                        : R"(<joint name="jb" type="continuous"><axis xyz="0 1 0"/>
    <origin xyz="0 0 -0.1"/>)" +
                              mimic;
  return std::string(R"(<robot name="rods"><link name="base"/>
  <link name="a">)") +
         kInertial + R"(</link>
  <link name="b">)" +
         kInertial + R"(</link>
  <joint name="ja" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/>
  </joint>
  )" + jb +
         R"(<parent link="a"/><child link="b"/><origin xyz="0 0 -0.1"/></joint>
</robot>)";
}

UrdfImport Coupled(const std::string& urdf) {
  return ImportUrdf(urdf, "rods.urdf", {}, UrdfImportOptions{.couple_mimic = true});
}

TEST(UrdfMimicTest, AMimicIsIgnoredWithAWarningSayingHowToCoupleIt) {
  const UrdfImport imported = ImportUrdf(TwoRods(R"(<mimic joint="ja"/>)"), "rods.urdf", {}, {});
  EXPECT_TRUE(imported.loops.empty());
  EXPECT_EQ(imported.model.num_dofs(), 2);
  EXPECT_THAT(::testing::PrintToString(imported.warnings),
              HasSubstr("rods.urdf:8: joint 'jb': <mimic> of joint 'ja' is ignored"));
  EXPECT_THAT(::testing::PrintToString(imported.warnings), HasSubstr("--couple-mimic"));
}

TEST(UrdfMimicTest, CoupledAMimicIsALoopEquationOnTheTwoJoints) {
  const UrdfImport imported =
      Coupled(TwoRods(R"(<mimic joint="ja" multiplier="-0.5" offset="0.25"/>)"));
  ASSERT_EQ(imported.loops.size(), 1u);
  const LoopClosure& coupling = imported.loops[0];
  EXPECT_EQ(coupling.name, "jb");
  EXPECT_EQ(coupling.where, "rods.urdf:8");
  EXPECT_EQ(coupling.type, LoopJointType::kMimic);
  EXPECT_EQ(imported.model.bodies[coupling.body_a].joint.name, "ja");
  EXPECT_EQ(imported.model.bodies[coupling.body_b].joint.name, "jb");
  EXPECT_EQ(coupling.multiplier, -0.5);
  EXPECT_EQ(coupling.offset, 0.25);
  EXPECT_EQ(LoopJointEquations(coupling.type), 1);
  for (const std::string& warning : imported.warnings) {
    EXPECT_THAT(warning, ::testing::Not(HasSubstr("mimic")));
  }

  // phi = q_b - m q_a - o; G = [-m, 1]; no velocity product.
  LoopConstraints constraints(imported.model, imported.loops);
  ASSERT_EQ(constraints.num_rows(), 1);
  Data data(imported.model);
  const Eigen::Vector2d q(0.7, -0.3), qd(1.1, 2.0);
  BodyKinematics(imported.model, data, q);
  Eigen::VectorXd phi(1), bias(1);
  Eigen::MatrixXd G(1, 2);
  constraints.Residual(data, q, phi);
  constraints.Jacobian(data, G);
  constraints.Bias(data, qd, bias);
  EXPECT_DOUBLE_EQ(phi(0), -0.3 + 0.5 * 0.7 - 0.25);
  EXPECT_EQ(G(0, 0), 0.5);
  EXPECT_EQ(G(0, 1), 1.0);
  EXPECT_EQ(bias(0), 0.0);
  EXPECT_DOUBLE_EQ(constraints.MaxAlignment(phi), std::abs(phi(0)));  // rad: a revolute follower
  EXPECT_EQ(constraints.MaxGap(phi), 0.0);
}

TEST(UrdfMimicTest, ABadMimicIsAnErrorNamingTheJointWhenCoupled) {
  const auto error_of = [](const std::string& urdf) {
    try {
      Coupled(urdf);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error_of(TwoRods(R"(<mimic joint="nowhere"/>)")),
              HasSubstr("rods.urdf:8: joint 'jb': <mimic joint=\"nowhere\">: the model has no "
                        "moving joint of that name"));
  EXPECT_THAT(error_of(TwoRods(R"(<mimic joint="jb"/>)")), HasSubstr("cannot follow itself"));
  std::string fixed = TwoRods("", true);
  fixed.replace(fixed.find(R"(<joint name="jb" type="fixed">)"),
                std::string(R"(<joint name="jb" type="fixed">)").size(),
                R"(<joint name="jb" type="fixed"><mimic joint="ja"/>)");
  EXPECT_THAT(error_of(fixed), HasSubstr("joint 'jb': a fixed joint cannot follow joint 'ja'"));
  // Not coupled, the same files import (with the warning; a fixed joint's says to remove it).
  EXPECT_NO_THROW(ImportUrdf(TwoRods(R"(<mimic joint="nowhere"/>)"), "rods.urdf", {}, {}));
  EXPECT_THAT(::testing::PrintToString(ImportUrdf(fixed, "rods.urdf", {}, {}).warnings),
              HasSubstr("joint 'jb': <mimic> of joint 'ja' is ignored; the joint is fixed; "
                        "remove the <mimic>"));
}

RunConfig Passive(double duration) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.01;
  config.drives.assign(2, DriveConfig{});
  config.rtol = 1e-10;
  config.atol = 1e-12;
  config.q0 = Eigen::Vector2d(1.0, 0.0);
  return config;
}

constexpr char kHeldAt03[] = R"(<mimic joint="ja" multiplier="0" offset="0.3"/>)";

// Multiplier 0, offset 0.3: rod b is held at 0.3 rad on rod a, so the pair swings as rod a
// with rod b welded to it there, a model with no loop at all.
TEST(MimicRunTest, AFollowerHeldAtItsOffsetSwingsAsIfWeldedToItsLeader) {
  const UrdfImport coupled = Coupled(TwoRods(kHeldAt03));
  const UrdfImport welded = ImportUrdf(TwoRods("", true), "welded.urdf", {}, {});
  ASSERT_EQ(welded.model.num_dofs(), 1);
  RunConfig config = Passive(2.0);
  ValidateLoopRun(coupled.model, coupled.loops, config);
  const RunResult pair = SimulateLoops(coupled.model, coupled.loops, config);
  ASSERT_EQ(pair.stats.status, RunStatus::kFinished) << pair.stats.message;
  EXPECT_EQ(pair.stats.loops.cut_joints, std::vector<std::string>{"jb (mimic)"});
  EXPECT_EQ(pair.stats.loops.mobility, 1);
  RunConfig one = config;
  one.drives.resize(1);
  one.q0 = Eigen::VectorXd::Constant(1, 1.0);
  const RunResult rigid = SimulateLoops(welded.model, {}, one);
  ASSERT_EQ(rigid.stats.status, RunStatus::kFinished) << rigid.stats.message;
  ASSERT_EQ(pair.num_frames(), rigid.num_frames());
  double worst = 0.0, worst_follow = 0.0;
  for (int k = 0; k < pair.num_frames(); ++k) {
    worst = std::max(worst, std::abs(pair.q[2 * k] - rigid.q[k]));
    worst_follow = std::max(worst_follow, std::abs(pair.q[2 * k + 1] - 0.3));
  }
  EXPECT_LT(worst, 1e-7) << "the swing differs from the welded pair's";
  EXPECT_LT(worst_follow, 1e-9);
  EXPECT_GT(std::abs(rigid.q[rigid.num_frames() / 4] - 1.0), 0.1) << "nothing swung";
}

// Multiplier -0.5 and an offset: released from rest, the follower keeps to its leader at
// every frame and the pair keeps its energy.
TEST(MimicRunTest, APassiveRunHoldsTheCouplingAndKeepsItsEnergy) {
  const UrdfImport coupled =
      Coupled(TwoRods(R"(<mimic joint="ja" multiplier="-0.5" offset="0.25"/>)"));
  const RunConfig config = Passive(2.0);
  const RunResult result = SimulateLoops(coupled.model, coupled.loops, config);
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_THAT(result.stats.loops.assembly, HasSubstr("assembled by Newton"));
  double worst = 0.0, worst_rate = 0.0;
  for (int k = 0; k < result.num_frames(); ++k) {
    worst = std::max(worst, std::abs(result.q[2 * k + 1] + 0.5 * result.q[2 * k] - 0.25));
    worst_rate = std::max(worst_rate, std::abs(result.qd[2 * k + 1] + 0.5 * result.qd[2 * k]));
  }
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(worst_rate, 1e-9);
  EXPECT_LT(result.stats.energy_error_max, 1e-7);
  EXPECT_EQ(result.stats.trust, Trust::kOk);
}

// The leader prescribed: the follower is computed (a kinematic run), and the leader's effort
// carries the follower's load through the coupling: held at its offset, the welded pair's;
// with multiplier -0.5, what virtual work gives from the tree's inverse dynamics.
TEST(MimicRunTest, APrescribedLeaderCarriesItsFollowersLoad) {
  const UrdfImport coupled = Coupled(TwoRods(kHeldAt03));
  const UrdfImport welded = ImportUrdf(TwoRods("", true), "welded.urdf", {}, {});
  DriveConfig sine;
  sine.kind = DriveConfig::Kind::kPrescribed;
  sine.trajectory.kind = Trajectory::Kind::kSine;
  sine.trajectory.amplitude = {0.8};
  sine.trajectory.omega = {M_PI};
  sine.trajectory.phase = {0.0};
  RunConfig config = Passive(1.0);
  config.q0 = Eigen::VectorXd();
  config.drives[0] = sine;
  const RunResult pair = SimulateLoops(coupled.model, coupled.loops, config);
  ASSERT_EQ(pair.stats.status, RunStatus::kFinished) << pair.stats.message;
  EXPECT_EQ(pair.stats.formulation, "kinematic");
  RunConfig one = config;
  one.drives.resize(1);
  const RunResult rigid = SimulateLoops(welded.model, {}, one);
  ASSERT_EQ(rigid.stats.status, RunStatus::kFinished) << rigid.stats.message;
  ASSERT_TRUE(pair.has_torques && rigid.has_torques);
  double worst = 0.0, largest = 0.0;
  for (int k = 0; k < pair.num_frames(); ++k) {
    EXPECT_NEAR(pair.q[2 * k + 1], 0.3, 1e-12);
    worst = std::max(worst, std::abs(pair.tau[2 * k] - rigid.tau[k]));
    largest = std::max(largest, std::abs(rigid.tau[k]));
  }
  EXPECT_GT(largest, 1.0);
  EXPECT_LT(worst, 1e-9 * largest);

  // Multiplier -0.5: by virtual work the leader's effort is tau_a - 0.5 tau_b, the tree's
  // inverse dynamics along the coupled motion; the coupling's reaction is what holds the
  // follower, tau_b, a torque along its axis (world y).
  const UrdfImport halved =
      Coupled(TwoRods(R"(<mimic joint="ja" multiplier="-0.5" offset="0.25"/>)"));
  RunConfig with_reactions = config;
  with_reactions.want_loop_forces = true;
  const RunResult driven = SimulateLoops(halved.model, halved.loops, with_reactions);
  ASSERT_EQ(driven.stats.status, RunStatus::kFinished) << driven.stats.message;
  ASSERT_EQ(driven.loop_force_names, std::vector<std::string>{"jb"});
  ASSERT_EQ(driven.loop_forces.size(), 6u * static_cast<size_t>(driven.num_frames()));
  Data data(halved.model);
  double worst_work = 0.0, worst_hold = 0.0;
  for (int k = 0; k < driven.num_frames(); ++k) {
    const double t = driven.t[k], w = M_PI;
    const double qa = 0.8 * std::sin(w * t), qda = 0.8 * w * std::cos(w * t),
                 qdda = -0.8 * w * w * std::sin(w * t);
    EXPECT_NEAR(driven.q[2 * k], qa, 1e-12);
    EXPECT_NEAR(driven.q[2 * k + 1], -0.5 * qa + 0.25, 1e-12);
    const Eigen::VectorXd tau =
        Rnea(halved.model, data, Eigen::Vector2d(qa, -0.5 * qa + 0.25),
             Eigen::Vector2d(qda, -0.5 * qda), Eigen::Vector2d(qdda, -0.5 * qdda));
    worst_work = std::max(worst_work, std::abs(driven.tau[2 * k] - (tau(0) - 0.5 * tau(1))));
    const double* reaction = &driven.loop_forces[6 * static_cast<size_t>(k)];
    for (int c = 0; c < 6; ++c) {
      worst_hold = std::max(worst_hold, std::abs(reaction[c] - (c == 4 ? tau(1) : 0.0)));
    }
  }
  EXPECT_LT(worst_work, 1e-9 * largest);
  EXPECT_LT(worst_hold, 1e-9 * largest);
}

TEST(MimicRunTest, TheBodyFormulationsRefuseACouplingAndAConflictingDriveIsNamed) {
  const UrdfImport coupled = Coupled(TwoRods(R"(<mimic joint="ja"/>)"));
  try {
    CheckBodyFormulationCloses(coupled.loops);
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("rods.urdf:8: joint 'jb' follows another joint"));
    EXPECT_THAT(error.what(), HasSubstr("use formulation joint"));
  }
  // Both joints prescribed, to values the coupling cannot meet.
  DriveConfig held;
  held.kind = DriveConfig::Kind::kPrescribed;
  held.trajectory.kind = Trajectory::Kind::kSine;
  held.trajectory.offset = 0.3;
  RunConfig config = Passive(1.0);
  config.q0 = Eigen::VectorXd();
  config.drives[0] = held;
  held.trajectory.offset = -0.3;
  config.drives[1] = held;
  try {
    ValidateLoopRun(coupled.model, coupled.loops, config);
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("joint 'jb' follows joint 'ja' (<mimic>"));
    EXPECT_THAT(error.what(), HasSubstr("prescribe the leader, not the follower"));
  }
}

// Two joints that follow each other: consistent couplings are one equation (the other
// redundant: mobility 1, and the run holds them); contradicting ones are refused.
TEST(MimicRunTest, CouplingsThatFollowEachOtherAreRedundantOrRefused) {
  const auto cycle = [](const std::string& back_offset) {
    std::string urdf = TwoRods(R"(<mimic joint="ja" multiplier="-0.5" offset="0.25"/>)");
    const std::string ja_axis = R"(<child link="a"/><axis xyz="0 1 0"/>)";
    urdf.replace(
        urdf.find(ja_axis), ja_axis.size(),
        ja_axis + R"(<mimic joint="jb" multiplier="-2" offset=")" + back_offset + R"("/>)");
    return Coupled(urdf);
  };
  const UrdfImport consistent = cycle("0.5");  // q_a = -2 q_b + 0.5, the same line
  ASSERT_EQ(consistent.loops.size(), 2u);
  const RunResult result = SimulateLoops(consistent.model, consistent.loops, Passive(1.0));
  ASSERT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_EQ(result.stats.loops.equations, 2);
  EXPECT_EQ(result.stats.loops.independent, 1);
  EXPECT_EQ(result.stats.loops.mobility, 1);
  for (int k = 0; k < result.num_frames(); ++k) {
    EXPECT_NEAR(result.q[2 * k + 1], -0.5 * result.q[2 * k] + 0.25, 1e-10);
  }
  const UrdfImport contradicting = cycle("0.9");
  try {
    ValidateLoopRun(contradicting.model, contradicting.loops, Passive(1.0));
    FAIL() << "accepted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("couplings that contradict each other"));
  }
}

}  // namespace
}  // namespace mbstream
