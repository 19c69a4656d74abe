// The constant description of a mechanism: a tree of rigid bodies, one joint each.
//
// Bodies are the links that move: each has exactly one revolute or prismatic joint to its
// parent (a ball joint is three such bodies, ball_joint.h), so body i is also degree of freedom i
// (q(i), qd(i), tau(i)). Links attached by fixed joints are merged into the body they hang from
// (their inertia added) and survive as frames. Bodies are in topological order: a parent's index is
// below its children's. A Model is built once by ModelBuilder and never changes; per-run workspaces
// are Data.
#pragma once

#include <string>
#include <vector>

#include "server/math/rigid_inertia.h"
#include "server/model/ball_joint.h"
#include "server/model/joint.h"

namespace mbstream {

// The fixed base (world) as a parent index.
inline constexpr int kBase = -1;

struct Body {
  std::string name;      // the URDF link's name
  int parent = kBase;    // index of the parent body, or kBase
  Joint joint;           // joint from the parent body's frame to this body's frame
  RigidInertia inertia;  // in this body's frame, merged fixed links included
};

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
  // Ball joints inside the tree, each three revolute bodies (ball_joint.h).
  std::vector<BallJoint> ball_joints;

  int num_dofs() const { return static_cast<int>(bodies.size()); }
  // Index of the frame (or body) with this name, or -1.
  int FindFrame(const std::string& frame_name) const;
  int FindBody(const std::string& body_name) const;
  // Sum of all body masses (kg), merged fixed links included, the base excluded.
  double TotalMass() const;
};

}  // namespace mbstream
