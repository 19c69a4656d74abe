#include "server/contact/narrow_phase.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/box_box.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/capsule_capsule.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_box.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_capsule.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_cylinder.h>
#include <fcl/narrowphase/detail/primitive_shape_algorithm/sphere_sphere.h>

#include "server/contact/polytope_clip.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

fcl::Transform3d ToFcl(const Pose& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.R;
  T.translation() = X.p;
  return T;
}

std::shared_ptr<fcl::CollisionGeometryd> FclShape(const CollisionShape& s) {
  switch (s.type) {
    case ShapeType::kSphere:
      return std::make_shared<fcl::Sphered>(s.radius);
    case ShapeType::kBox:
      return std::make_shared<fcl::Boxd>(s.size);
    case ShapeType::kCylinder:
      return std::make_shared<fcl::Cylinderd>(s.radius, s.length);
    case ShapeType::kCapsule:
      return std::make_shared<fcl::Capsuled>(s.radius, s.length);
    case ShapeType::kConvex:
      return std::make_shared<fcl::Convexd>(s.convex.vertices, s.convex.num_faces, s.convex.faces);
    case ShapeType::kPlane:
      return nullptr;  // closed forms only (narrow_phase.h)
  }
  return nullptr;
}

// A point of a shape at depth `depth` below the plane (normal n, world): the contact midway.
// The corners of a cylinder's rim as the narrow phase sees it (fixed in the cylinder): against
// a plane or a face, and a cap's outline against another cap (NarrowPhase::CapContacts).
constexpr int kRimCorners = 16;

// A rim corner's weight against a plane of normal n, from c = |n . axis| (1: the cap flat on
// the plane, 0: the cylinder lying): 1 above cos 8.1 deg (the rim's corners stand for the cap),
// 0 below cos 25.8 deg (the rim's exact deepest point alone, as for a cylinder lying or rolling),
// a smoothstep between. The deepest point takes 1 - weight. Each point's share of the pair's
// stiffness is its weight times its depth over the sum (ContactForces::AddForces), so the
// force is continuous as the cylinder tilts: the deepest point's direction is undefined when
// the cap lies flat, and switching to it at a threshold made a can standing under an
// off-centre load stall BDF at the start.
double RimCornerWeight(double c) {
  constexpr double kFlat = 0.99, kTilted = 0.9;
  const double x = std::clamp((c - kTilted) / (kFlat - kTilted), 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

void AddPlanePoint(int a, int b, const Vector3d& x, const Vector3d& n, double depth, double weight,
                   std::vector<ContactPoint>* out) {
  if (depth > 0.0) {
    out->push_back(ContactPoint::UnderFace(a, b, x, n, 1.0, depth));
    out->back().weight = weight;
  }
}

// The points of shape a (pose X_WA) that a plane (pose X_WP, normal its z) tests: calls
// point(x, weight) for each candidate surface point x (world) with its weight (1 but for a
// cylinder's rim: RimCornerWeight).
template <typename PointFn>
void PlaneCandidates(const CollisionShape& s, const Pose& X_WA, const Vector3d& n, PointFn point) {
  switch (s.type) {
    case ShapeType::kSphere:
      point(X_WA.p - s.radius * n, 1.0);
      return;
    case ShapeType::kBox:
      for (int k = 0; k < 8; ++k) {
        const Vector3d corner(k & 1 ? 0.5 : -0.5, k & 2 ? 0.5 : -0.5, k & 4 ? 0.5 : -0.5);
        point(X_WA.Apply(corner.cwiseProduct(s.size)), 1.0);
      }
      return;
    case ShapeType::kCapsule:
      for (const double e : {-0.5, 0.5}) {
        point(X_WA.Apply(Vector3d(0, 0, e * s.length)) - s.radius * n, 1.0);
      }
      return;
    case ShapeType::kCylinder: {
      const Vector3d axis = X_WA.R.col(2);
      const Vector3d radial = n - n.dot(axis) * axis;  // toward the plane's outside, in the cap
      const double norm = radial.norm();
      const double corners = RimCornerWeight(std::abs(n.dot(axis)));
      for (const double e : {-0.5, 0.5}) {
        const Vector3d centre = X_WA.Apply(Vector3d(0, 0, e * s.length));
        if (corners < 1.0 && norm > 1e-9) point(centre - s.radius * radial / norm, 1.0 - corners);
        if (corners > 0.0) {
          for (int k = 0; k < kRimCorners; ++k) {
            const double angle = 2.0 * M_PI * k / kRimCorners;
            point(centre + s.radius *
                               (std::cos(angle) * X_WA.R.col(0) + std::sin(angle) * X_WA.R.col(1)),
                  corners);
          }
        }
      }
      return;
    }
    case ShapeType::kConvex:  // each vertex, as a box's corners
      for (const Vector3d& v : *s.convex.vertices) point(X_WA.Apply(v), 1.0);
      return;
    case ShapeType::kPlane:
      return;
  }
}

// A convex polytope's face planes (its triangles): outward unit normal n and offset, n.x = d
// on the face.
std::vector<Eigen::Vector4d> FacePlanes(const ConvexPolytope& convex) {
  std::vector<Eigen::Vector4d> planes;
  const std::vector<Vector3d>& v = *convex.vertices;
  const std::vector<int>& f = *convex.faces;
  for (size_t k = 0; k + 3 < f.size(); k += 4) {  // triangles: 3, a, b, c
    const Vector3d n = (v[f[k + 2]] - v[f[k + 1]]).cross(v[f[k + 3]] - v[f[k + 1]]);
    if (!(n.norm() > 0.0)) continue;  // a degenerate triangle: its neighbours bound the hull
    const Vector3d u = n.normalized();
    planes.emplace_back(u.x(), u.y(), u.z(), u.dot(v[f[k + 1]]));
  }
  return planes;
}

// The point of triangle abc closest to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vector3d ClosestOnTriangle(const Vector3d& p, const Vector3d& a, const Vector3d& b,
                           const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// The signed distance from point p (in the polytope's frame) to a convex polytope's surface
// (< 0 inside) and the outward unit normal there: exact, in closed form (the nearest face
// plane inside; the nearest point of its triangles outside). Allocates nothing.
double PointConvexDistance(const Vector3d& p, const ConvexPolytope& convex,
                           const std::vector<Eigen::Vector4d>& planes, Vector3d* normal) {
  double highest = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector4d& plane : planes) {
    const double s = plane.head<3>().dot(p) - plane(3);
    if (s > highest) {
      highest = s;
      *normal = plane.head<3>();
    }
  }
  if (highest <= 0.0) return highest;  // inside: the nearest face
  const std::vector<Vector3d>& v = *convex.vertices;
  const std::vector<int>& f = *convex.faces;
  double nearest = std::numeric_limits<double>::infinity();
  Vector3d closest = p;
  for (size_t k = 0; k + 3 < f.size(); k += 4) {  // triangles: 3, a, b, c
    const Vector3d q = ClosestOnTriangle(p, v[f[k + 1]], v[f[k + 2]], v[f[k + 3]]);
    const double d = (p - q).squaredNorm();
    if (d < nearest) {
      nearest = d;
      closest = q;
    }
  }
  const double distance = std::sqrt(nearest);
  if (distance > 0.0) *normal = (p - closest) / distance;
  return distance;
}

// The largest signed distance of point p to `planes` (< 0: inside all of them) and that plane's
// normal.
double DeepestPlane(const Vector3d& p, const std::vector<Eigen::Vector4d>& planes,
                    Vector3d* normal) {
  double highest = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector4d& plane : planes) {
    const double s = plane.head<3>().dot(p) - plane(3);
    if (s > highest) {
      highest = s;
      *normal = plane.head<3>();
    }
  }
  return highest;
}

