// The scenes of bench/contact_peers in DART 6.12 (Debian's libdart-dev; built only where CMake
// finds it): the same bodies, masses, inertias, friction and, for the bounce, elasticity
// (restitution 1; DART's default, 0, is inelastic), on a 20 x 20 x 0.2 m fixed box whose top
// face is the plane z = 0 (DART's examples' ground). DART's contact is rigid: a
// velocity-level LCP (its BoxedLcpConstraintSolver, Dantzig with PGS as the fallback) with a
// Coulomb friction pyramid of one coefficient (the smaller of the two shapes'), restitution
// as the product of the two shapes', the error reduction ERP 0.01 and the constraint force
// mixing 1e-5 of its defaults; there is no stiffness, no dissipation and no Stribeck curve.
#pragma once

#include <string>

#include "bench/contact_peers_common.h"

namespace mbstream::contact_peers {

struct DartSetting {
  double timestep = 1e-3;  // s, DART's default
  // The collision detector: DART's default, FCL with every primitive as a triangle mesh
  // (FCLCollisionDetector::MESH), or FCL's primitive shapes (PRIMITIVE: a single contact
  // point a pair but for box-box, says DART).
  bool fcl_primitives = false;
};

// One run of `scene` ("incline", "rolling", "bounce"); `label` is the CSV's setting. CPU:
// the median of three runs of a world built afresh each time (the build not counted).
Row RunDart(const std::string& scene, const DartSetting& setting, const std::string& label);

}  // namespace mbstream::contact_peers
