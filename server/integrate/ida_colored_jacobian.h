// The iteration matrix of IDA, J = dF/dy + cj dF/dy', by coloured forward differences over
// a DaeSystem's known sparsity: columns that share no row are perturbed together, so one
// residual evaluation gives a whole group of columns.
#pragma once

#include <vector>

#include "server/integrate/ida_system.h"

namespace mbstream {

// Greedy distance-2 colouring of the columns of a CSC pattern: color[j] in [0, colors).
// Two columns that have a row in common never share a colour.
std::vector<int> ColorColumns(int size, const std::vector<int>& column_starts,
                              const std::vector<int>& row_indices, int* colors);

class ColoredJacobian {
 public:
  // Keeps a reference to `system`, which must outlive it.
  explicit ColoredJacobian(DaeSystem& system);

  int num_colors() const { return num_colors_; }

  // Writes J at (t, y, yp) with residual r = F(t, y, yp) into `values` (one per pattern
  // entry, in the pattern's CSC order). `ewt` are the solver's error weights, h its current
  // step; increments follow IDA's own difference quotients:
  //   inc_j = max(sqrt(uround) max(|y_j|, |h yp_j|), 1 / ewt_j), with the sign of h yp_j.
  // Returns the residual's code (0 = ok). Allocates nothing.
  int Evaluate(double t, double cj, double h, const double* y, const double* yp, const double* r,
               const double* ewt, double* values);

  // Number of residual evaluations made so far.
  long num_residual_evals() const { return num_evals_; }

 private:
  DaeSystem& system_;
  int size_;
  std::vector<int> color_;
  int num_colors_ = 0;
  std::vector<std::vector<int>> columns_of_color_;
  std::vector<double> y_shifted_, yp_shifted_, r_shifted_, increment_;
  long num_evals_ = 0;
};

}  // namespace mbstream
