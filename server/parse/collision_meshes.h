// A collision mesh as convex pieces: the mesh file's vertices read with Assimp (STL, OBJ,
// Collada, glTF, PLY: whatever Debian's libassimp reads), each piece's convex hull by qhull
// (convex_hull.h). A piece is a node of the file that carries meshes (an OBJ object or group,
// a Collada node, an STL's one solid), its vertices moved by the node's transform in the file
// (as the viewer draws it), then scaled. docs/contact.md says how meshes are handled.
#pragma once

#include <string>
#include <vector>

#include "server/model/collision_geometry.h"

namespace mbstream {

// The most vertices (after identical ones are joined) a collision mesh file may have: beyond
// it, InputError (simplify the mesh, or give its hull).
inline constexpr int kMaxCollisionMeshVertices = 100000;
// A piece whose mesh encloses less than this fraction of its hull's volume (or more: a mesh
// that is not closed) is not convex: a warning says its hull is used.
inline constexpr double kConvexVolumeRatio = 0.99;

struct CollisionMesh {
  std::vector<ConvexPolytope> pieces;  // the convex hull of each piece, in file order
  // For each piece, its mesh's volume over its hull's (1 for a convex closed mesh).
  std::vector<double> volume_ratio;
};

// Reads the mesh file `bytes` (its format told by `file`'s extension), scales its vertices
// by `scale` and returns the hull of each piece. `what` ("FILE:LINE: link 'L': collision
// 'C': mesh 'F'") starts the InputError for a file Assimp cannot read, one without vertices,
// more than kMaxCollisionMeshVertices, a piece without volume, or a scale with a zero or
// non-finite factor.
CollisionMesh ReadCollisionMesh(const std::string& bytes, const std::string& file,
                                const Vector3d& scale, const std::string& what);

}  // namespace mbstream
