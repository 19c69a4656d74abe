// The narrow phase: the contact points of two collision geometries at their poses in the world.
//
// Against a plane (the half-space below it) closed forms: a sphere's deepest point; a box's
// penetrating vertices, each a contact (so a box resting flat stands on four points); a
// capsule's two end spheres; a cylinder's deepest rim point at each end, and as its cap comes
// to lie on the plane its rim's 16 corners instead, weighted in between (RimCornerWeight in
// narrow_phase.cc); a convex polytope's (a mesh's hull) penetrating
// vertices, as a box's. Between other shapes FCL's primitive routines (sphere-sphere,
// sphere-box, sphere-cylinder, sphere-capsule, box-box with the whole overlap of
// the faces, up to eight points, never culled (culling jumps as a box tilts);
// capsule-capsule as the spheres at the segments' closest points); a sphere against a convex
// polytope in closed form (the nearest face plane when its centre is inside, the nearest
// point of the hull's triangles outside: exact, no allocation); a box or convex polytope
// against a convex polytope by the separating-axis test (polytope_clip.h): a face on a face
// stands on the whole clipped overlap of the two faces (no allocation); edges crossing: each
// vertex of one inside the other, a point with the depth and normal of the other's nearest
// face, and when no vertex is inside FCL's GJK/EPA; a cylinder or
// capsule against a box or convex polytope as against the polytope's face of least overlap
// (the separating-axis test over its face normals): the plane's candidate points of the round
// shape below that face and inside the polytope's other faces (a can standing or lying on a
// table: its rim's four or two points, as on a plane), and when none is (an edge or a corner
// in the way) GJK/EPA; a cylinder on a cylinder cap on cap (stacked cans): each rim's points
// under the other's cap and within its radius (CapContacts); the remaining pairs (box,
// cylinder or capsule against cylinder or capsule, cylinders side on side; box against box by
// FCL's boxBox2 above) by FCL's GJK/EPA through libccd, one point per pair, which allocates on
// the heap. Allocates nothing otherwise once the scratch has
// grown.
#pragma once

#include <memory>
#include <vector>

#include "server/contact/contact_point.h"
#include "server/model/collision_geometry.h"

namespace mbstream {

class NarrowPhase {
 public:
  explicit NarrowPhase(const std::vector<CollisionGeometry>& geometries);
  ~NarrowPhase();
  NarrowPhase(const NarrowPhase&) = delete;
  NarrowPhase& operator=(const NarrowPhase&) = delete;

  // Appends to *out the contacts of geometries a and b (indices) at poses X_WA and X_WB; the
  // normals point from b toward a. Only overlapping points (depth > 0) are appended.
  void Collide(int a, const Pose& X_WA, int b, const Pose& X_WB, std::vector<ContactPoint>* out);

  // The signed distance of a and b (m, < 0 when they overlap: minus the largest depth), for
  // pairs of which one is a plane (while the other's bounding sphere is above it, the sphere's
  // height instead: a lower bound, positive as the distance), both are spheres or capsules, a
  // sphere and a convex polytope, or a sphere and a box or cylinder (FCL's distance routines); two
  // boxes or hulls: their separating axes' largest separation (polytope_clip.h: the gap of faces or
  // crossing edges, a lower bound of the distance otherwise, capped at `margin`); other pairs:
  // `margin` (unknown but positive) when their bounding spheres are apart, else minus their
  // largest depth when they overlap, else `margin`. Allocates nothing but for the pairs
  // Collide hands to libccd (when their bounding spheres overlap).
  double SignedDistance(int a, const Pose& X_WA, int b, const Pose& X_WB, double margin);

 private:
  struct Fcl;
  // How far geometry g's bounding sphere is above the plane through `on_plane` with unit normal
  // n (m, world; <= 0 when it reaches the plane).
  double PlaneClearance(int g, const Pose& X_WG, const Vector3d& n, const Vector3d& on_plane) const;
  // Box or hull i against hull j (polytope_clip.h): a face contact's clipped overlap, or apart;
  // edges crossing: VertexContacts. False: nothing settled it (GJK/EPA must).
  bool PolytopeContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                        std::vector<ContactPoint>* out);
  // Box or hull i against hull j: each vertex of one inside the other a point; how many.
  int VertexContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                     std::vector<ContactPoint>* out);
  // Cylinder or capsule `round` against box or hull `poly` (one of them i, the other j of the
  // ordered pair): the round shape's points below the polytope's face of least overlap and
  // inside its other faces. True when that settles the pair (points found, or apart along a
  // face normal); false: GJK/EPA must (an edge or corner in the way).
  bool FaceContacts(int i, int j, int round, const Pose& X_WR, int poly, const Pose& X_WP,
                    std::vector<ContactPoint>* out);
  // Cylinder i against cylinder j, cap facing cap (stacked cans; the caps overlap less along
  // their axes than the sides do across): the other's facing rim clipped to the reference
  // cap's rim, both polygons of 16 corners fixed in their cylinders, and each clipped
  // corner below the reference cap a point, as a polytope's face on a face. True when that
  // settles the pair (points found, or apart along an axis); false: GJK/EPA must (side on
  // side, a rim across a side).
  bool CapContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                   std::vector<ContactPoint>* out);
  const std::vector<CollisionGeometry>& geometries_;
  std::unique_ptr<Fcl> fcl_;
  std::vector<ContactPoint> scratch_;
};

}  // namespace mbstream