// Whether boxes [lower_a, upper_a] at X_WA and [lower_b, upper_b] at X_WB (each in its own
// frame) are apart: the separating-axis test of two oriented boxes (Gottschalk's 15 axes),
// with a relative margin against round-off on parallel edges.
bool BoxesApart(const Vector3d& lower_a, const Vector3d& upper_a, const Pose& X_WA,
                const Vector3d& lower_b, const Vector3d& upper_b, const Pose& X_WB) {
  const Vector3d ha = 0.5 * (upper_a - lower_a), hb = 0.5 * (upper_b - lower_b);
  const Matrix3d R = X_WA.R.transpose() * X_WB.R;  // b's axes in a's frame
  const Matrix3d A = R.cwiseAbs().array() + 1e-12;
  // b's centre from a's, in a's frame
  const Vector3d t = X_WA.R.transpose() * (X_WB.Apply(0.5 * (lower_b + upper_b)) -
                                           X_WA.Apply(0.5 * (lower_a + upper_a)));
  for (int k = 0; k < 3; ++k) {
    if (std::abs(t(k)) > ha(k) + A.row(k).dot(hb)) return true;
    if (std::abs(R.col(k).dot(t)) > A.col(k).dot(ha) + hb(k)) return true;
  }
  for (int k = 0; k < 3; ++k) {  // a's axis k crossed with b's axis l
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    for (int l = 0; l < 3; ++l) {
      const int l1 = (l + 1) % 3, l2 = (l + 2) % 3;
      const double along = std::abs(t(k2) * R(k1, l) - t(k1) * R(k2, l));
      const double ra = ha(k1) * A(k2, l) + ha(k2) * A(k1, l);
      const double rb = hb(l1) * A(k, l2) + hb(l2) * A(k, l1);
      if (along > ra + rb) return true;
    }
  }
  return false;
}

