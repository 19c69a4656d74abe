// Closed loops whose spanning tree has free bodies or ball joints (issue 43): the loop
// constraints in velocity space (nv columns), Newton steps that move q on its manifold, the
// projected ODE with y = [q (nq); v (nv)]. Each mechanism is run against the same mechanism
// modelled with a tree of revolute joints (an independent modelling: no quaternion, no cut
// joint where the tree has a joint):
// - a pendulum as a free body hung from the world by a cut revolute joint;
// - the shipped four-bar with its coupler a free body, closed by two cut revolute joints;
// - the four-bar with its crank-coupler joint a ball joint of the tree (the cut revolute at
//   the rocker keeps the coupler in the plane), and a ball pendulum whose bob a coaxial cut
//   revolute turns into a revolute pendulum (the cut joint's three gap rows redundant);
// and the quaternions' norms, the loops' drift and the refusals (ida, body formulations).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/kinematics/forward_kinematics.h"
#include "server/model/model_builder.h"
#include "server/parse/sdf_import.h"
#include "server/sim/closed_loop_ode.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_trust.h"
#include "shared/common/check.h"
#include "tests/common/allocation_counter.h"

namespace mbstream {
namespace {

const std::string kFourBar = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/four_bar.sdf";

RunConfig Config(const Model& model, Method method, double rtol, double duration) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.01;
  config.formulation = Formulation::kJoint;
  config.method = method;
  config.rtol = rtol;
  config.atol = rtol / 100.0;
  config.drives.assign(static_cast<size_t>(model.nv()), DriveConfig{});
  return config;
}

// The quaternion (qw qx qy qz) of R.
Eigen::Vector4d QuaternionOf(const Matrix3d& R) {
  const Eigen::Quaterniond quat(R);
  return {quat.w(), quat.x(), quat.y(), quat.z()};
}

Matrix3d RotationOf(const double* quat) {
  return Eigen::Quaterniond(quat[0], quat[1], quat[2], quat[3]).toRotationMatrix();
}

// The largest | |quat| - 1 | of the recorded frames' quaternions starting at `k` in q.
double FrameQuaternionError(const RunResult& result, int k) {
  double worst = 0.0;
  const int width = result.positions();
  for (size_t f = 0; f < result.t.size(); ++f) {
    const double* quat = result.q.data() + f * static_cast<size_t>(width) + k;
    worst =
        std::max(worst, std::abs(Eigen::Vector4d(quat[0], quat[1], quat[2], quat[3]).norm() - 1.0));
  }
  return worst;
}

// --- The pendulum -------------------------------------------------------------------------

// The pivot 1 m up, the joint frame turned 0.3 rad about x, the axis y of the joint frame; a
// bob of general inertia whose centre of mass is off the axis.
const Pose kPivot{Eigen::AngleAxisd(0.3, Vector3d::UnitX()).toRotationMatrix(),
                  Vector3d(0.0, 0.0, 1.0)};
const Vector3d kAxis = Vector3d::UnitY();

RigidInertia BobInertia() {
  Matrix3d I;
  I << 0.02, 0.001, 0.0, 0.001, 0.03, 0.002, 0.0, 0.002, 0.04;
  return RigidInertia{1.5, Vector3d(0.1, 0.05, -0.5), I};
}

Model TreePendulum() {
  ModelBuilder builder("pendulum", "world");
  Joint joint;
  joint.name = "hinge";
  joint.type = JointType::kRevolute;
  joint.X_PJ = kPivot;
  joint.axis = kAxis;
  builder.AddMovingLink("bob", "world", joint, BobInertia());
  return builder.Build();
}

// The bob a free body; the hinge a cut revolute joint between the world and the bob.
Model FreePendulum(std::vector<LoopClosure>* loops) {
  ModelBuilder builder("free_pendulum", "world");
  builder.AddFreeLink("bob", "bob", kPivot, BobInertia());
  LoopClosure hinge;
  hinge.name = "hinge";
  hinge.where = "test";
  hinge.type = LoopJointType::kRevolute;
  hinge.body_a = kBase;
  hinge.X_AJ = kPivot;
  hinge.body_b = 0;
  hinge.X_BJ = Pose::Identity();
  hinge.axis = kAxis;
  loops->push_back(hinge);
  return builder.Build();
}

// The free bob's state at hinge angle theta and rate omega: its frame the joint frame turned
// about the axis, its origin on the axis (at rest), w_B = omega * axis in the body.
void FreeBobState(double theta, double omega, Eigen::VectorXd* q, Eigen::VectorXd* v) {
  const Matrix3d R = kPivot.R * Eigen::AngleAxisd(theta, kAxis).toRotationMatrix();
  q->resize(7);
  *q << kPivot.p, QuaternionOf(R);
  v->resize(6);
  *v << 0.0, 0.0, 0.0, omega * kAxis;
}

// The free body's hinge angle from its quaternion (the rotation about the axis from the
// joint frame), continued from `last`.
double HingeAngle(const double* quat, double last) {
  const Matrix3d R = kPivot.R.transpose() * RotationOf(quat);
  const Vector3d u = Vector3d::UnitX();
  const double angle = std::atan2(kAxis.dot(u.cross(R * u)), u.dot(R * u));
  return angle + 2.0 * M_PI * std::round((last - angle) / (2.0 * M_PI));
}

TEST(FreeLoopTest, AFreeBodyHungByACutRevoluteIsTheTreePendulum) {
  const double theta0 = 0.7, omega0 = 1.5;
  const Model tree = TreePendulum();
  RunConfig tree_config = Config(tree, Method::kErk, 1e-13, 3.0);
  tree_config.q0 = Eigen::VectorXd::Constant(1, theta0);
  tree_config.qd0 = Eigen::VectorXd::Constant(1, omega0);
  const RunResult a = SimulateLoops(tree, {}, tree_config);
  ASSERT_EQ(a.stats.status, RunStatus::kFinished) << a.stats.message;

  std::vector<LoopClosure> loops;
  const Model free = FreePendulum(&loops);
  ASSERT_EQ(free.nq(), 7);
  ASSERT_EQ(free.nv(), 6);
  for (const Method method : {Method::kBdf, Method::kAdams, Method::kErk}) {
    SCOPED_TRACE(MethodName(method));
    // ERK at rtol 1e-10; BDF and Adams, whose error at 1e-10 is 2e-9 rad, at 1e-11 (atol 1e-13).
    RunConfig config = Config(free, method,
                              method == Method::kErk   ? 1e-10
                              : method == Method::kBdf ? 1e-12
                                                       : 1e-11,
                              3.0);
    config.atol = method == Method::kErk ? 1e-12 : 1e-13;
    FreeBobState(theta0, omega0, &config.q0, &config.qd0);
    ASSERT_NO_THROW(ValidateLoopRun(free, loops, config));
    const RunResult b = SimulateLoops(free, loops, config);
    ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
    EXPECT_EQ(b.stats.loops.equations, 5);
    EXPECT_EQ(b.stats.loops.independent, 5);
    EXPECT_EQ(b.stats.loops.mobility, 1);
    ASSERT_EQ(b.t.size(), a.t.size());
    ASSERT_EQ(b.positions(), 8);  // x y z qw qx qy qz, the cut hinge's angle
    ASSERT_EQ(b.num_dofs, 7);     // vx vy vz wx wy wz, the hinge's rate
    double angle_error = 0.0, column_error = 0.0, rate_error = 0.0, origin_error = 0.0;
    double last = theta0;
    for (size_t f = 0; f < a.t.size(); ++f) {
      const double* q = b.q.data() + 8 * f;
      last = HingeAngle(q + 3, last);
      angle_error = std::max(angle_error, std::abs(last - a.q[f]));
      column_error = std::max(column_error, std::abs(q[7] - a.q[f]));
      rate_error = std::max(rate_error, std::abs(b.qd[7 * f + 6] - a.qd[f]));
      origin_error = std::max(origin_error, (Vector3d(q[0], q[1], q[2]) - kPivot.p).norm());
    }
    RecordProperty(std::string(MethodName(method)) + "_angle_error", std::to_string(angle_error));
    std::printf(
        "%s: angle %.3g, column %.3g, rate %.3g, origin %.3g m, quaternion %.3g, "
        "drift %.3g m %.3g rad, energy %.3g, steps %ld\n",
        MethodName(method), angle_error, column_error, rate_error, origin_error,
        b.stats.quaternion_norm_error_max, b.stats.drift_position_max,
        b.stats.drift_orientation_max, b.stats.energy_error_max, b.stats.solver.steps);
    EXPECT_LT(angle_error, 1e-9);
    EXPECT_LT(column_error, 1e-9);
    EXPECT_LT(rate_error, 1e-8);
    EXPECT_LT(origin_error, 1e-9);
    // The frames' quaternions are unit to round-off; the integrator's own states at the frames
    // (interpolants between the projected steps) within the tolerance.
    EXPECT_LT(FrameQuaternionError(b, 3), 1e-15);
    EXPECT_GE(b.stats.quaternion_norm_error_max, 0.0);
    EXPECT_LT(b.stats.quaternion_norm_error_max, 10 * config.rtol);
    EXPECT_LT(b.stats.energy_error_max, 1e-8);
    EXPECT_EQ(b.stats.trust, Trust::kOk) << b.stats.trust_reason;
    if (method == Method::kBdf) {  // projected onto the loops after each step
      EXPECT_LT(b.stats.drift_position_max, 1e-12);
      EXPECT_LT(b.stats.drift_orientation_max, 1e-12);
    }
  }
}

TEST(FreeLoopTest, AssemblyMovesAFreeBodyOntoItsLoopOnTheManifold) {
  std::vector<LoopClosure> loops;
  const Model free = FreePendulum(&loops);
  RunConfig config = Config(free, Method::kBdf, 1e-10, 0.05);
  FreeBobState(0.4, 0.0, &config.q0, &config.qd0);
  // Off the hinge by 2 cm and 0.05 rad about a tilted axis; the quaternion still unit.
  config.q0.head<3>() += Vector3d(0.02, -0.01, 0.015);
  const Matrix3d off = RotationOf(config.q0.data() + 3) *
                       Eigen::AngleAxisd(0.05, Vector3d(1, 0, 1).normalized()).toRotationMatrix();
  config.q0.tail<4>() = QuaternionOf(off);
  config.qd0 << 0.1, 0.0, -0.2, 0.3, 1.0, 0.0;  // not along the hinge
  const RunResult b = SimulateLoops(free, loops, config);
  ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
  EXPECT_NE(b.stats.loops.assembly.find("assembled by Newton"), std::string::npos)
      << b.stats.loops.assembly;
  // The first frame: the origin on the pivot, the body's x y z axes turned about the hinge
  // only, its velocity a turn about the hinge.
  const double* q = b.q.data();
  EXPECT_LT((Vector3d(q[0], q[1], q[2]) - kPivot.p).norm(), 1e-12);
  const Matrix3d R = kPivot.R.transpose() * RotationOf(q + 3);
  EXPECT_LT((R * kAxis - kAxis).norm(), 1e-12);
  EXPECT_NEAR(Eigen::Vector4d(q[3], q[4], q[5], q[6]).norm(), 1.0, 1e-15);
  EXPECT_LT(Vector3d(b.qd[0], b.qd[1], b.qd[2]).norm(), 1e-12);
  EXPECT_LT(Vector3d(b.qd[3], b.qd[4], b.qd[5]).cross(kAxis).norm(), 1e-12);
}

// --- The four-bar -------------------------------------------------------------------------

struct FourBar {
  Model model;
  std::vector<LoopClosure> loops;
};

const Body& BodyNamed(const Model& model, const std::string& name) {
  const int i = model.FindBody(name);
  MBSTREAM_CHECK_MSG(i >= 0, name);
  return model.bodies[static_cast<size_t>(i)];
}

// The shipped four-bar's cut joint (coupler to rocker) for `model`, its bodies by name.
LoopClosure RemappedLoop(const SdfImport& sdf, const Model& model) {
  LoopClosure loop = sdf.loops.at(0);
  loop.body_a = model.FindBody(sdf.model.bodies[loop.body_a].name);
  loop.body_b = model.FindBody(sdf.model.bodies[loop.body_b].name);
  return loop;
}

void AddLinkOf(const SdfImport& sdf, const std::string& link, ModelBuilder* builder) {
  const Body& body = BodyNamed(sdf.model, link);
  const std::string parent =
      body.parent == kBase ? "world" : sdf.model.bodies[static_cast<size_t>(body.parent)].name;
  builder->AddMovingLink(link, parent, body.joint, body.inertia);
}

// The coupler a free body at its drawn pose; the crank-coupler joint a second cut revolute.
FourBar FreeCouplerFourBar(const SdfImport& sdf) {
  const Model& tree = sdf.model;
  Data data(tree);
  BodyKinematics(tree, data, Eigen::VectorXd::Zero(tree.nq()));
  const Body& coupler = BodyNamed(tree, "coupler");
  const int c = tree.FindBody("coupler");
  ModelBuilder builder("four_bar_free_coupler", "world");
  AddLinkOf(sdf, "crank", &builder);
  AddLinkOf(sdf, "rocker", &builder);
  builder.AddFreeLink("coupler", "coupler", data.X_world[static_cast<size_t>(c)], coupler.inertia);
  FourBar bar{builder.Build(), {}};
  LoopClosure pin;
  pin.name = coupler.joint.name;
  pin.where = "test";
  pin.type = LoopJointType::kRevolute;
  pin.body_a = bar.model.FindBody("crank");
  pin.X_AJ = coupler.joint.X_PJ;
  pin.body_b = bar.model.FindBody("coupler");
  pin.X_BJ = Pose::Identity();  // the coupler's frame is its joint's
  pin.axis = coupler.joint.axis;
  bar.loops = {pin, RemappedLoop(sdf, bar.model)};
  return bar;
}

// The crank-coupler joint a ball joint of the tree at the same centre.
FourBar BallCouplerFourBar(const SdfImport& sdf) {
  const Body& coupler = BodyNamed(sdf.model, "coupler");
  ModelBuilder builder("four_bar_ball_coupler", "world");
  AddLinkOf(sdf, "crank", &builder);
  AddLinkOf(sdf, "rocker", &builder);
  builder.AddBallLink("coupler", "crank", coupler.joint.name, coupler.joint.X_PJ, coupler.inertia);
  FourBar bar{builder.Build(), {}};
  bar.loops = {RemappedLoop(sdf, bar.model)};
  return bar;
}

// The four-bar released at rest at its drawn pose, 2 s under gravity (at rest: the start is
// the same state in every modelling; a velocity would be projected onto the loops by the
// minimal change, which depends on the coordinates).
RunConfig FourBarConfig(const Model& model, Method method, double rtol) {
  return Config(model, method, rtol, 2.0);
}

// The tree four-bar's reference run: ERK at rtol 1e-13. (Its motion under gravity is
// sensitive: BDF at rtol 1e-11 is 3.9e-7 rad from Simbody, docs/closed_loops.md, and from this
// reference; ERK at 1e-12 and Adams at 1e-13 are 1e-10 and 2e-9 rad from it.)
RunResult FourBarReference(const SdfImport& sdf) {
  const RunResult a =
      SimulateLoops(sdf.model, sdf.loops, FourBarConfig(sdf.model, Method::kErk, 1e-13));
  MBSTREAM_CHECK_MSG(a.stats.status == RunStatus::kFinished, a.stats.message);
  return a;
}

struct MethodAndTolerance {
  Method method;
  double rtol;
};
constexpr MethodAndTolerance kFourBarRuns[] = {{Method::kErk, 1e-12}, {Method::kAdams, 1e-13}};

// The crank's and rocker's angles, and the coupler's world pose, of two runs' frames.
struct Difference {
  double joints = 0.0;     // rad
  double coupler_p = 0.0;  // m
  double coupler_R = 0.0;  // Frobenius norm of the rotations' difference
};

Difference Compare(const Model& model_a, const RunResult& a, const Model& model_b,
                   const RunResult& b) {
  Difference d;
  Data data_a(model_a), data_b(model_b);
  const int ca = model_a.FindBody("coupler"), cb = model_b.FindBody("coupler");
  for (size_t f = 0; f < a.t.size(); ++f) {
    const Eigen::VectorXd qa = Eigen::Map<const Eigen::VectorXd>(
        a.q.data() + f * static_cast<size_t>(a.positions()), model_a.nq());
    const Eigen::VectorXd qb = Eigen::Map<const Eigen::VectorXd>(
        b.q.data() + f * static_cast<size_t>(b.positions()), model_b.nq());
    for (const char* joint : {"crank", "rocker"}) {
      d.joints = std::max(d.joints, std::abs(qa(BodyNamed(model_a, joint).q_index) -
                                             qb(BodyNamed(model_b, joint).q_index)));
    }
    BodyKinematics(model_a, data_a, qa);
    BodyKinematics(model_b, data_b, qb);
    const Pose& Xa = data_a.X_world[static_cast<size_t>(ca)];
    const Pose& Xb = data_b.X_world[static_cast<size_t>(cb)];
    d.coupler_p = std::max(d.coupler_p, (Xa.p - Xb.p).norm());
    d.coupler_R = std::max(d.coupler_R, (Xa.R - Xb.R).norm());
  }
  return d;
}

TEST(FreeLoopTest, AFourBarWithAFreeCouplerIsTheTreeFourBar) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  ASSERT_EQ(sdf.loops.size(), 1u);
  const RunResult a = FourBarReference(sdf);
  const FourBar bar = FreeCouplerFourBar(sdf);
  ASSERT_EQ(bar.model.nq(), 9);
  ASSERT_EQ(bar.model.nv(), 8);
  for (const MethodAndTolerance& run : kFourBarRuns) {
    SCOPED_TRACE(MethodName(run.method));
    const RunConfig config = FourBarConfig(bar.model, run.method, run.rtol);
    ASSERT_NO_THROW(ValidateLoopRun(bar.model, bar.loops, config));
    const RunResult b = SimulateLoops(bar.model, bar.loops, config);
    ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
    EXPECT_EQ(b.stats.loops.equations, 10);
    EXPECT_EQ(b.stats.loops.mobility, 1);  // planar: 3 of the 10 rows are redundant
    ASSERT_EQ(b.t.size(), a.t.size());
    const Difference d = Compare(sdf.model, a, bar.model, b);
    std::printf(
        "free coupler (%s, rtol %g): joints %.3g rad, coupler %.3g m %.3g; quaternion "
        "%.3g, drift %.3g m %.3g rad %.3g, energy %.3g, steps %ld\n",
        MethodName(run.method), run.rtol, d.joints, d.coupler_p, d.coupler_R,
        b.stats.quaternion_norm_error_max, b.stats.drift_position_max,
        b.stats.drift_orientation_max, b.stats.drift_velocity_max, b.stats.energy_error_max,
        b.stats.solver.steps);
    EXPECT_LT(d.joints, 1e-8);
    EXPECT_LT(d.coupler_p, 1e-8);
    EXPECT_LT(d.coupler_R, 1e-8);
    EXPECT_LT(FrameQuaternionError(b, BodyNamed(bar.model, "coupler").q_index + 3), 1e-15);
    EXPECT_LT(b.stats.quaternion_norm_error_max, 1e-12);
    EXPECT_LT(b.stats.drift_position_max, 1e-10);
    EXPECT_LT(b.stats.energy_error_max, 1e-10);
    EXPECT_EQ(b.stats.trust, Trust::kOk) << b.stats.trust_reason;
  }
}

