// The body-baumgarte formulation: the body equations at acceleration level with Baumgarte
// stabilisation, d2g/dt2 + alpha dg/dt + beta g = 0, as an ODE in y = [positions (7n);
// velocities (6n)] for CVODE, ARKODE or the fixed-step methods. The multipliers are solved
// at every evaluation (a dense Schur complement of the constraint rows); they are not states.
#pragma once

#include "server/body/baumgarte_parameters.h"
#include "server/body/body_mechanics.h"
#include "server/body/body_model.h"
#include "server/integrate/ode_system.h"

namespace mbstream {

class BodyBaumgarteOde : public OdeSystem {
 public:
  // Keeps references to its arguments, which must outlive it. `track_work`: one quadrature,
  // the work W(t) of the drives and the joint damping (see Quadrature). `contact`, when given
  // (not owned, outlives it), adds the contact forces to the bodies at every evaluation
  // (body_contact.h); the work then includes their power, and a second quadrature integrates
  // the power they dissipate (ContactForces::dissipated_power).
  BodyBaumgarteOde(const BodyModel& body_model, const DriveSet& drives,
                   const BaumgarteParameters& parameters, bool track_work = false,
                   ContactForces* contact = nullptr);

  int size() const override { return bm_.ode_size(); }
  int Rhs(double t, const double* y, double* ydot) override;

  // W' = sum_j (effort_j - damping_j qd_j) qd_j, J/s, as BodyReadout reports the efforts
  // (a prescribed joint's is its drive constraint's multiplier) and the joint rates:
  // integrated with the ODE, the energy balance measures the integration, not a quadrature
  // over the output frames. Allocates nothing.
  int num_quadratures() const override {
    return track_work_ ? (mechanics_.contact() != nullptr ? 2 : 1) : 0;
  }
  int Quadrature(double t, const double* y, double* qdot) override;
  // Rhs and Quadrature from one evaluation of the mechanics, bit for bit the two calls'.
  int RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) override;

  // With contact: the signed distances of the contact's root pairs (ContactForces::
  // SignedDistances), so that CVODE and ARKODE end a step where a contact begins or ends.
  // Allocates nothing.
  int num_roots() const override;
  int Roots(double t, const double* y, double* g) override;

  // Structural non-zeros of df/dy: the kinematic rows (dx/dt = v: 3 per body; de/dt: 7 per
  // row) and dense acceleration rows (every acceleration depends on every position and
  // velocity through the multipliers).
  int JacobianNonZeros() const;

  BodyMechanics& mechanics() { return mechanics_; }
  // The contacts of the last evaluation (null without contact).
  const ContactForces* contact() const;

 private:
  double Power() const;  // W' after Rhs's evaluation, the contacts' power included

  const BodyModel& bm_;
  BaumgarteParameters parameters_;
  BodyMechanics mechanics_;
  const bool track_work_;
  Eigen::VectorXd ydot_;  // for Quadrature alone: Rhs's output, discarded
};

}  // namespace mbstream
