// The base polygon of a Polyprism: straight edges and arcs turned into points.
//
// An arc runs from the previous point to its end point on a circle of radius |r|: the
// short arc unless `Large`, clockwise (seen from +z) for r > 0, anticlockwise for r < 0,
// split into `res` segments.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "viewer/script/commands.h"
#include "viewer/script/diagnostics.h"

namespace mbstream::scene_script {

// The closed outline (the last point joins the first), mm. Errors (a radius shorter than
// half the chord, an arc of zero length, an outline enclosing no area) go to `diagnostics`.
std::vector<Eigen::Vector2d> PolyprismOutline(const PolyprismShape& prism,
                                              Diagnostics* diagnostics);

// Twice the signed area of a closed polygon (> 0 anticlockwise).
double TwiceSignedArea(const std::vector<Eigen::Vector2d>& polygon);

}  // namespace mbstream::scene_script
