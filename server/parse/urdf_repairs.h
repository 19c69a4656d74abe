// Repairs of the small defects that published URDFs commonly carry (`--repair`): each
// returns the repaired value, or nothing when the input needs no repair. The importer
// applies them only when asked and lists each one as a warning with the old and new values;
// without `--repair` the same defects stay errors whose message says that `--repair` exists.
#pragma once

#include <optional>

#include "server/math/spatial.h"

namespace urdf {
class Link;
}

namespace mbstream {

// The nearest physical rotational inertia (kg*m^2, about the centre of mass) to `I` with the
// same principal axes: principal moments below 1e-6 of the largest are raised to it, and when
// the two smaller moments add up to less than the largest, both are raised by half the
// shortfall (the least change, in the Frobenius norm, that meets the triangle inequality).
// A tensor with no positive moment gets that of a solid sphere of 1 cm radius and `mass`.
std::optional<Matrix3d> NearestPhysicalInertia(const Matrix3d& I, double mass);

// A small mass (kg) and inertia (kg*m^2, about its centre) for a moving link without mass:
// 1 g spread over the bounding box of its first visual when that is a box, cylinder or
// sphere, or over a 2 cm cube otherwise.
struct StandInInertia {
  double mass = 0.0;
  Matrix3d inertia = Matrix3d::Zero();
  Vector3d size = Vector3d::Zero();  // m, the box used
};
StandInInertia StandInForMasslessLink(const urdf::Link& link);

}  // namespace mbstream
