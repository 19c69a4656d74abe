// A differential-algebraic system F(t, y, y') = 0, as IDA sees it: no mechanics.
#pragma once

#include <vector>

namespace mbstream {

class DaeSystem {
 public:
  virtual ~DaeSystem() = default;

  // Number of equations = number of unknowns (the length of y and y').
  virtual int size() const = 0;

  // r = F(t, y, yp). Returns 0 on success, > 0 for a recoverable failure (the solver
  // retries with a smaller step), < 0 for an unrecoverable one. Called on the hot path:
  // must not allocate.
  virtual int Residual(double t, const double* y, const double* yp, double* r) = 0;

  // id[i] = 1 for a differential unknown (y'_i appears in F), 0 for an algebraic one.
  virtual void DifferentialIds(double* id) const = 0;

  // The structural non-zeros of the iteration matrix dF/dy + cj dF/dy' in compressed
  // sparse column form: column j's rows are row_indices[column_starts[j] ..
  // column_starts[j + 1] - 1], ascending. Entries outside the pattern must be zero for every
  // (t, y, y'); the integrator fills the pattern by coloured finite differences.
  virtual const std::vector<int>& JacobianColumnStarts() const = 0;
  virtual const std::vector<int>& JacobianRowIndices() const = 0;
  int JacobianNonZeros() const { return static_cast<int>(JacobianRowIndices().size()); }
};

}  // namespace mbstream
