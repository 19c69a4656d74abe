// The C callbacks handed to SUNDIALS: right-hand side and dense Jacobian (user_data = a
// CallbackData), and an error handler that keeps SUNDIALS quiet and stores its last message.
#pragma once

#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nvector.h>

#include "server/integrate/rhs_adapter.h"
#include "server/integrate/sundials_handles.h"

namespace mbstream::sundials {

// What the right-hand side and Jacobian callbacks reach through user_data.
struct CallbackData {
  RhsAdapter* rhs = nullptr;
  void* solver = nullptr;  // the CVODE or ARKStep memory (for the finite differences)
  Family family = Family::kCvode;
  bool own_jacobian = false;  // the system's Jacobian, not finite differences
  // For ErrorWeightCallback: the tolerances and how many leading states they apply to (all
  // but appended quadratures).
  double rtol = 0.0, atol = 0.0;
  int error_states = 0;
};

// CVRhsFn / ARKRhsFn. Like every callback handed to SUNDIALS it lets no exception out: the
// RhsAdapter turns one into an unrecoverable failure that keeps its message.
int RhsCallback(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) noexcept;

// CVRootFn / ARKRootFn: the system's root functions (OdeSystem::Roots), each at least
// kRootFloor from 0 (KeepRootsAwayFromZero).
int RootCallback(sunrealtype t, N_Vector y, sunrealtype* g, void* user_data) noexcept;

// SUNDIALS finds a sign change where glo * ghi < 0, and takes a g of exactly 0 at a root it
// has just found, and again a tiny step later, as bad input (CV_ILL_INPUT, "Root found at and
// very near t"). So each g_k is moved to at least kRootFloor from 0: a 0 to +kRootFloor (two
// geometries just touching are apart), a smaller value to kRootFloor of its sign. The floor
// is large enough that no product of two floored values underflows to 0: with DBL_MIN for an
// exact 0, a box placed exactly on the floor had DBL_MIN * -1.4e-17 = -0.0, CVODE's Illinois
// iteration lost the bracket, asked g at t = -3.2e-9 s and then t = inf, and the run failed.
inline constexpr double kRootFloor = 1e-150;
inline void KeepRootsAwayFromZero(int n, double* g) {
  for (int k = 0; k < n; ++k) {
    if (g[k] < kRootFloor && g[k] > -kRootFloor) g[k] = g[k] < 0.0 ? -kRootFloor : kRootFloor;
  }
}

// CVEwtFn / ARKEwtFn: SUNDIALS' scalar-tolerance weights 1 / (rtol |y_i| + atol) for the first
// error_states states, 0 for the rest (they take no part in the error control).
int ErrorWeightCallback(N_Vector y, N_Vector ewt, void* user_data) noexcept;

// CVLsJacFn / ARKLsJacFn for a SUNDenseMatrix: the system's own Jacobian, or else forward
// differences computed as SUNDIALS' internal ones (cvLsDenseDQJac / arkLsDenseDQJac: the
// same increments, n evaluations of f) but without their allocation of a vector per call,
// so that a step allocates nothing.
int DenseJacobianCallback(sunrealtype t, N_Vector y, N_Vector fy, SUNMatrix jac, void* user_data,
                          N_Vector tmp1, N_Vector tmp2, N_Vector tmp3) noexcept;

// Receives SUNDIALS' error messages instead of stderr (CVErrHandlerFn / ARKErrHandlerFn,
// eh_data = this). Keeps the last error (warnings are dropped). Allocates nothing.
class ErrorSink {
 public:
  static void Handle(int error_code, const char* module, const char* function, char* message,
                     void* sink) noexcept;

  void Clear() { message_[0] = '\0'; }
  const char* message() const { return message_; }  // "" when there was none

 private:
  char message_[512] = {};
};

}  // namespace mbstream::sundials