// A sphere about the shape: centre (in its frame) and radius.
Eigen::Vector4d BoundingSphere(const CollisionShape& s) {
  switch (s.type) {
    case ShapeType::kSphere:
      return Eigen::Vector4d(0, 0, 0, s.radius);
    case ShapeType::kBox:
      return Eigen::Vector4d(0, 0, 0, 0.5 * s.size.norm());
    case ShapeType::kCylinder:
      return Eigen::Vector4d(0, 0, 0, std::hypot(s.radius, 0.5 * s.length));
    case ShapeType::kCapsule:
      return Eigen::Vector4d(0, 0, 0, s.radius + 0.5 * s.length);
    case ShapeType::kConvex: {
      const Vector3d centre = 0.5 * (s.convex.lower + s.convex.upper);
      double radius = 0.0;
      for (const Vector3d& v : *s.convex.vertices) radius = std::max(radius, (v - centre).norm());
      return Eigen::Vector4d(centre.x(), centre.y(), centre.z(), radius);
    }
    case ShapeType::kPlane:
      break;
  }
  return Eigen::Vector4d(0, 0, 0, std::numeric_limits<double>::infinity());
}

}  // namespace

struct NarrowPhase::Fcl {
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> shapes;  // null for planes
  // A convex polytope's (or a box's) vertices and face planes, in its frame; else empty.
  std::vector<std::vector<Vector3d>> vertices;
  std::vector<std::vector<Eigen::Vector4d>> planes;
  // A box's or convex polytope's bounding box in its frame; else empty.
  std::vector<Vector3d> lower, upper;
  // Each shape's bounding sphere in its frame: centre and radius (a plane's infinite).
  std::vector<Eigen::Vector4d> bounds;
  // A box's or convex polytope's faces and edges (polytope_clip.h); else empty.
  std::vector<PolytopeFaces> faces;
  PolytopeClip clip;
  // Per shape (null for planes): the CollisionObject GJK/EPA is called with, posed per call.
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;
  std::vector<fcl::ContactPointd> points;
  fcl::CollisionRequestd request{8, true};
  fcl::CollisionResultd result;
};

NarrowPhase::NarrowPhase(const std::vector<CollisionGeometry>& geometries)
    : geometries_(geometries), fcl_(std::make_unique<Fcl>()) {
  for (const CollisionGeometry& g : geometries) {
    fcl_->shapes.push_back(FclShape(g.shape));
    fcl_->objects.push_back(fcl_->shapes.back() != nullptr
                                ? std::make_unique<fcl::CollisionObjectd>(fcl_->shapes.back())
                                : nullptr);
    const ShapeType type = g.shape.type;
    fcl_->planes.push_back(type == ShapeType::kConvex ? FacePlanes(g.shape.convex)
                           : type == ShapeType::kBox  ? BoxPlanes(g.shape.size)
                                                      : std::vector<Eigen::Vector4d>{});
    fcl_->bounds.push_back(BoundingSphere(g.shape));
    fcl_->lower.push_back(type == ShapeType::kConvex ? g.shape.convex.lower : -0.5 * g.shape.size);
    fcl_->upper.push_back(type == ShapeType::kConvex ? g.shape.convex.upper : 0.5 * g.shape.size);
    fcl_->faces.push_back(type == ShapeType::kConvex ? PolytopeFaces::OfHull(g.shape.convex)
                          : type == ShapeType::kBox  ? PolytopeFaces::OfBox(g.shape.size)
                                                     : PolytopeFaces{});
    fcl_->vertices.push_back(type == ShapeType::kConvex ? *g.shape.convex.vertices
                             : type == ShapeType::kBox  ? BoxCorners(g.shape.size)
                                                        : std::vector<Vector3d>{});
  }
  fcl_->points.reserve(16);
  scratch_.reserve(16);
}

NarrowPhase::~NarrowPhase() = default;

