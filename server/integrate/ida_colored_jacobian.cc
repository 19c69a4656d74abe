#include "server/integrate/ida_colored_jacobian.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "shared/common/check.h"

namespace mbstream {

std::vector<int> ColorColumns(int size, const std::vector<int>& column_starts,
                              const std::vector<int>& row_indices, int* colors) {
  MBSTREAM_CHECK(static_cast<int>(column_starts.size()) == size + 1);
  // Rows -> columns (the transpose pattern), to find each column's neighbours.
  std::vector<std::vector<int>> columns_of_row(size);
  for (int j = 0; j < size; ++j) {
    for (int k = column_starts[j]; k < column_starts[j + 1]; ++k) {
      MBSTREAM_CHECK(row_indices[k] >= 0 && row_indices[k] < size);
      columns_of_row[row_indices[k]].push_back(j);
    }
  }
  std::vector<int> color(size, -1);
  std::vector<int> used_by(size + 1, -1);  // used_by[c] == j: colour c taken by a neighbour of j
  int count = 0;
  for (int j = 0; j < size; ++j) {
    for (int k = column_starts[j]; k < column_starts[j + 1]; ++k) {
      for (int other : columns_of_row[row_indices[k]]) {
        if (color[other] >= 0) used_by[color[other]] = j;
      }
    }
    int c = 0;
    while (used_by[c] == j) ++c;
    color[j] = c;
    count = std::max(count, c + 1);
  }
  *colors = count;
  return color;
}

ColoredJacobian::ColoredJacobian(DaeSystem& system)
    : system_(system),
      size_(system.size()),
      y_shifted_(size_),
      yp_shifted_(size_),
      r_shifted_(size_),
      increment_(size_) {
  color_ =
      ColorColumns(size_, system.JacobianColumnStarts(), system.JacobianRowIndices(), &num_colors_);
  columns_of_color_.resize(num_colors_);
  for (int j = 0; j < size_; ++j) columns_of_color_[color_[j]].push_back(j);
}

int ColoredJacobian::Evaluate(double t, double cj, double h, const double* y, const double* yp,
                              const double* r, const double* ewt, double* values) {
  const std::vector<int>& starts = system_.JacobianColumnStarts();
  const std::vector<int>& rows = system_.JacobianRowIndices();
  const double srur = std::sqrt(DBL_EPSILON);
  std::copy(y, y + size_, y_shifted_.begin());
  std::copy(yp, yp + size_, yp_shifted_.begin());
  for (const std::vector<int>& group : columns_of_color_) {
    for (int j : group) {
      double inc = std::max(srur * std::max(std::abs(y[j]), std::abs(h * yp[j])), 1.0 / ewt[j]);
      if (h * yp[j] < 0.0) inc = -inc;
      y_shifted_[j] = y[j] + inc;
      inc = y_shifted_[j] - y[j];  // the increment actually represented
      yp_shifted_[j] = yp[j] + cj * inc;
      increment_[j] = inc;
    }
    ++num_evals_;
    const int code = system_.Residual(t, y_shifted_.data(), yp_shifted_.data(), r_shifted_.data());
    for (int j : group) {
      y_shifted_[j] = y[j];
      yp_shifted_[j] = yp[j];
    }
    if (code != 0) return code;
    for (int j : group) {
      for (int k = starts[j]; k < starts[j + 1]; ++k) {
        const int i = rows[k];
        values[k] = (r_shifted_[i] - r[i]) / increment_[j];
      }
    }
  }
  return 0;
}

}  // namespace mbstream
