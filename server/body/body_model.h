// The constant description of a mechanism in body coordinates: every moving link a free
// rigid body (centre-of-mass position in the base frame, orientation quaternion, linear
// velocity of the centre of mass in the base frame, angular velocity in the body frame),
// every joint a set of constraints with Lagrange multipliers. Built once per run.
//
// State layout (n bodies, m constraint rows):
//   y = [ x_0 (3), e_0 (4), ..., x_{n-1}, e_{n-1}      positions, 7n
//         v_0 (3), w_0 (3), ..., v_{n-1}, w_{n-1}      velocities nu, 6n
//         lambda (m) ]                                  multipliers (DAE variants only)
// A revolute joint has 5 rows (3 for the common joint point, base frame; 2 keeping the axes
// aligned) and a sixth when it is prescribed (the rheonomic drive constraint, whose
// multiplier is the drive torque). A prismatic joint has 5 rows too (3 locking the relative
// orientation; 2 keeping the child's origin on the axis line) and a sixth, the prescribed
// displacement along the axis, whose multiplier is the drive force.
//
// A mechanism with closed loops adds its cut joints (server/model/loop_closure.h) as more
// joints between two bodies (BodyModel::cuts): a revolute or prismatic one has the same 5
// rows as in the tree, a ball joint the 3 joint-point rows. Their rows are dependent when the
// mechanism is (a planar loop of spatial revolutes): SelectCutRows (body_cuts.h) keeps the
// independent ones at the initial pose, after the tree's, and the dropped rows stay satisfied
// (their residual is still measured).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "server/drives/drive_set.h"
#include "server/math/spatial.h"
#include "server/model/model.h"

namespace mbstream {

struct BodyJoint {
  JointType type = JointType::kRevolute;
  int parent = kBase;  // body index, or kBase
  int child = 0;       // the body this joint moves (= the joint's index)
  Vector3d d_P;        // joint point (origin of J) from the parent's centre of mass, parent frame
  Vector3d d_B;        // the child's origin from its centre of mass, child frame (m)
  Vector3d a_P;        // joint axis in the parent frame
  Vector3d a;          // joint axis in the child frame
  Vector3d u1, u2;     // unit vectors perpendicular to a in the child frame, u2 = a x u1
  Matrix3d R_PJ;       // the joint frame (the child frame at q = 0) in the parent frame
  Matrix3d R_BJ = Matrix3d::Identity();  // the joint frame in the child frame (a cut joint's)
  bool ball = false;                     // a cut ball joint: the 3 joint-point rows only
  bool sides_swapped = false;  // a cut joint whose child side is the base: parent = its child
  int row = 0;                 // first constraint row (a cut joint's: in its rows before selection)
  int rows = 5;                // 5, or 6 when prescribed
  bool prescribed = false;
  double q_offset = 0.0;  // rad: a velocity source started off its reference's q(0)
  double damping = 0.0;   // N*m*s/rad or N*s/m
  double armature = 0.0;  // kg*m^2 or kg, rotor inertia reflected to the joint
};

struct BodyModel {
  int n = 0;                      // bodies
  int m = 0;                      // constraint rows
  std::vector<double> mass;       // kg
  std::vector<Matrix3d> inertia;  // kg*m^2 about the centre of mass, body frame
  std::vector<Vector3d> com;      // centre of mass from the body frame's origin, body frame
  std::vector<BodyJoint> joints;  // joint i moves body i
  std::vector<std::vector<int>> children;  // joints whose parent is body i
  // Cut joints (closed loops): parent = the loop's side A, child = side B (swapped when B is
  // the base); `row` numbers their rows among cut_rows_all. cut_rows: the kept ones, the
  // constraint rows m_tree.. m-1, each (cut joint, its row k).
  std::vector<BodyJoint> cuts;
  struct CutRow {
    int cut = 0, k = 0;
  };
  std::vector<CutRow> cut_rows;
  int cut_rows_all = 0;  // every cut joint's rows, dependent ones included
  int m_tree = 0;        // the tree joints' rows
  Vector3d gravity = Vector3d::Zero();
  bool any_armature = false;
  int tcp_body = kBase;                      // body of the model's TCP frame (kBase: none or fixed)
  Vector3d tcp_from_com = Vector3d::Zero();  // TCP from that body's centre of mass, body frame
  Vector3d tcp_fixed = Vector3d::Zero();     // TCP in the base when fixed to it

  int ode_size() const { return 13 * n; }
  int dae_size() const { return 13 * n + m; }
  static int position(int body) { return 7 * body; }
  static int quaternion(int body) { return 7 * body + 3; }
  int velocity(int body) const { return 7 * n + 6 * body; }
  int omega(int body) const { return 7 * n + 6 * body + 3; }
  int multiplier(int row) const { return 13 * n + row; }
};

// A unit vector perpendicular to the unit vector a.
Vector3d Perpendicular(const Vector3d& a);

// Throws InputError for what the body formulations do not model (a massless link), saying
// what to use instead. MakeBodyModel calls it; a run's validation calls it up front.
void CheckBodyFormulationHandles(const Model& model);

// Builds the body description of `model` with these drives. q0: the run's initial joint
// positions (for velocity sources that start off their reference). Throws InputError as
// CheckBodyFormulationHandles.
BodyModel MakeBodyModel(const Model& model, const DriveSet& drives, const Eigen::VectorXd& q0);

}  // namespace mbstream