TEST(FreeLoopTest, AFourBarWithABallJointInItsTreeIsTheTreeFourBar) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const RunResult a = FourBarReference(sdf);
  const FourBar bar = BallCouplerFourBar(sdf);
  ASSERT_EQ(bar.model.nq(), 6);
  ASSERT_EQ(bar.model.nv(), 5);
  for (const MethodAndTolerance& run : kFourBarRuns) {
    SCOPED_TRACE(MethodName(run.method));
    const RunConfig config = FourBarConfig(bar.model, run.method, run.rtol);
    ASSERT_NO_THROW(ValidateLoopRun(bar.model, bar.loops, config));
    const RunResult b = SimulateLoops(bar.model, bar.loops, config);
    ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
    EXPECT_EQ(b.stats.loops.equations, 5);
    EXPECT_EQ(b.stats.loops.independent, 4);
    EXPECT_EQ(b.stats.loops.mobility, 1);
    const Difference d = Compare(sdf.model, a, bar.model, b);
    std::printf(
        "ball coupler (%s, rtol %g): joints %.3g rad, coupler %.3g m %.3g; quaternion "
        "%.3g, drift %.3g m %.3g rad, energy %.3g, steps %ld\n",
        MethodName(run.method), run.rtol, d.joints, d.coupler_p, d.coupler_R,
        b.stats.quaternion_norm_error_max, b.stats.drift_position_max,
        b.stats.drift_orientation_max, b.stats.energy_error_max, b.stats.solver.steps);
    EXPECT_LT(d.joints, 1e-8);
    EXPECT_LT(d.coupler_p, 1e-8);
    EXPECT_LT(d.coupler_R, 1e-8);
    EXPECT_LT(FrameQuaternionError(b, BodyNamed(bar.model, "coupler").q_index), 1e-15);
    EXPECT_LT(b.stats.quaternion_norm_error_max, 1e-12);
    EXPECT_EQ(b.stats.trust, Trust::kOk) << b.stats.trust_reason;
  }
}

