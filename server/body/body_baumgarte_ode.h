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
  // the work W(t) of the drives and the joint damping (see Quadrature).
  BodyBaumgarteOde(const BodyModel& body_model, const DriveSet& drives,
                   const BaumgarteParameters& parameters, bool track_work = false);

  int size() const override { return bm_.ode_size(); }
  int Rhs(double t, const double* y, double* ydot) override;

  // W' = sum_j (effort_j - damping_j qd_j) qd_j, J/s, as BodyReadout reports the efforts
  // (a prescribed joint's is its drive constraint's multiplier) and the joint rates:
  // integrated with the ODE, the energy balance measures the integration, not a quadrature
  // over the output frames. Allocates nothing.
  int num_quadratures() const override { return track_work_ ? 1 : 0; }
  int Quadrature(double t, const double* y, double* qdot) override;
  // Rhs and Quadrature from one evaluation of the mechanics, bit for bit the two calls'.
  int RhsAndQuadrature(double t, const double* y, double* ydot, double* qdot) override;

  // Structural non-zeros of df/dy: the kinematic rows (dx/dt = v: 3 per body; de/dt: 7 per
  // row) and dense acceleration rows (every acceleration depends on every position and
  // velocity through the multipliers).
  int JacobianNonZeros() const;

  BodyMechanics& mechanics() { return mechanics_; }

 private:
  double Power() const;  // W' after Rhs's evaluation

  const BodyModel& bm_;
  BaumgarteParameters parameters_;
  BodyMechanics mechanics_;
  const bool track_work_;
  Eigen::VectorXd ydot_;  // for Quadrature alone: Rhs's output, discarded
};

}  // namespace mbstream
