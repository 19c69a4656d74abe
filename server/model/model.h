// The constant description of a mechanism: a forest of rigid bodies, one joint each.
//
// Bodies are the links that move: each has exactly one joint to its parent. A revolute or
// prismatic joint has one coordinate; a ball joint (JointType::kBall) turns its body about the
// joint frame's origin in all three directions; a free joint (JointType::kFree) moves a root
// body (parent kBase) in all six. Links attached by fixed joints are merged into the body they
// hang from (their inertia added) and survive as frames. Bodies are in topological order: a
// parent's index is below its children's. A Model is built once by ModelBuilder and never
// changes; per-run workspaces are Data.
//
// Coordinates. A model without free bodies and ball joints has one position and one velocity
// coordinate per body: body i is q(i), qd(i), tau(i), and nq() == nv() == num_bodies(). A free
// body has 7 position coordinates at q_index, MuJoCo's layout,
//   x y z qw qx qy qz: p_WB, the body frame's origin in the world (m), then the unit
//                      quaternion of R_WB (world <- body), scalar first;
// and 6 velocity coordinates at v_index, also MuJoCo's,
//   vx vy vz wx wy wz: v_WB, the velocity of the body frame's origin in the WORLD frame (m/s),
//                      then w_B, the angular velocity in the BODY frame (rad/s);
// so that q' = G(q) v is p' = v_WB, quat' = 1/2 quat (x) (0, w_B). Its generalised forces
// (tau at v_index) are the force on the body in the world frame (N) then the moment about the
// body origin in the body frame (N*m). A ball joint has 4 position coordinates, the unit
// quaternion qw qx qy qz of R_JB (the child's rotation relative to the joint frame J on the
// parent, scalar first), and 3 velocity coordinates wx wy wz, the angular velocity of the child
// relative to the parent in the child frame (rad/s), MuJoCo's ball joint; its generalised
// forces are the moment about the joint centre in the child frame (N*m), and the child's
// frame origin is the joint centre. The algorithms' spatial velocities (Data::v) stay in each
// body's frame (server/math/spatial.h). Free joints exist only at the root of a tree, as in
// MuJoCo: a free body's children hang from it through revolute, prismatic, ball and fixed
// joints. docs/free_bodies.md has the details.
#pragma once

#include <string>
#include <vector>

#include "server/math/rigid_inertia.h"
#include "server/model/collision_geometry.h"
#include "server/model/joint.h"

namespace mbstream {

// The fixed base (world) as a parent index.
inline constexpr int kBase = -1;

struct Body {
  std::string name;      // the URDF link's name
  int parent = kBase;    // index of the parent body, or kBase
  Joint joint;           // joint from the parent body's frame to this body's frame
  RigidInertia inertia;  // in this body's frame, merged fixed links included
  // First position and velocity coordinate (set by ModelBuilder; equal to the body's index in a
  // model without free bodies, where the algorithms index by body and never read them).
  int q_index = 0;
  int v_index = 0;
  // A free body's default pose in the world, X_WB (its q when the run gives no initial_q).
  Pose X_W0;
  bool free() const { return joint.type == JointType::kFree; }
  bool ball() const { return joint.type == JointType::kBall; }
  // Position and velocity coordinates of its joint: 7 and 6 (free), 4 and 3 (ball), else 1.
  int nq() const;
  int nv() const;
};

// A free joint's coordinate counts.
inline constexpr int kFreeNq = 7;
inline constexpr int kFreeNv = 6;
// A ball joint's.
inline constexpr int kBallNq = 4;
inline constexpr int kBallNv = 3;

inline int Body::nq() const { return free() ? kFreeNq : ball() ? kBallNq : 1; }
inline int Body::nv() const { return free() ? kFreeNv : ball() ? kBallNv : 1; }

// A frame fixed in a body (or in the base): every link, the TCP and probes.
struct Frame {
  std::string name;
  int body = kBase;  // the body it is fixed in, or kBase
  Pose X_BF;         // the frame in that body's frame
};

struct Model {
  std::string name;
  std::string base_name;              // name of the fixed base link
  std::vector<Body> bodies;           // one per degree of freedom, topological order
  std::vector<Frame> frames;          // every link, then named points
  Vector3d gravity{0.0, 0.0, -9.81};  // m/s^2 in the base frame
  int tcp_frame = -1;                 // index into frames of the tool centre point, or -1
  // The free bodies' indices, ascending; empty for a fixed-base model.
  std::vector<int> free_bodies;
  // The bodies moved by ball joints, ascending.
  std::vector<int> ball_bodies;
  // The index in q of every quaternion's qw (free bodies' and ball joints'), ascending: the
  // integrators keep each unit. Empty when nq == nv (the algorithms' fast paths test this
  // once per call: has_quaternions()).
  std::vector<int> quaternions;
  // The <collision> shapes (collision_geometry.h), in file order; empty: no contact.
  std::vector<CollisionGeometry> collisions;

  int num_bodies() const { return static_cast<int>(bodies.size()); }
  // Position and velocity coordinates: num_bodies() plus 6 and 5 per free body, 3 and 2 per
  // ball joint.
  int nq() const {
    return num_bodies() + (kFreeNq - 1) * static_cast<int>(free_bodies.size()) +
           (kBallNq - 1) * static_cast<int>(ball_bodies.size());
  }
  int nv() const {
    return num_bodies() + (kFreeNv - 1) * static_cast<int>(free_bodies.size()) +
           (kBallNv - 1) * static_cast<int>(ball_bodies.size());
  }
  bool has_free_bodies() const { return !free_bodies.empty(); }
  bool has_ball_joints() const { return !ball_bodies.empty(); }
  // Free bodies or ball joints: q indexed by Body::q_index, qd by Body::v_index, nq != nv.
  bool has_quaternions() const { return !quaternions.empty(); }
  // Degrees of freedom: nv(). The name predates free bodies; code that indexes q by body must
  // use num_bodies() (equal when has_quaternions() is false).
  int num_dofs() const { return nv(); }
  // Index of the frame (or body) with this name, or -1.
  int FindFrame(const std::string& frame_name) const;
  int FindBody(const std::string& body_name) const;
  // The body whose joint has velocity coordinate v (v itself without quaternions).
  int BodyOfVelocity(int v) const;
  // Sum of all body masses (kg), merged fixed links included, the base excluded.
  double TotalMass() const;
};

// Sets q_index, v_index, free_bodies, ball_bodies and quaternions from the bodies' joints
// (ModelBuilder::Build calls it).
void IndexCoordinates(Model* model);

// The positions a run starts from when it gives none: 0 for every revolute and prismatic
// coordinate, each free body's default pose X_W0, each ball joint's identity quaternion
// (1, 0, 0, 0). `q` has model.nq() values.
void NeutralPositions(const Model& model, double* q);

}  // namespace mbstream
