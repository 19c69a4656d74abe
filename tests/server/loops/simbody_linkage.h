// Simbody's side of the cross-checks (simbody_cross_check_test.cc, ball_joint_test.cc), in a
// translation unit of its own: Simbody 3.7's headers predate C++20's rewritten comparisons
// (ambiguous operator==), so this file is compiled as C++17 and includes no header that
// needs C++20.
#pragma once

#include <vector>

#include "server/parse/sdf_import.h"

namespace mbstream {

// Simbody's joint trajectories of `sdf` started at q = 0 (as drawn) with joint rates qd0,
// under gravity -z (pin and slider mobilizers, a ball constraint at each cut revolute joint,
// Runge-Kutta-Merson at 1e-12), at `times`.
std::vector<std::vector<double>> SimbodyTrajectories(const SdfImport& sdf,
                                                     const std::vector<double>& times,
                                                     const std::vector<double>& qd0);

// The model's last body (a ball joint's child, its frame the joint frame) moved by a Ball
// mobilizer about the first of the ball's bodies' joint frame X_PJ, under gravity -z, from
// orientation R0 and angular velocity w0 (both in the joint frame), by Runge-Kutta-Merson at
// 1e-12: the child's orientation in the joint frame at `times`.
std::vector<Matrix3d> SimbodyBallOrientations(const Model& model, const Matrix3d& R0,
                                              const Vector3d& w0, const std::vector<double>& times);

}  // namespace mbstream
