#include "server/contact/contact_forces.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/convex.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/collision_object.h>

#include "server/contact/contact_law.h"
#include "server/contact/point_forces.h"
#include "server/kinematics/forward_kinematics.h"

namespace mbstream {

namespace {

// The broad phase's boxes are the shapes grown by this much (m), so that pairs about to touch
// are candidates too.
constexpr double kBroadMargin = 1e-3;

// The box [lower, upper] (in the geometry's frame, not centred on it) as an fcl::Convex: a
// convex polytope's broad-phase shape (its vertices are all the broad phase looks at).
std::shared_ptr<fcl::CollisionGeometryd> GrownBoundingBox(const Vector3d& lower,
                                                          const Vector3d& upper) {
  auto corners = std::make_shared<std::vector<Vector3d>>();
  for (int k = 0; k < 8; ++k) {
    corners->emplace_back(k & 1 ? upper.x() : lower.x(), k & 2 ? upper.y() : lower.y(),
                          k & 4 ? upper.z() : lower.z());
  }
  // The six faces, counter-clockwise seen from outside.
  auto faces = std::make_shared<std::vector<int>>(std::vector<int>{
      4, 0, 2, 3, 1, 4, 4, 5, 7, 6, 4, 0, 1, 5, 4, 4, 2, 6, 7, 3, 4, 0, 4, 6, 2, 4, 1, 3, 7, 5});
  return std::make_shared<fcl::Convexd>(std::move(corners), 6, std::move(faces));
}

std::shared_ptr<fcl::CollisionGeometryd> GrownShape(const CollisionShape& s) {
  const double m = kBroadMargin;
  switch (s.type) {
    case ShapeType::kSphere:
      return std::make_shared<fcl::Sphered>(s.radius + m);
    case ShapeType::kBox:
      return std::make_shared<fcl::Boxd>(s.size + Vector3d::Constant(2 * m));
    case ShapeType::kCylinder:
      return std::make_shared<fcl::Cylinderd>(s.radius + m, s.length + 2 * m);
    case ShapeType::kCapsule:
      return std::make_shared<fcl::Capsuled>(s.radius + m, s.length);
    case ShapeType::kConvex:
      return GrownBoundingBox(s.convex.lower - Vector3d::Constant(m),
                              s.convex.upper + Vector3d::Constant(m));
    case ShapeType::kPlane:
      return nullptr;
  }
  return nullptr;
}

double Or(double value, double fallback) { return std::isnan(value) ? fallback : value; }

// The body each body hangs from (a ball joint's child hangs from its parent directly).
std::vector<int> FileParents(const Model& model) {
  std::vector<int> parent(model.bodies.size());
  for (size_t b = 0; b < model.bodies.size(); ++b) parent[b] = model.bodies[b].parent;
  return parent;
}

bool Adjacent(const Model& model, const std::vector<int>& parent, int a, int b) {
  if (a != kBase && parent[a] == b && !model.bodies[a].free()) return true;
  if (b != kBase && parent[b] == a && !model.bodies[b].free()) return true;
  return false;
}

// The first body of the mechanism a body belongs to: up its parents (the file's) to one that
// hangs from the world or on a free joint (a free body is a mechanism of its own).
int MechanismOf(const Model& model, const std::vector<int>& parent, int body) {
  if (body == kBase) return kBase;
  while (parent[body] != kBase && !model.bodies[body].free()) body = parent[body];
  return body;
}

bool Filtered(const ContactSettings& settings, const CollisionGeometry& a,
              const CollisionGeometry& b) {
  auto names = [](const CollisionGeometry& g, const std::string& name) {
    return name == g.link || (!g.name.empty() && name == g.name);
  };
  for (const auto& [first, second] : settings.filter) {
    if ((names(a, first) && names(b, second)) || (names(a, second) && names(b, first))) return true;
  }
  return false;
}

fcl::Transform3d BroadTransform(const Pose& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.R;
  T.translation() = X.p;
  return T;
}

}  // namespace

double ContactPeriod(const Model& model, const ContactSettings& settings) {
  double mass = std::numeric_limits<double>::infinity();
  double stiffness = 0.0;
  for (const CollisionGeometry& g : model.collisions) {
    stiffness = std::max(stiffness, Or(g.surface.stiffness, settings.stiffness));
    if (g.body != kBase) mass = std::min(mass, model.bodies[g.body].inertia.mass);
  }
  if (!(stiffness > 0.0) || !std::isfinite(mass) || !(mass > 0.0)) {
    return std::numeric_limits<double>::infinity();
  }
  return M_PI * std::sqrt(mass / stiffness);
}

struct ContactForces::Broad {
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> objects;  // one per entry of others_
  fcl::DynamicAABBTreeCollisionManagerd manager;
};

ContactForces::ContactForces(const Model& model, const ContactSettings& settings)
    : model_(model),
      settings_(settings),
      n_(static_cast<int>(model.collisions.size())),
      allowed_(static_cast<size_t>(n_) * n_, 0),
      X_W_(n_),
      narrow_(model.collisions),
      broad_(std::make_unique<Broad>()) {
  const std::vector<CollisionGeometry>& geometries = model.collisions;
  for (const CollisionGeometry& g : geometries) {
    surfaces_.push_back({Or(g.surface.stiffness, settings.stiffness),
                         Or(g.surface.dissipation, settings.dissipation),
                         Or(g.surface.mu_static, settings.mu_static),
                         Or(g.surface.mu_dynamic, settings.mu_dynamic)});
  }
  if (!settings.enabled || n_ < 2) return;
  const std::vector<int> parent = FileParents(model);
  for (int a = 0; a < n_; ++a) {
    for (int b = a + 1; b < n_; ++b) {
      const CollisionGeometry& ga = geometries[a];
      const CollisionGeometry& gb = geometries[b];
      const bool ok = ga.body != gb.body && !Adjacent(model, parent, ga.body, gb.body) &&
                      (ga.collide_bitmask & gb.collide_bitmask) != 0 &&
                      !(ga.shape.type == ShapeType::kPlane && gb.shape.type == ShapeType::kPlane) &&
                      !Filtered(settings, ga, gb);
      allowed_[a * n_ + b] = allowed_[b * n_ + a] = ok ? 1 : 0;
      num_allowed_ += ok ? 1 : 0;
      if (ok && static_cast<int>(root_pairs_.size()) < kMaxRootPairs)
        root_pairs_.emplace_back(a, b);
    }
  }
  DropOverlapsAtRest(parent);
  active_ = num_allowed_ > 0;
  if (!active_) return;
  for (int g = 0; g < n_; ++g) {
    const Pose X_WG =
        geometries[g].body == kBase ? geometries[g].X_BG : Pose::Identity() * geometries[g].X_BG;
    X_W_[g] = X_WG;
    if (geometries[g].shape.type == ShapeType::kPlane) {
      planes_.push_back(g);
      continue;
    }
    others_.push_back(g);
    auto object = std::make_unique<fcl::CollisionObjectd>(GrownShape(geometries[g].shape),
                                                          BroadTransform(X_WG));
    object->setUserData(reinterpret_cast<void*>(static_cast<intptr_t>(g)));
    broad_->manager.registerObject(object.get());
    broad_->objects.push_back(std::move(object));
  }
  broad_->manager.setup();
  pairs_.reserve(static_cast<size_t>(num_allowed_));
  contacts_.reserve(8 * static_cast<size_t>(n_) + 16);
}

ContactForces::~ContactForces() = default;

void ContactForces::DropOverlapsAtRest(const std::vector<int>& parent) {
  const std::vector<CollisionGeometry>& geometries = model_.collisions;
  std::vector<int> mechanism(static_cast<size_t>(n_));
  bool any = false;
  for (int a = 0; a < n_ && !any; ++a) {
    for (int b = a + 1; b < n_ && !any; ++b) {
      any = Allowed(a, b) && geometries[a].body != kBase && geometries[b].body != kBase &&
            MechanismOf(model_, parent, geometries[a].body) ==
                MechanismOf(model_, parent, geometries[b].body);
    }
  }
  if (!any) return;
  Data data(model_);
  Eigen::VectorXd q(model_.nq());
  NeutralPositions(model_, q.data());
  BodyKinematics(model_, data, q);
  std::vector<Pose> X_W(static_cast<size_t>(n_));
  for (int g = 0; g < n_; ++g) {
    const CollisionGeometry& geometry = geometries[g];
    X_W[g] = geometry.body == kBase ? geometry.X_BG : data.X_world[geometry.body] * geometry.X_BG;
    mechanism[g] = MechanismOf(model_, parent, geometry.body);
  }
  for (int a = 0; a < n_; ++a) {
    for (int b = a + 1; b < n_; ++b) {
      if (!Allowed(a, b) || mechanism[a] == kBase || mechanism[a] != mechanism[b]) continue;
      if (narrow_.SignedDistance(a, X_W[a], b, X_W[b], 1.0) >= 0.0) continue;
      allowed_[a * n_ + b] = allowed_[b * n_ + a] = 0;
      --num_allowed_;
      ++num_overlapping_at_rest_;
    }
  }
  root_pairs_.clear();
  for (int a = 0; a < n_; ++a) {
    for (int b = a + 1; b < n_; ++b) {
      if (Allowed(a, b) && static_cast<int>(root_pairs_.size()) < kMaxRootPairs) {
        root_pairs_.emplace_back(a, b);
      }
    }
  }
}

void ContactForces::UpdatePoses(const ContactBodies& bodies) {
  for (size_t k = 0; k < others_.size(); ++k) {
    const int g = others_[k];
    const CollisionGeometry& geometry = model_.collisions[g];
    if (geometry.body == kBase) continue;
    X_W_[g] = bodies.X_world(geometry.body) * geometry.X_BG;
    broad_->objects[k]->setTransform(BroadTransform(X_W_[g]));
    broad_->objects[k]->computeAABB();
  }
  for (const int g : planes_) {
    const CollisionGeometry& geometry = model_.collisions[g];
    if (geometry.body != kBase) X_W_[g] = bodies.X_world(geometry.body) * geometry.X_BG;
  }
  broad_->manager.update();
}

bool ContactForces::OnPair(void* o1, void* o2, void* self) {
  auto* forces = static_cast<ContactForces*>(self);
  const int a = static_cast<int>(
      reinterpret_cast<intptr_t>(static_cast<fcl::CollisionObjectd*>(o1)->getUserData()));
  const int b = static_cast<int>(
      reinterpret_cast<intptr_t>(static_cast<fcl::CollisionObjectd*>(o2)->getUserData()));
  if (forces->Allowed(a, b) && forces->pairs_.size() < forces->pairs_.capacity()) {
    forces->pairs_.emplace_back(std::min(a, b), std::max(a, b));
  }
  return false;  // go on
}

void ContactForces::Candidates() {
  pairs_.clear();
  broad_->manager.collide(static_cast<void*>(this),
                          [](fcl::CollisionObjectd* o1, fcl::CollisionObjectd* o2, void* self) {
                            return OnPair(o1, o2, self);
                          });
  for (const int p : planes_) {
    for (const int g : others_) {
      if (Allowed(p, g) && pairs_.size() < pairs_.capacity()) {
        pairs_.emplace_back(std::min(p, g), std::max(p, g));
      }
    }
  }
  // The broad phase's order depends on its tree: sort, so that the forces are summed in one
  // order whatever the tree did (bit-for-bit repeatable runs).
  std::sort(pairs_.begin(), pairs_.end());
}

void ContactForces::SignedDistances(const Data& data, double* g) {
  SignedDistances(JointContactBodies(model_, data, nullptr, nullptr), g);
}

void ContactForces::SignedDistances(const ContactBodies& bodies, double* g) {
  for (int k = 0; k < n_; ++k) {
    const CollisionGeometry& geometry = model_.collisions[k];
    if (geometry.body != kBase) X_W_[k] = bodies.X_world(geometry.body) * geometry.X_BG;
  }
  // Far pairs: their distance, or 1 m when the narrow phase has none (then the sign changes
  // only at contact: CVODE and ARKODE still find the time).
  for (size_t k = 0; k < root_pairs_.size(); ++k) {
    const auto [a, b] = root_pairs_[k];
    g[k] = narrow_.SignedDistance(a, X_W_[a], b, X_W_[b], 1.0);
  }
}

bool ContactForces::AddForces(const Data& data, const Eigen::VectorXd& qd, Eigen::VectorXd* tau) {
  JointContactBodies bodies(model_, data, &qd, tau);
  return AddForces(bodies);
}

bool ContactForces::AddForces(ContactBodies& bodies) {
  contacts_.clear();
  dissipated_power_ = 0.0;
  if (!active_) return true;
  UpdatePoses(bodies);
  Candidates();
  // Each pair's points, and the share of the pair's stiffness each takes: w_i delta_i over the
  // sum of w delta (w the point's weight, 1 but for a tilting cylinder's rim).
  for (const auto& [a, b] : pairs_) {
    const size_t first = contacts_.size();
    narrow_.Collide(a, X_W_[a], b, X_W_[b], &contacts_);
    double sum = 0.0;
    for (size_t k = first; k < contacts_.size(); ++k)
      sum += contacts_[k].weight * contacts_[k].depth;
    for (size_t k = first; k < contacts_.size(); ++k) {
      contacts_[k].share = contacts_[k].weight * contacts_[k].depth / sum;
    }
  }
  const double v_s = settings_.stiction_tolerance;
  bool finite = true;
  for (ContactPoint& c : contacts_) {
    const ResolvedSurface& sa = surfaces_[c.geometry_a];
    const ResolvedSurface& sb = surfaces_[c.geometry_b];
    const double k = contact_law::CombineStiffness(sa.stiffness, sb.stiffness);
    const double d =
        contact_law::CombineDissipation(sa.stiffness, sa.dissipation, sb.stiffness, sb.dissipation);
    const double mu_s = contact_law::CombineFriction(sa.mu_static, sb.mu_static);
    const double mu_d = contact_law::CombineFriction(sa.mu_dynamic, sb.mu_dynamic);
    const int body_a = model_.collisions[c.geometry_a].body;
    const int body_b = model_.collisions[c.geometry_b].body;
    const Vector3d v = bodies.PointVelocity(body_a, c.point) -
                       bodies.PointVelocity(body_b, c.point);  // a relative to b
    const double vn = v.dot(c.normal);
    c.normal_force = contact_law::NormalForce(c.share * k, d, c.depth, -vn);
    double spring = contact_law::NormalForce(c.share * k, 0.0, c.depth, 0.0);
    if (settings_.hertz_modulus > 0.0) {  // Hertz for a sphere against a sphere or a plane
      const CollisionShape& a = model_.collisions[c.geometry_a].shape;
      const CollisionShape& b = model_.collisions[c.geometry_b].shape;
      const auto radius = [](const CollisionShape& s) {
        return s.type == ShapeType::kSphere  ? s.radius
               : s.type == ShapeType::kPlane ? std::numeric_limits<double>::infinity()
                                             : -1.0;
      };
      const double ra = radius(a), rb = radius(b);
      if (ra > 0.0 && rb > 0.0 && !(std::isinf(ra) && std::isinf(rb))) {
        const double hertz = contact_law::HertzStiffness(settings_.hertz_modulus, ra, rb);
        c.normal_force = contact_law::HertzNormalForce(hertz, d, c.depth, -vn);
        spring = contact_law::HertzNormalForce(hertz, 0.0, c.depth, 0.0);
      }
    }
    const Vector3d vt = v - vn * c.normal;
    const double speed = vt.norm();
    c.friction_force.setZero();
    if (speed > 1e-14) {
      c.friction_force =
          -(contact_law::StribeckMu(speed, mu_s, mu_d, v_s) * c.normal_force / speed) * vt;
    }
    const Vector3d f = c.normal_force * c.normal + c.friction_force;
    finite = finite && f.allFinite();
    // The normal force's damping part against the penetration rate -vn, and the friction's.
    dissipated_power_ += (c.normal_force - spring) * -vn - c.friction_force.dot(vt);
    bodies.AddPointForce(body_a, c.point, f);
    bodies.AddPointForce(body_b, c.point, -f);
  }
  return finite;
}

}  // namespace mbstream