void NarrowPhase::Collide(int a, const Pose& X_WA, int b, const Pose& X_WB,
                          std::vector<ContactPoint>* out) {
  ShapeType ta = geometries_[a].shape.type;
  ShapeType tb = geometries_[b].shape.type;
  if (ta == ShapeType::kPlane && tb == ShapeType::kPlane) return;
  // Order the pair so that a's type is the lesser (sphere < box < cylinder < capsule <
  // convex < plane); the normals are flipped back at the end.
  const bool swapped = static_cast<int>(ta) > static_cast<int>(tb);
  const int i = swapped ? b : a;
  const int j = swapped ? a : b;
  const Pose& X_WI = swapped ? X_WB : X_WA;
  const Pose& X_WJ = swapped ? X_WA : X_WB;
  ta = geometries_[i].shape.type;
  tb = geometries_[j].shape.type;
  const size_t first = out->size();
  const bool round_i = ta == ShapeType::kCylinder || ta == ShapeType::kCapsule;
  const bool box_round =
      ta == ShapeType::kBox && (tb == ShapeType::kCylinder || tb == ShapeType::kCapsule);
  const bool round_convex = round_i && tb == ShapeType::kConvex;
  if (tb == ShapeType::kPlane) {
    const Vector3d n = X_WJ.R.col(2);
    // Its bounding sphere above the plane: no point of it is below (a hull's vertices are not
    // walked, most of a robot's links at every evaluation).
    if (PlaneClearance(i, X_WI, n, X_WJ.p) <= 0.0) {
      PlaneCandidates(geometries_[i].shape, X_WI, n, [&](const Vector3d& x, double weight) {
        AddPlanePoint(i, j, x, n, -n.dot(x - X_WJ.p), weight, out);
      });
    }
  } else if (ta == ShapeType::kCapsule && tb == ShapeType::kCapsule) {
    const CollisionShape& si = geometries_[i].shape;
    const CollisionShape& sj = geometries_[j].shape;
    const Vector3d hi = 0.5 * si.length * X_WI.R.col(2);
    const Vector3d hj = 0.5 * sj.length * X_WJ.R.col(2);
    double s = 0.0, t = 0.0;
    Vector3d ci, cj;
    fcl::detail::closestPtSegmentSegment<double>(X_WI.p - hi, X_WI.p + hi, X_WJ.p - hj, X_WJ.p + hj,
                                                 &s, &t, &ci, &cj);
    const Vector3d d = ci - cj;
    const double distance = d.norm();
    const double depth = si.radius + sj.radius - distance;
    if (depth > 0.0 && distance > 1e-12) {
      ContactPoint c;
      c.geometry_a = i;
      c.geometry_b = j;
      c.normal = d / distance;
      c.depth = depth;
      c.point = cj + (sj.radius - 0.5 * depth) * c.normal;
      out->push_back(c);
    }
  } else if (ta == ShapeType::kCylinder && tb == ShapeType::kCylinder &&
             CapContacts(i, X_WI, j, X_WJ, out)) {
    // cap on cap: each rim's points under the other's cap; or apart along a cap's axis
  } else if ((ta == ShapeType::kBox || ta == ShapeType::kConvex) && tb == ShapeType::kConvex &&
             PolytopeContacts(i, X_WI, j, X_WJ, out)) {
    // a face on a face: the overlap's corners; apart; or edges crossing with a vertex inside
  } else if (box_round ? FaceContacts(i, j, j, X_WJ, i, X_WI, out)
                       : round_convex && FaceContacts(i, j, i, X_WI, j, X_WJ, out)) {
    // the round shape on the polytope's face, or apart along a face normal
  } else if (ta == ShapeType::kSphere && tb == ShapeType::kConvex) {
    const double r = geometries_[i].shape.radius;
    Vector3d n_J = Vector3d::UnitZ();
    const double distance = PointConvexDistance(X_WJ.R.transpose() * (X_WI.p - X_WJ.p),
                                                geometries_[j].shape.convex, fcl_->planes[j], &n_J);
    const double depth = r - distance;
    if (depth > 0.0) {
      ContactPoint c;
      c.geometry_a = i;
      c.geometry_b = j;
      c.normal = X_WJ.R * n_J;
      c.depth = depth;
      c.point = X_WI.p - (r - 0.5 * depth) * c.normal;
      out->push_back(c);
    }
  } else {
    const fcl::Transform3d Ti = ToFcl(X_WI), Tj = ToFcl(X_WJ);
    const fcl::CollisionGeometryd& gi = *fcl_->shapes[i];
    const fcl::CollisionGeometryd& gj = *fcl_->shapes[j];
    std::vector<fcl::ContactPointd>& points = fcl_->points;
    points.clear();
    using namespace fcl::detail;
    const auto sphere = [&gi]() -> const fcl::Sphered& {
      return static_cast<const fcl::Sphered&>(gi);
    };
    if (ta == ShapeType::kSphere && tb == ShapeType::kSphere) {
      sphereSphereIntersect(sphere(), Ti, static_cast<const fcl::Sphered&>(gj), Tj, &points);
    } else if (ta == ShapeType::kSphere && tb == ShapeType::kBox) {
      sphereBoxIntersect(sphere(), Ti, static_cast<const fcl::Boxd&>(gj), Tj, &points);
    } else if (ta == ShapeType::kSphere && tb == ShapeType::kCylinder) {
      sphereCylinderIntersect(sphere(), Ti, static_cast<const fcl::Cylinderd&>(gj), Tj, &points);
    } else if (ta == ShapeType::kSphere && tb == ShapeType::kCapsule) {
      sphereCapsuleIntersect(sphere(), Ti, static_cast<const fcl::Capsuled&>(gj), Tj, &points);
    } else if (ta == ShapeType::kBox && tb == ShapeType::kBox) {
      // boxBox2 itself: boxBoxIntersect copies through a vector of its own (allocates). At
      // most 8 points, the whole clipped overlap: fewer culls it, which jumps
      // (polytope_pairs_test).
      Vector3d normal;
      double depth = 0.0;
      int code = 0;
      boxBox2(static_cast<const fcl::Boxd&>(gi).side, Ti, static_cast<const fcl::Boxd&>(gj).side,
              Tj, normal, &depth, &code, 8, points);
    } else {  // GJK/EPA (libccd): allocates
      // The geometries' own objects, posed: a CollisionObject made for the call would compute
      // its shape's local bounding box again (a hull's every vertex, each call).
      fcl::CollisionObjectd& oi = *fcl_->objects[i];
      fcl::CollisionObjectd& oj = *fcl_->objects[j];
      oi.setTransform(Ti);
      oi.computeAABB();
      oj.setTransform(Tj);
      oj.computeAABB();
      fcl_->result.clear();
      fcl::collide(&oi, &oj, fcl_->request, fcl_->result);
      for (size_t k = 0; k < fcl_->result.numContacts(); ++k) {
        const fcl::Contactd& contact = fcl_->result.getContact(k);
        points.push_back(
            fcl::ContactPointd(contact.normal, contact.pos, contact.penetration_depth));
      }
    }
    for (const fcl::ContactPointd& p : points) {
      if (!(p.penetration_depth > 0.0)) continue;
      ContactPoint c;
      c.geometry_a = i;
      c.geometry_b = j;
      c.normal = -p.normal;  // FCL's points from the first object to the second
      c.depth = p.penetration_depth;
      c.point = p.pos;
      out->push_back(c);
    }
  }
  if (swapped) {
    for (size_t k = first; k < out->size(); ++k) {
      ContactPoint& c = (*out)[k];
      std::swap(c.geometry_a, c.geometry_b);
      c.normal = -c.normal;
    }
  }
}

