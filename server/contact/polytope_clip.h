// Two convex polytopes (boxes, collision meshes' hulls) in contact: the separating-axis test
// over both polytopes' face normals and their edge pairs, then, for a face contact, the
// incident face clipped against the reference face (Sutherland-Hodgman), as ODE's dBoxBox and
// FCL's boxBox2 do for boxes: each clipped corner below the reference face is a point.
//
// So a face resting on a face stands on the whole overlap of the two faces, whatever the
// sizes: a turned mesh box on a mesh box of its size (edges crossing, no corner of either
// inside the other) gets its overlap's eight corners, where a corner-inside test found none and
// GJK/EPA gave one point that jumped as the box tilted. The force is continuous in the poses
// as long as the reference and incident faces stay (a clipped corner enters or leaves at depth
// 0). The edge test prunes edge pairs by their Gauss maps (D. Gregorius, "The Separating Axis
// Test between Convex Polyhedra", GDC 2013): only pairs whose arcs cross form a face of the
// Minkowski difference. Allocates nothing once the scratch has grown.
#pragma once

#include <vector>

#include "server/contact/contact_point.h"
#include "server/math/spatial.h"
#include "server/model/collision_geometry.h"

namespace mbstream {

// A box's corners (the 8 sign combinations of +-size/2, x fastest) and its 6 face planes
// (outward unit normal n, offset d: n.x <= d), in its frame.
std::vector<Vector3d> BoxCorners(const Vector3d& size);
std::vector<Eigen::Vector4d> BoxPlanes(const Vector3d& size);

// A convex polytope's faces as polygons (coplanar triangles of a hull merged) and its edges
// with their two faces, in its frame G.
struct PolytopeFaces {
  struct Edge {
    int a = 0, b = 0;         // vertex indices
    int left = 0, right = 0;  // the faces on either side
  };
  std::vector<Vector3d> vertices;
  std::vector<Eigen::Vector4d> planes;  // per face: outward unit normal n, offset d (n.x <= d)
  std::vector<int> loop_start;          // face f's corners: loop[loop_start[f] .. [f + 1])
  std::vector<int> loop;                // vertex indices, counter-clockwise seen from outside
  std::vector<Edge> edges;
  Vector3d centroid = Vector3d::Zero();  // of the vertices (inside)

  static PolytopeFaces OfBox(const Vector3d& size);
  static PolytopeFaces OfHull(const ConvexPolytope& convex);
};

class PolytopeClip {
 public:
  // Whether the pair is small enough for Collide and Separation, which cost O(edges_I edges_J
  // + vertices faces) per call: boxes and simple meshes. A humanoid's link hulls (Atlas: up to
  // 141 vertices) are not; against them the narrow phase keeps its vertex test and GJK/EPA,
  // whose cost the bounding boxes prune (with the face queries here, Atlas's 3 s fall took
  // 370 s of CPU instead of 52, and more than 600 s with the edge query too).
  static constexpr size_t kMaxEdgePairs = 10000;
  static constexpr size_t kMaxVertexFaces = 4000;
  static bool Affordable(const PolytopeFaces& I, const PolytopeFaces& J);

  enum class Outcome {
    kApart,   // separated along a face normal or an edge pair's axis: no contact
    kPoints,  // a face contact: its points appended
    kEdge,    // edges crossing (the deepest axis an edge pair's): for a one-point method
  };

  // The contacts of polytope I (geometry i, at X_WI) and J (j, at X_WJ), appended to *out
  // with normals from j toward i.
  Outcome Collide(int i, const PolytopeFaces& I, const Pose& X_WI, int j, const PolytopeFaces& J,
                  const Pose& X_WJ, std::vector<ContactPoint>* out);

  // The separating-axis test's separation (m): apart, the first face separation found positive
  // (else the edge pairs' largest), a lower bound of the distance (the gap of two faces or of
  // crossing edges); touching, 0; overlapping, the largest over the face normals and the edge
  // pairs, minus the penetration depth. Continuous where it is <= 0 and of the right sign
  // everywhere: a root function whose zero is where a contact starts.
  double Separation(const PolytopeFaces& I, const Pose& X_WI, const PolytopeFaces& J,
                    const Pose& X_WJ);

 private:
  struct World {  // a polytope's vertices and face normals in the world frame
    std::vector<Vector3d> vertices, normals;
    std::vector<double> offsets;  // n.x of each face's plane
    Vector3d centroid = Vector3d::Zero();
  };
  static void ToWorld(const PolytopeFaces& P, const Pose& X, World* w);
  // The separation of Q's deepest vertex below P's faces: the first positive one (a separating
  // face: apart), else the largest (<= 0: overlap); its face.
  static double FaceQuery(const World& P, const World& Q, int* face);
  // The largest separation over the edge pairs that form Minkowski faces.
  static double EdgeQuery(const PolytopeFaces& P, const World& p, const PolytopeFaces& Q,
                          const World& q);
  // The face of q most against the direction n.
  static int IncidentFace(const World& q, const Vector3d& n);
  // Clips Q's face most against P's face `face` to P's face; appends the corners below it.
  int Clip(const PolytopeFaces& P, const World& p, int face, const PolytopeFaces& Q, const World& q,
           double sign, int i, int j, std::vector<ContactPoint>* out);

  World wi_, wj_;
  std::vector<Vector3d> polygon_, clipped_;
};

}  // namespace mbstream
