// The body-coordinate DAE for IDA: unknowns y = [positions (7n); velocities (6n);
// multipliers (m)], residual
//   dx/dt - v = 0,  de/dt - 1/2 e (x) (0, w) = 0,  M dnu/dt - f - G^T lambda = 0,
//   and the constraints at position level (body-index3: g(x, t) = 0) or at velocity level
//   (body-index2: G nu + g_t = 0; positions then drift, and the drift is measured).
#pragma once

#include <vector>

#include "server/body/body_mechanics.h"
#include "server/body/body_model.h"
#include "server/integrate/ida_system.h"

namespace mbstream {

enum class ConstraintLevel {
  kPosition,  // index 3
  kVelocity,  // index 2
};

// The structural pattern of dF/dy + cj dF/dy' of the body DAE (CSC).
void BodyDaePattern(const BodyModel& bm, ConstraintLevel level, std::vector<int>* column_starts,
                    std::vector<int>* row_indices);

class BodyDae : public DaeSystem {
 public:
  // Keeps references to its arguments, which must outlive it.
  BodyDae(const BodyModel& body_model, const DriveSet& drives, ConstraintLevel level);

  int size() const override { return bm_.dae_size(); }
  int Residual(double t, const double* y, const double* yp, double* r) override;
  void DifferentialIds(double* id) const override;
  const std::vector<int>& JacobianColumnStarts() const override { return column_starts_; }
  const std::vector<int>& JacobianRowIndices() const override { return row_indices_; }

  BodyMechanics& mechanics() { return mechanics_; }

 private:
  const BodyModel& bm_;
  ConstraintLevel level_;
  BodyMechanics mechanics_;
  std::vector<int> column_starts_, row_indices_;
};

}  // namespace mbstream