namespace {

// Cylinder P's cap that faces cylinder Q: its outward unit normal n (world), the cap's height
// h = n.x on it, and how far Q reaches past it along n (> 0: overlap; <= 0: apart along n).
struct Cap {
  Vector3d n = Vector3d::UnitZ();
  double h = 0.0, overlap = 0.0;
};
Cap FacingCap(const CollisionShape& p, const Pose& X_WP, const CollisionShape& q,
              const Pose& X_WQ) {
  const Vector3d a = X_WP.R.col(2);
  Cap cap;
  cap.n = a.dot(X_WQ.p - X_WP.p) >= 0.0 ? a : Vector3d(-a);
  cap.h = cap.n.dot(X_WP.p) + 0.5 * p.length;
  const double along = cap.n.dot(X_WQ.R.col(2));
  const double lowest = cap.n.dot(X_WQ.p) - 0.5 * q.length * std::abs(along) -
                        q.radius * std::sqrt(std::max(0.0, 1.0 - along * along));
  cap.overlap = cap.h - lowest;
  return cap;
}

}  // namespace

bool NarrowPhase::CapContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                              std::vector<ContactPoint>* out) {
  const CollisionShape& si = geometries_[i].shape;
  const CollisionShape& sj = geometries_[j].shape;
  const Cap cap_i = FacingCap(si, X_WI, sj, X_WJ);
  const Cap cap_j = FacingCap(sj, X_WJ, si, X_WI);
  if (!(cap_i.overlap > 0.0) || !(cap_j.overlap > 0.0)) return true;  // apart along an axis
  // Side on side (the axes' segments closer than the radii by less than the caps overlap):
  // not a cap contact.
  const Vector3d hi = 0.5 * si.length * X_WI.R.col(2), hj = 0.5 * sj.length * X_WJ.R.col(2);
  double s = 0.0, t = 0.0;
  Vector3d ci, cj;
  fcl::detail::closestPtSegmentSegment<double>(X_WI.p - hi, X_WI.p + hi, X_WJ.p - hj, X_WJ.p + hj,
                                               &s, &t, &ci, &cj);
  const double side = si.radius + sj.radius - (ci - cj).norm();
  if (!(std::min(cap_i.overlap, cap_j.overlap) < side)) return false;
  // The reference cap: j's, unless i's overlaps less by more than 5 % (a resting pair keeps
  // it, as polytopes keep theirs).
  const bool on_j = cap_j.overlap <= 1.05 * cap_i.overlap;
  const CollisionShape& sp = on_j ? sj : si;  // the reference's cylinder P, the other Q
  const CollisionShape& sq = on_j ? si : sj;
  const Pose& X_WP = on_j ? X_WJ : X_WI;
  const Pose& X_WQ = on_j ? X_WI : X_WJ;
  const Vector3d n = on_j ? cap_j.n : cap_i.n;  // P's cap's outward normal, toward Q
  const double sign = on_j ? 1.0 : -1.0;        // the normal from j toward i
  // In P's cap plane (origin its centre, axes P's x and y): P's rim as a polygon of kRimCorners
  // corners, and Q's facing rim, as many corners fixed in Q, seen along n; Q's clipped to P's
  // (Sutherland-Hodgman), whose corners move with the poses (a corner enters or leaves at an
  // edge crossing, not at a jump).
  const Vector3d centre_p = X_WP.p + 0.5 * sp.length * n;
  const Vector3d u = X_WP.R.col(0), v = X_WP.R.col(1);
  const Vector3d a_q = X_WQ.R.col(2);
  const Vector3d centre_q = X_WQ.p - (n.dot(a_q) >= 0.0 ? 0.5 : -0.5) * sq.length * a_q;
  using Polygon = std::array<Eigen::Vector2d, 2 * kRimCorners + 1>;
  Polygon rim_p, polygon, clipped;
  int count = kRimCorners;
  for (int k = 0; k < kRimCorners; ++k) {
    const double angle = 2.0 * M_PI * k / kRimCorners;
    rim_p[k] = sp.radius * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    const Vector3d x =
        centre_q + sq.radius * (std::cos(angle) * X_WQ.R.col(0) + std::sin(angle) * X_WQ.R.col(1));
    polygon[k] = Eigen::Vector2d(u.dot(x - centre_p), v.dot(x - centre_p));
  }
  // Q's rim runs counter-clockwise about Q's axis: seen along n, clockwise when n and a_q
  // oppose (the usual stack). Clipping needs both counter-clockwise about P's z.
  const bool q_flipped = n.dot(a_q) * n.dot(X_WP.R.col(2)) < 0.0;
  if (q_flipped) std::reverse(polygon.begin(), polygon.begin() + count);
  for (int e = 0; e < kRimCorners && count > 0; ++e) {
    const Eigen::Vector2d& e0 = rim_p[e];
    const Eigen::Vector2d edge = rim_p[(e + 1) % kRimCorners] - e0;
    const auto side = [&](const Eigen::Vector2d& x) {  // > 0 inside (left of the edge)
      const Eigen::Vector2d r = x - e0;
      return edge.x() * r.y() - edge.y() * r.x();
    };
    int kept = 0;
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector2d& x0 = polygon[k];
      const Eigen::Vector2d& x1 = polygon[(k + 1) % count];
      const double s0 = side(x0), s1 = side(x1);
      if (s0 >= 0.0) clipped[kept++] = x0;
      if ((s0 >= 0.0) != (s1 >= 0.0) && kept < static_cast<int>(clipped.size())) {
        clipped[kept++] = x0 + (s0 / (s0 - s1)) * (x1 - x0);
      }
      if (kept >= static_cast<int>(clipped.size())) break;
    }
    std::copy(clipped.begin(), clipped.begin() + kept, polygon.begin());
    count = kept;
  }
  // Each corner on Q's cap plane along n: a point where it is below P's cap.
  const double across = a_q.dot(n);
  if (std::abs(across) < 1e-9) return false;  // Q's cap seen edge on: not a cap contact
  int added = 0;
  for (int k = 0; k < count; ++k) {
    const Vector3d y = centre_p + polygon[k].x() * u + polygon[k].y() * v;  // on P's cap
    const double along = a_q.dot(centre_q - y) / across;  // y + along n is on Q's cap
    const double depth = -along;
    if (!(depth > 0.0)) continue;
    out->push_back(ContactPoint::UnderFace(i, j, y + along * n, n, sign, depth));
    ++added;
  }
  return added > 0;
}

