#include "server/integrate/sundials_callbacks.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>

#include <arkode/arkode_arkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace mbstream::sundials {

namespace {

// Forward differences, column by column, with SUNDIALS' increments:
//   inc_j = max(sqrt(uround) |y_j|, min_inc / ewt_j),
//   min_inc = 1000 |h| uround n ||fy||_wrms (or 1 when fy = 0).
int FiniteDifferenceJacobian(const CallbackData& data, double t, N_Vector y, N_Vector fy,
                             SUNMatrix jac, N_Vector y_shifted, N_Vector f_shifted,
                             N_Vector weights) noexcept {
  double h = 0.0;
  int flag = data.family == Family::kCvode ? CVodeGetCurrentStep(data.solver, &h)
                                           : ARKStepGetCurrentStep(data.solver, &h);
  if (flag != 0) return -1;
  flag = data.family == Family::kCvode ? CVodeGetErrWeights(data.solver, weights)
                                       : ARKStepGetErrWeights(data.solver, weights);
  if (flag != 0) return -1;

  // The increments and the rows of the states under error control are those of the system
  // without its appended quadratures (the first error_states); the quadratures' rows are
  // zero, as in AppendedQuadratureOde's own Jacobian: Q feeds nothing back, and with zero
  // rows the Newton matrix keeps the system's own (and its pivots) in its leading block.
  const int n = data.rhs->size();
  const int controlled = data.error_states;
  const double uround = DBL_EPSILON;
  const double fnorm = N_VWrmsNorm(fy, weights);
  const double min_inc = fnorm != 0.0 ? 1000.0 * std::abs(h) * uround * controlled * fnorm : 1.0;
  const double* ewt = N_VGetArrayPointer(weights);
  const double* f0 = N_VGetArrayPointer(fy);
  double* shifted = N_VGetArrayPointer(y_shifted);
  double* f1 = N_VGetArrayPointer(f_shifted);
  N_VScale(1.0, y, y_shifted);
  for (int j = 0; j < n; ++j) {
    double* column = SUNDenseMatrix_Column(jac, j);
    if (ewt[j] == 0.0) {  // a state outside the error control: an appended quadrature,
      std::fill(column, column + n, 0.0);  // which feeds nothing back
      continue;
    }
    const double yj = shifted[j];
    shifted[j] = yj + std::max(std::sqrt(uround) * std::abs(yj), min_inc / ewt[j]);
    const double inc = shifted[j] - yj;  // the increment actually represented
    const int code = data.rhs->Evaluate(t, shifted, f1);
    shifted[j] = yj;
    if (code != 0) return code;
    for (int i = 0; i < controlled; ++i) column[i] = (f1[i] - f0[i]) / inc;
    std::fill(column + controlled, column + n, 0.0);
  }
  return 0;
}

}  // namespace

int RhsCallback(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept {
  const auto* data = static_cast<const CallbackData*>(user_data);
  return data->rhs->Evaluate(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

int RootCallback(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) noexcept {
  const auto* data = static_cast<const CallbackData*>(user_data);
  try {
    OdeSystem& system = data->rhs->system();
    const int code = system.Roots(t, N_VGetArrayPointer(y), g);
    if (code == 0) KeepRootsAwayFromZero(system.num_roots(), g);
    return code;
  } catch (const std::exception& error) {
    return data->rhs->RecordException(t, error.what());
  }
}

int ErrorWeightCallback(N_Vector y, N_Vector ewt, void* user_data) noexcept {
  const auto* data = static_cast<const CallbackData*>(user_data);
  const double* values = N_VGetArrayPointer(y);
  double* weights = N_VGetArrayPointer(ewt);
  const int n = static_cast<int>(N_VGetLength(y));
  for (int i = 0; i < n; ++i) {
    const double scale = data->rtol * std::abs(values[i]) + data->atol;
    if (i >= data->error_states) {
      weights[i] = 0.0;
    } else if (!(scale > 0.0)) {
      return -1;
    } else {
      weights[i] = 1.0 / scale;
    }
  }
  return 0;
}

int DenseJacobianCallback(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void* user_data,
                          N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) noexcept {
  const auto* data = static_cast<const CallbackData*>(user_data);
  if (!data->own_jacobian) {
    return FiniteDifferenceJacobian(*data, t, y, fy, jac, tmp1, tmp2, tmp3);
  }
  // SUNDenseMatrix stores its columns contiguously (column-major, leading dimension = rows).
  return data->rhs->EvaluateJacobian(t, N_VGetArrayPointer(y), N_VGetArrayPointer(fy),
                                     SUNDenseMatrix_Data(jac));
}

void ErrorSink::Handle(int error_code, const char* module, const char* function, char* message,
                       void* sink) noexcept {
  if (error_code >= 0) return;  // a warning (CV_WARNING, ARK_WARNING): not kept
  auto* self = static_cast<ErrorSink*>(sink);
  std::snprintf(self->message_, sizeof(self->message_), "%s (%s): %s",
                module != nullptr ? module : "?", function != nullptr ? function : "?",
                message != nullptr ? message : "");
}

}  // namespace mbstream::sundials
