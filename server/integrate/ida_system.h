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

  // atols[i]: the absolute tolerance of unknown i (IDASVtolerances), given the run's atol, which
  // is in the units of the differential unknowns, and the consistent start y0. By default
  // atol for every unknown. A system whose algebraic unknowns are multipliers says so here:
  // MultiplierTolerances below.
  virtual void AbsoluteTolerances(double atol, const double* /*y0*/, double* atols) const {
    for (int i = 0; i < size(); ++i) atols[i] = atol;
  }

  // The structural non-zeros of the iteration matrix dF/dy + cj dF/dy' in compressed
  // sparse column form: column j's rows are row_indices[column_starts[j] ..
  // column_starts[j + 1] - 1], ascending. Entries outside the pattern must be zero for every
  // (t, y, y'); the integrator fills the pattern by coloured finite differences.
  virtual const std::vector<int>& JacobianColumnStarts() const = 0;
  virtual const std::vector<int>& JacobianRowIndices() const = 0;
  int JacobianNonZeros() const { return static_cast<int>(JacobianRowIndices().size()); }
};

// The multipliers' absolute tolerance relative to their scale (MultiplierTolerances).
// Measured on the five linkages of models/linkages with the GGL DAE at rtol 1e-5 to 1e-11:
// 1e-7 still fails at 1e-10 and 1e-11, 1e-5 takes up to 50 % more steps (docs/closed_loops.md).
inline constexpr double kMultiplierNoiseFloor = 1e-6;

// Fills atols for a DAE whose unknowns from `first_multiplier` on are Lagrange multipliers
// (forces, torques, or the stabilising multipliers of a GGL system), the others in the units
// the run's atol is given in: atol for those, and for the multipliers at least
// kMultiplierNoiseFloor times the largest |y0| among them (1 at least). Index-2 and index-3
// iteration matrices are conditioned as 1/h^2 and 1/h^3: the multipliers' Newton corrections
// carry that rounding noise, and held to an atol in radians and metres they kept IDA's Newton
// from converging (docs/closed_loops.md, "Where they fail"). They are out of the error test
// (IdaOptions::suppress_algebraic): this changes only when Newton is taken to have converged.
// Used by the joint-space GGL DAE (ClosedLoopDae). Not by the body DAEs: there the joint
// reactions are multipliers too, of many sizes, and one floor from the largest doubled the
// steps of body-index2 at rtol 1e-9 (four-bar, slider-crank; measured 2026-11-27).
void MultiplierTolerances(int size, int first_multiplier, double atol, const double* y0,
                          double* atols);

}  // namespace mbstream