double NarrowPhase::PlaneClearance(int g, const Pose& X_WG, const Vector3d& n,
                                   const Vector3d& on_plane) const {
  const Eigen::Vector4d& bound = fcl_->bounds[static_cast<size_t>(g)];
  return n.dot(X_WG.Apply(bound.head<3>()) - on_plane) - bound(3);
}

bool NarrowPhase::PolytopeContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                                   std::vector<ContactPoint>* out) {
  // Their bounding boxes apart (the separating-axis test of two oriented boxes): so are they.
  if (BoxesApart(fcl_->lower[i], fcl_->upper[i], X_WI, fcl_->lower[j], fcl_->upper[j], X_WJ)) {
    return true;
  }
  const PolytopeFaces& I = fcl_->faces[static_cast<size_t>(i)];
  const PolytopeFaces& J = fcl_->faces[static_cast<size_t>(j)];
  if (PolytopeClip::Affordable(I, J) &&
      fcl_->clip.Collide(i, I, X_WI, j, J, X_WJ, out) != PolytopeClip::Outcome::kEdge) {
    return true;
  }
  return VertexContacts(i, X_WI, j, X_WJ, out) > 0;
}

int NarrowPhase::VertexContacts(int i, const Pose& X_WI, int j, const Pose& X_WJ,
                                std::vector<ContactPoint>* out) {
  int added = 0;
  // Vertices of `from` inside `into`: the normal (from j toward i) along the nearest face of
  // `into`, outward for a vertex of i, inward for a vertex of j.
  const auto inside = [&](int from, const Pose& X_WF, int into, const Pose& X_WT, double sign) {
    const Matrix3d R_TF = X_WT.R.transpose() * X_WF.R;
    const Vector3d p_TF = X_WT.R.transpose() * (X_WF.p - X_WT.p);
    const Vector3d& lower = fcl_->lower[into];
    const Vector3d& upper = fcl_->upper[into];
    // `into`'s bounding box seen from `from`'s frame, boxed again: a vertex outside it is
    // outside `into`, found without transforming it (most of a large hull's vertices).
    const Vector3d centre_F = R_TF.transpose() * (0.5 * (lower + upper) - p_TF);
    const Vector3d half_F = R_TF.transpose().cwiseAbs() * (0.5 * (upper - lower));
    const Eigen::Array3d lower_F = (centre_F - half_F).array(),
                         upper_F = (centre_F + half_F).array();
    for (const Vector3d& v : fcl_->vertices[from]) {
      if ((v.array() < lower_F).any() || (v.array() > upper_F).any()) continue;
      const Vector3d v_T = R_TF * v + p_TF;
      // outside `into`'s bounding box: not inside (the faces' test costs O(faces))
      if ((v_T.array() <= lower.array()).any() || (v_T.array() >= upper.array()).any()) continue;
      Vector3d n_T = Vector3d::UnitZ();
      const double s = DeepestPlane(v_T, fcl_->planes[into], &n_T);
      if (!(s < 0.0)) continue;
      ContactPoint c;
      c.geometry_a = i;
      c.geometry_b = j;
      c.depth = -s;
      const Vector3d n_W = X_WT.R * n_T;  // outward of `into`
      c.normal = sign * n_W;
      c.point = X_WF.Apply(v) + 0.5 * c.depth * n_W;
      out->push_back(c);
      ++added;
    }
  };
  inside(i, X_WI, j, X_WJ, 1.0);
  inside(j, X_WJ, i, X_WI, -1.0);
  return added;
}