// The same from SDFormat (tests/data/loops/four_bar_ball.sdf: the shipped four-bar's
// coupler_joint of type ball): imported as a ball joint of the tree and a cut revolute, its
// results named by position and velocity coordinate, then the cut joint's column.
TEST(FreeLoopTest, AnSdfFourBarWithABallJointInItsTreeIsTheTreeFourBar) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const RunResult a = FourBarReference(sdf);
  const SdfImport ball =
      ImportSdfFile(std::string(MBSTREAM_SOURCE_DIR) + "/tests/data/loops/four_bar_ball.sdf");
  ASSERT_EQ(ball.model.ball_bodies.size(), 1u);
  ASSERT_EQ(ball.loops.size(), 1u);
  const RunConfig config = FourBarConfig(ball.model, Method::kErk, 1e-12);
  ASSERT_NO_THROW(ValidateLoopRun(ball.model, ball.loops, config));
  const RunResult b = SimulateLoops(ball.model, ball.loops, config);
  ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
  const std::vector<std::string> positions = {
      "crank_joint",      "rocker_joint",     "coupler_joint.qw", "coupler_joint.qx",
      "coupler_joint.qy", "coupler_joint.qz", "loop_joint"};
  const std::vector<std::string> velocities = {"crank_joint",      "rocker_joint",
                                               "coupler_joint.wx", "coupler_joint.wy",
                                               "coupler_joint.wz", "loop_joint"};
  EXPECT_EQ(b.position_names, positions);
  EXPECT_EQ(b.joint_names, velocities);
  EXPECT_EQ(b.position_index, (std::vector<int>{0, 1, -1, -1, -1, 6}));
  const Difference d = Compare(sdf.model, a, ball.model, b);
  EXPECT_LT(d.joints, 1e-8);
  EXPECT_LT(d.coupler_R, 1e-8);
  // The cut joint's column is the coupler's angle relative to the rocker: the tree four-bar
  // has it as a cut joint too.
  double cut = 0.0;
  for (size_t f = 0; f < a.t.size(); ++f) {
    cut = std::max(cut, std::abs(b.q[f * 7 + 6] - a.q[f * static_cast<size_t>(a.num_dofs) + 3]));
  }
  EXPECT_LT(cut, 1e-8);
}

