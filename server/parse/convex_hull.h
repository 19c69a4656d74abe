// The convex hull of a point set, by qhull (Debian's libqhull-dev, its reentrant C library
// libqhull_r): the hull's vertices (input points, unmoved), its facets triangulated (qhull's
// option Qt) and oriented outward, its volume and bounding box.
#pragma once

#include <string>
#include <vector>

#include "server/model/collision_geometry.h"

namespace mbstream {

// The hull of `points`. Fewer than 4 points, points that are all in one plane (or on a line),
// or a non-finite coordinate: InputError "`what`: why; what to do".
ConvexPolytope ConvexHullOf(const std::vector<Vector3d>& points, const std::string& what);

// The volume a closed triangle mesh encloses (m^3; divergence theorem, the absolute value of
// the signed sum, so either orientation counts): `triangles` holds three indices into
// `vertices` per triangle. For a mesh that is not closed the number means little.
double MeshVolume(const std::vector<Vector3d>& vertices, const std::vector<int>& triangles);

}  // namespace mbstream