bool NarrowPhase::FaceContacts(int i, int j, int round, const Pose& X_WR, int poly,
                               const Pose& X_WP, std::vector<ContactPoint>* out) {
  const CollisionShape& s = geometries_[round].shape;
  const std::vector<Eigen::Vector4d>& planes = fcl_->planes[poly];
  const Vector3d axis = X_WR.R.col(2);
  // The face of least overlap: along each outward face normal n (world), the polytope reaches
  // h = n.p_P + d and the round shape down to n.c - (L/2)|n.a| - r (times sin(n, a) for a
  // cylinder's disc); the overlap is the difference.
  double least = std::numeric_limits<double>::infinity();
  int face = -1;
  for (size_t f = 0; f < planes.size(); ++f) {
    const Vector3d n = X_WP.R * planes[f].head<3>();
    const double along = n.dot(axis);
    const double radial = s.type == ShapeType::kCylinder
                              ? s.radius * std::sqrt(std::max(0.0, 1.0 - along * along))
                              : s.radius;
    const double lowest = n.dot(X_WR.p) - 0.5 * s.length * std::abs(along) - radial;
    const double overlap = n.dot(X_WP.p) + planes[f](3) - lowest;
    if (overlap < least) {
      least = overlap;
      face = static_cast<int>(f);
    }
  }
  if (!(least > 0.0)) return true;  // apart along that face's normal
  if (face < 0) return false;
  const Vector3d n = X_WP.R * planes[static_cast<size_t>(face)].head<3>();
  const double h = n.dot(X_WP.p) + planes[static_cast<size_t>(face)](3);
  const double sign = round == i ? 1.0 : -1.0;  // the normal from j toward i
  int added = 0;
  PlaneCandidates(s, X_WR, n, [&](const Vector3d& x, double weight) {
    const double depth = h - n.dot(x);
    if (!(depth > 0.0)) return;
    const Vector3d x_P = X_WP.R.transpose() * (x - X_WP.p);
    for (size_t g = 0; g < planes.size(); ++g) {  // under the face, inside the others
      if (static_cast<int>(g) != face && planes[g].head<3>().dot(x_P) - planes[g](3) > 0.0) return;
    }
    out->push_back(ContactPoint::UnderFace(i, j, x, n, sign, depth));
    out->back().weight = weight;
    ++added;
  });
  return added > 0;
}