// Driven: the crank prescribed at one turn per second, formulation kinematic (Newton on the
// loops at each frame, now on the manifold): the free coupler's pose, the rocker's angle and
// the crank's effort are the tree four-bar's.
TEST(FreeLoopTest, ADrivenFourBarWithAFreeCouplerIsSolvedFrameByFrameAsTheTreeFourBar) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const FourBar bar = FreeCouplerFourBar(sdf);
  DriveConfig crank;
  crank.kind = DriveConfig::Kind::kPrescribed;
  crank.trajectory.kind = Trajectory::Kind::kSpline;
  crank.trajectory.times = {-1.0, 3.0};
  crank.trajectory.values = {-2.0 * M_PI, 6.0 * M_PI};
  RunResult runs[2];
  for (int k = 0; k < 2; ++k) {
    const Model& model = k == 0 ? sdf.model : bar.model;
    const std::vector<LoopClosure>& loops = k == 0 ? sdf.loops : bar.loops;
    RunConfig config = FourBarConfig(model, Method::kBdf, 1e-10);
    config.formulation = Formulation::kKinematic;
    config.want_torques = true;
    config.drives[static_cast<size_t>(BodyNamed(model, "crank").v_index)] = crank;
    ASSERT_EQ(ValidateLoopRun(model, loops, config).formulation, Formulation::kKinematic);
    runs[k] = SimulateLoops(model, loops, config);
    ASSERT_EQ(runs[k].stats.status, RunStatus::kFinished) << runs[k].stats.message;
  }
  const Difference d = Compare(sdf.model, runs[0], bar.model, runs[1]);
  double effort = 0.0, largest = 0.0;
  const int ca = BodyNamed(sdf.model, "crank").v_index, cb = BodyNamed(bar.model, "crank").v_index;
  for (size_t f = 0; f < runs[0].t.size(); ++f) {
    const double ta = runs[0].tau[f * static_cast<size_t>(runs[0].num_dofs) + ca];
    const double tb = runs[1].tau[f * static_cast<size_t>(runs[1].num_dofs) + cb];
    effort = std::max(effort, std::abs(ta - tb));
    largest = std::max(largest, std::abs(ta));
  }
  std::printf(
      "driven free coupler: joints %.3g rad, coupler %.3g m %.3g, crank effort %.3g of "
      "%.3g N*m, drift %.3g m\n",
      d.joints, d.coupler_p, d.coupler_R, effort, largest, runs[1].stats.drift_position_max);
  EXPECT_LT(d.joints, 1e-10);
  EXPECT_LT(d.coupler_p, 1e-10);
  EXPECT_LT(d.coupler_R, 1e-10);
  EXPECT_LT(effort, 1e-8 * largest);
  EXPECT_LT(FrameQuaternionError(runs[1], BodyNamed(bar.model, "coupler").q_index + 3), 1e-15);
}

