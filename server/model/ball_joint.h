// A ball (spherical) joint inside the tree. The Model has one degree of freedom per body, so
// the importer expands a ball joint into three revolute joints through its centre: about the
// joint frame's x axis, then about y and z as turned by the ones before (Cardan angles,
// R = Rx(q_x) Ry(q_y) Rz(q_z)), with two massless bodies between them. The expansion is exact
// except at the Cardan angles' singularity, q_y = +-90 degrees, where the child's z axis lines
// up with the joint frame's x axis (gimbal lock: the three axes span two directions, the mass
// matrix is singular there and the angles' rates grow without bound near it). GimbalWatch
// names it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace mbstream {

struct Model;

struct BallJoint {
  std::string name;    // the ball joint's name in the model file
  std::string where;   // "FILE:LINE" of the joint, for messages
  int first_body = 0;  // its x axis; first_body + 1 its y axis, first_body + 2 its z axis
};

// How close to +-90 degrees the middle angle may come before a run stops (rad): 1 degree.
inline constexpr double kGimbalMarginRad = 0.017453292519943295;

// When a ball joint of `model` has its middle angle within `margin` of +-90 degrees at tree
// coordinates `q` (the model's num_dofs values): "ball joint 'NAME' (WHERE) reached its gimbal
// lock at t = T s: NAME.y = A deg ..." with what to do; else nullopt.
std::optional<std::string> GimbalLockMessage(const Model& model, const double* q, double t,
                                             double margin = kGimbalMarginRad);

// How close to +-90 degrees a frame's middle angle must come for the run to warn (rad): 10
// degrees, where the other two angles' rates are 5.8 times the angular velocity.
inline constexpr double kGimbalWarningRad = 0.17453292519943295;

// Watches a run's frames for a ball joint reaching its gimbal lock: at a frame within the
// margin, or between two frames (cos q_y changed sign: the motion went through +-90 degrees).
// The lock is a curve in the space of orientations, so a motion generally passes beside it,
// its other two angles swinging fast by about 180 degrees: the closest frame is kept for a
// warning. Allocates only in its constructor.
class GimbalWatch {
 public:
  explicit GimbalWatch(const Model& model);
  // The frame at time t with tree coordinates q (num_dofs values): the message when a ball
  // joint reached its lock at or before it (since the previous frame), else nullopt.
  std::optional<std::string> Check(const double* q, double t);
  // After the frames: a warning for the ball joint whose frames came closest to its lock,
  // when within kGimbalWarningRad, else nullopt.
  std::optional<std::string> NearWarning() const;

 private:
  const Model& model_;
  std::vector<double> last_cos_;  // cos q_y of each ball joint at the previous frame
  double last_t_ = 0.0;
  bool first_ = true;
  double closest_ = 1.0;  // the smallest |cos q_y| over the frames and ball joints
  size_t closest_ball_ = 0;
  double closest_t_ = 0.0, closest_y_ = 0.0;
};

}  // namespace mbstream