double NarrowPhase::SignedDistance(int a, const Pose& X_WA, int b, const Pose& X_WB,
                                   double margin) {
  ShapeType ta = geometries_[a].shape.type;
  ShapeType tb = geometries_[b].shape.type;
  if (ta == ShapeType::kPlane && tb == ShapeType::kPlane) return margin;
  if (static_cast<int>(ta) > static_cast<int>(tb)) {
    std::swap(a, b);
    std::swap(ta, tb);
    return SignedDistance(a, X_WB, b, X_WA, margin);
  }
  if (tb == ShapeType::kPlane) {
    const Vector3d n = X_WB.R.col(2);
    // Its bounding sphere above the plane: that height, a lower bound of the distance, is
    // positive as the distance is (a root function needs the sign; it is exact from contact on).
    if (const double clearance = PlaneClearance(a, X_WA, n, X_WB.p); clearance > 0.0) {
      return clearance;
    }
    double lowest = std::numeric_limits<double>::infinity();
    PlaneCandidates(geometries_[a].shape, X_WA, n, [&](const Vector3d& x, double) {
      lowest = std::min(lowest, n.dot(x - X_WB.p));
    });
    return lowest;
  }
  const CollisionShape& sa = geometries_[a].shape;
  const CollisionShape& sb = geometries_[b].shape;
  const bool round_a = ta == ShapeType::kSphere || ta == ShapeType::kCapsule;
  const bool round_b = tb == ShapeType::kSphere || tb == ShapeType::kCapsule;
  if (round_a && round_b) {  // segments (a sphere's of length 0) less the radii
    const double la = ta == ShapeType::kCapsule ? sa.length : 0.0;
    const double lb = tb == ShapeType::kCapsule ? sb.length : 0.0;
    const Vector3d ha = 0.5 * la * X_WA.R.col(2), hb = 0.5 * lb * X_WB.R.col(2);
    double s = 0.0, t = 0.0;
    Vector3d ca, cb;
    fcl::detail::closestPtSegmentSegment<double>(X_WA.p - ha, X_WA.p + ha, X_WB.p - hb, X_WB.p + hb,
                                                 &s, &t, &ca, &cb);
    return (ca - cb).norm() - sa.radius - sb.radius;
  }
  if (ta == ShapeType::kSphere && (tb == ShapeType::kBox || tb == ShapeType::kCylinder)) {
    const auto& sphere = static_cast<const fcl::Sphered&>(*fcl_->shapes[a]);
    double distance = -1.0;
    const bool apart =
        tb == ShapeType::kBox
            ? fcl::detail::sphereBoxDistance<double>(
                  sphere, ToFcl(X_WA), static_cast<const fcl::Boxd&>(*fcl_->shapes[b]), ToFcl(X_WB),
                  &distance, nullptr, nullptr)
            : fcl::detail::sphereCylinderDistance<double>(
                  sphere, ToFcl(X_WA), static_cast<const fcl::Cylinderd&>(*fcl_->shapes[b]),
                  ToFcl(X_WB), &distance, nullptr, nullptr);
    if (apart && distance >= 0.0) return distance;
  }
  if (ta == ShapeType::kSphere && tb == ShapeType::kConvex) {
    Vector3d n_B;
    return PointConvexDistance(X_WB.R.transpose() * (X_WA.p - X_WB.p), sb.convex, fcl_->planes[b],
                               &n_B) -
           sa.radius;
  }
  if (ta == ShapeType::kCylinder && tb == ShapeType::kCylinder) {
    // Apart along a cap's axis: that gap, a lower bound of the distance.
    const double gap =
        -std::min(FacingCap(sa, X_WA, sb, X_WB).overlap, FacingCap(sb, X_WB, sa, X_WA).overlap);
    if (gap > 0.0) return std::min(margin, gap);
  }
  // No distance routine for the pair: apart when their bounding spheres are (the common case
  // of a robot's many root pairs: no narrow phase, no libccd); two polytopes: the separating
  // axes' separation; else minus the depth.
  const Eigen::Vector4d& ba = fcl_->bounds[a];
  const Eigen::Vector4d& bb = fcl_->bounds[b];
  if ((X_WA.Apply(ba.head<3>()) - X_WB.Apply(bb.head<3>())).norm() > ba(3) + bb(3)) return margin;
  const bool polytope_a = ta == ShapeType::kBox || ta == ShapeType::kConvex;
  const bool polytope_b = tb == ShapeType::kBox || tb == ShapeType::kConvex;
  if (polytope_a && polytope_b) {
    const PolytopeFaces& A = fcl_->faces[static_cast<size_t>(a)];
    const PolytopeFaces& B = fcl_->faces[static_cast<size_t>(b)];
    if (PolytopeClip::Affordable(A, B)) {
      return std::min(margin, fcl_->clip.Separation(A, X_WA, B, X_WB));
    }
  }
  scratch_.clear();
  Collide(a, X_WA, b, X_WB, &scratch_);
  double deepest = 0.0;
  for (const ContactPoint& c : scratch_) deepest = std::max(deepest, c.depth);
  return scratch_.empty() ? margin : -deepest;
}

}  // namespace mbstream