// A ball pendulum whose bob a cut revolute joint at the same centre, about the tree
// pendulum's axis, turns into that revolute pendulum: the cut joint's three gap rows hold
// identically (the ball joint keeps the centre), two alignment rows remain.
TEST(FreeLoopTest, ABallPendulumTiedByACoaxialCutRevoluteIsTheTreePendulum) {
  const double theta0 = -0.9, omega0 = 2.5;
  const Model tree = TreePendulum();
  RunConfig tree_config = Config(tree, Method::kBdf, 1e-11, 3.0);
  tree_config.q0 = Eigen::VectorXd::Constant(1, theta0);
  tree_config.qd0 = Eigen::VectorXd::Constant(1, omega0);
  const RunResult a = SimulateLoops(tree, {}, tree_config);
  ASSERT_EQ(a.stats.status, RunStatus::kFinished) << a.stats.message;

  ModelBuilder builder("ball_pendulum", "world");
  builder.AddBallLink("bob", "world", "ball", kPivot, BobInertia());
  const Model ball = builder.Build();
  LoopClosure hinge;
  hinge.name = "hinge";
  hinge.where = "test";
  hinge.body_a = kBase;
  hinge.X_AJ = kPivot;
  hinge.body_b = 0;
  hinge.axis = kAxis;
  const std::vector<LoopClosure> loops = {hinge};
  RunConfig config = Config(ball, Method::kBdf, 1e-11, 3.0);
  config.q0 = QuaternionOf(Eigen::AngleAxisd(theta0, kAxis).toRotationMatrix());
  config.qd0 = omega0 * kAxis;
  const RunResult b = SimulateLoops(ball, loops, config);
  ASSERT_EQ(b.stats.status, RunStatus::kFinished) << b.stats.message;
  EXPECT_EQ(b.stats.loops.equations, 5);
  EXPECT_EQ(b.stats.loops.independent, 2);
  EXPECT_EQ(b.stats.loops.mobility, 1);
  ASSERT_EQ(b.positions(), 5);  // qw qx qy qz, the hinge's angle
  double error = 0.0, last = theta0;
  for (size_t f = 0; f < a.t.size(); ++f) {
    // The ball's quaternion is R_JB: the hinge angle about the axis of J.
    const Matrix3d R = RotationOf(b.q.data() + 5 * f);
    const Vector3d u = Vector3d::UnitX();
    double angle = std::atan2(kAxis.dot(u.cross(R * u)), u.dot(R * u));
    angle += 2.0 * M_PI * std::round((last - angle) / (2.0 * M_PI));
    last = angle;
    error = std::max(error, std::abs(angle - a.q[f]));
    error = std::max(error, std::abs(b.q[5 * f + 4] - a.q[f]));  // the cut joint's column
  }
  std::printf("ball pendulum: angle %.3g rad, quaternion %.3g, drift %.3g rad, energy %.3g\n",
              error, b.stats.quaternion_norm_error_max, b.stats.drift_orientation_max,
              b.stats.energy_error_max);
  EXPECT_LT(error, 1e-8);
  EXPECT_LT(FrameQuaternionError(b, 0), 1e-15);
  EXPECT_LT(b.stats.quaternion_norm_error_max, config.rtol);
  EXPECT_EQ(b.stats.trust, Trust::kOk) << b.stats.trust_reason;
}

