// The contact forces of a run: which geometry pairs may touch, the broad phase (FCL's dynamic
// AABB tree), the narrow phase (narrow_phase.h), the contact law (contact_law.h) and the
// generalised forces J^T f (point_forces.h). docs/contact.md states the law.
//
// What may touch: two geometries on different bodies that are not adjacent (a body and its
// parent through a revolute, prismatic or ball joint; a free joint makes no adjacency, so a
// free body touches the world), not both fixed in the world, whose collide bitmasks share a
// bit, that no pair of the run's filter names (by link or collision name), and, for two
// geometries of one mechanism (bodies joined by joints other than free ones, not the world),
// that do not overlap at the model's default pose (the neutral q): a robot's link meshes'
// hulls often reach into their neighbours' (Atlas: 8 pairs, up to 7.8 cm), and would push
// the robot apart. Planes are tested against every geometry they may touch, outside the tree
// (their boxes are infinite).
//
// Built once per run (it allocates); AddForces allocates nothing once its buffers have grown
// to the run's largest contact count (reserved for 8 points per geometry at the start), except
// the pairs the narrow phase hands to libccd (narrow_phase.h).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "server/contact/contact_bodies.h"
#include "server/contact/contact_point.h"
#include "server/contact/contact_settings.h"
#include "server/contact/narrow_phase.h"
#include "server/model/data.h"
#include "server/model/model.h"

namespace mbstream {

// One geometry's surface parameters after the run's defaults filled what the model left out.
struct ResolvedSurface {
  double stiffness = 0.0, dissipation = 0.0, mu_static = 0.0, mu_dynamic = 0.0;
};

// The shortest period of a contact of the model: pi sqrt(m / k) with m the lightest mass of a
// body that carries geometry and k the stiffest surface (s; infinity with no geometry on a
// moving body). The joint-space run caps an adaptive method's step at kContactStepsPerPeriod
// of it while contact may act, so that no step jumps from free flight deep into a surface.
double ContactPeriod(const Model& model, const ContactSettings& settings);
inline constexpr double kContactStepsPerPeriod = 8.0;

class ContactForces {
 public:
  // Keeps a reference to `model`, which must outlive it.
  ContactForces(const Model& model, const ContactSettings& settings);
  ~ContactForces();
  ContactForces(const ContactForces&) = delete;
  ContactForces& operator=(const ContactForces&) = delete;

  // Whether any pair may touch (contact enabled, geometry present, some pair allowed).
  bool active() const { return active_; }
  int num_allowed_pairs() const { return num_allowed_; }
  // The pairs of one mechanism left out because they overlap at the default pose.
  int num_overlapping_at_rest() const { return num_overlapping_at_rest_; }

  // After BodyKinematics (or ForwardKinematics) for q: finds the contacts, fills their forces
  // and adds their generalised forces to *tau (nv values). Returns false when a force is not
  // finite. Allocates nothing (see above).
  bool AddForces(const Data& data, const Eigen::VectorXd& qd, Eigen::VectorXd* tau);
  // The same for any formulation's state (contact_bodies.h): the forces go to `bodies`.
  bool AddForces(ContactBodies& bodies);

  // The pairs whose signed distances are root functions of the integration (CVODE, ARKODE:
  // a step ends where a contact begins or ends): every allowed pair, at most kMaxRootPairs
  // (the first in geometry order beyond that).
  static constexpr int kMaxRootPairs = 256;
  int num_root_pairs() const { return static_cast<int>(root_pairs_.size()); }
  // After BodyKinematics for q: g[k] = the signed distance of root pair k (m, < 0 when they
  // overlap; narrow_phase.h says for which shapes it is exact). Allocates nothing.
  void SignedDistances(const Data& data, double* g);
  void SignedDistances(const ContactBodies& bodies, double* g);

  // The contacts of the last AddForces.
  const std::vector<ContactPoint>& contacts() const { return contacts_; }
  // The power the contacts of the last AddForces dissipate (W, >= 0): each point's normal force
  // less its spring part (the law at zero rate: k delta, or Hertz's) times the penetration
  // rate, and its friction force against the sliding velocity. The run integrates it as a
  // quadrature: the dissipated contact work (RunStats.contact).
  double dissipated_power() const { return dissipated_power_; }
  const ResolvedSurface& surface(int geometry) const { return surfaces_[geometry]; }
  bool Allowed(int a, int b) const { return allowed_[a * n_ + b] != 0; }
  const Model& model() const { return model_; }

 private:
  struct Broad;
  static bool OnPair(void* o1, void* o2, void* self);
  void UpdatePoses(const ContactBodies& bodies);
  void DropOverlapsAtRest(const std::vector<int>& parent);
  void Candidates();

  const Model& model_;
  const ContactSettings settings_;
  const int n_;  // geometries
  bool active_ = false;
  int num_allowed_ = 0;
  int num_overlapping_at_rest_ = 0;
  std::vector<unsigned char> allowed_;  // n x n, symmetric
  std::vector<ResolvedSurface> surfaces_;
  std::vector<int> planes_, others_;        // geometry indices
  std::vector<Pose> X_W_;                   // each geometry's pose in the world
  std::vector<std::pair<int, int>> pairs_;  // the broad phase's candidates
  std::vector<std::pair<int, int>> root_pairs_;
  std::vector<ContactPoint> contacts_;
  double dissipated_power_ = 0.0;
  NarrowPhase narrow_;
  std::unique_ptr<Broad> broad_;
};

}  // namespace mbstream
