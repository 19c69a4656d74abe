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
  // Keeps references to its arguments, which must outlive it.
  BodyBaumgarteOde(const BodyModel& body_model, const DriveSet& drives,
                   const BaumgarteParameters& parameters);

  int size() const override { return bm_.ode_size(); }
  int Rhs(double t, const double* y, double* ydot) override;

  // Structural non-zeros of df/dy: the kinematic rows (dx/dt = v: 3 per body; de/dt: 7 per
  // row) and dense acceleration rows (every acceleration depends on every position and
  // velocity through the multipliers).
  int JacobianNonZeros() const;

  BodyMechanics& mechanics() { return mechanics_; }

 private:
  const BodyModel& bm_;
  BaumgarteParameters parameters_;
  BodyMechanics mechanics_;
};

}  // namespace mbstream