// The ODE's right-hand side, its projection (Newton on the manifold) and its per-step
// quaternion normalisation allocate nothing; the projection closes both loops and puts the
// quaternion back on the unit sphere.
TEST(FreeLoopTest, TheOdeWithAFreeCouplerStepsWithoutAllocatingAndProjectsOntoTheManifold) {
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const FourBar bar = FreeCouplerFourBar(sdf);
  const RunConfig config = FourBarConfig(bar.model, Method::kBdf, 1e-10);
  const DriveSet drives(bar.model, config.drives);
  Eigen::VectorXd q0(bar.model.nq());
  NeutralPositions(bar.model, q0.data());
  ClosedLoopOde ode(bar.model, bar.loops, drives, q0, config.baumgarte, 1e-12);
  ASSERT_EQ(ode.size(), 17);
  ASSERT_EQ(ode.num_positions(), 9);
  ASSERT_EQ(ode.num_velocities(), 8);
  ASSERT_TRUE(ode.ProjectsEveryMethod());
  // Off the loops by millimetres and milliradians, the quaternion 1e-4 off unit length.
  const int c = BodyNamed(bar.model, "coupler").q_index;
  Eigen::VectorXd y(17), ydot(17), correction(17);
  y << q0, Eigen::VectorXd::Zero(8);
  y(0) += 0.003;
  y(c) += 0.002;
  y(c + 2) -= 0.001;
  y.segment<4>(c + 3) *= 1.0001;
  y.tail(8) << 0.5, -0.2, 0.01, 0.02, 0.0, 0.1, 0.3, -0.1;
  Eigen::VectorXd normalised = y;
  const long before = testing::AllocationCount();
  const int rhs = ode.Rhs(0.0, y.data(), ydot.data());
  const int project = ode.Project(0.0, y.data(), correction.data());
  const int in_place = ode.ProjectInPlace(0.0, normalised.data());
  EXPECT_EQ(testing::AllocationCount() - before, 0);
  EXPECT_EQ(rhs, 0);
  EXPECT_EQ(project, 0);
  EXPECT_EQ(in_place, 0);
  EXPECT_TRUE(ydot.allFinite());
  EXPECT_NEAR(normalised.segment<4>(c + 3).norm(), 1.0, 1e-15);
  // The projected state: on the loops (phi = 0, G v = 0) with a unit quaternion.
  const Eigen::VectorXd projected = y + correction;
  EXPECT_NEAR(projected.segment<4>(c + 3).norm(), 1.0, 1e-15);
  ASSERT_TRUE(ode.Evaluate(0.0, projected.data()));
  double gap = 0.0, alignment = 0.0, velocity = 0.0;
  ode.Residuals(&gap, &alignment, &velocity);
  EXPECT_LT(gap, 1e-12);
  EXPECT_LT(alignment, 1e-12);
  EXPECT_LT(velocity, 1e-12);
  // The quaternion's rate is q' = 1/2 quat (x) (0, w_B): orthogonal to quat.
  EXPECT_LT(std::abs(ydot.segment<4>(c + 3).dot(y.segment<4>(c + 3).normalized())), 1e-14);
}

// --- What stays refused -------------------------------------------------------------------

TEST(FreeLoopTest, IdaAndTheBodyFormulationsAreRefusedNamingTheJoint) {
  std::vector<LoopClosure> loops;
  const Model free = FreePendulum(&loops);
  const SdfImport sdf = ImportSdfFile(kFourBar);
  const FourBar bar = BallCouplerFourBar(sdf);
  struct Case {
    const Model& model;
    const std::vector<LoopClosure>& loops;
    Formulation formulation;
    Method method;
    const char* joint;
    const char* instead;
  };
  const Case cases[] = {
      {free, loops, Formulation::kJoint, Method::kIda, "free joint 'bob'", "use method bdf"},
      {free, loops, Formulation::kBodyIndex2, Method::kIda, "free joint 'bob'",
       "use formulation joint"},
      {bar.model, bar.loops, Formulation::kJoint, Method::kIda, "ball joint 'coupler_joint'",
       "use method bdf"},
      {bar.model, bar.loops, Formulation::kBodyBaumgarte, Method::kBdf,
       "ball joint 'coupler_joint'", "use formulation joint"},
  };
  for (const Case& c : cases) {
    RunConfig config = Config(c.model, c.method, 1e-8, 0.1);
    config.formulation = c.formulation;
    try {
      ValidateLoopRun(c.model, c.loops, config);
      ADD_FAILURE() << "accepted: " << c.joint << " " << MethodName(c.method);
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(c.joint), std::string::npos) << message;
      EXPECT_NE(message.find(c.instead), std::string::npos) << message;
      EXPECT_NE(message.find("closed loops"), std::string::npos) << message;
    }
  }
  // A drive on a free joint's coordinate (a prescribed pose: not a loop constraint yet).
  RunConfig config = Config(free, Method::kBdf, 1e-8, 0.1);
  config.drives[2].kind = DriveConfig::Kind::kPrescribed;
  try {
    ValidateLoopRun(free, loops, config);
    ADD_FAILURE() << "accepted a drive on the free joint";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("free joint 'bob'"), std::string::npos) << message;
    EXPECT_NE(message.find("leave it passive"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace mbstream
