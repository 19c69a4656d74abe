#include "server/integrate/ida_integrator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <ida/ida.h>
#include <ida/ida_ls.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include "server/integrate/c_boundary.h"
#include "server/integrate/failure_messages.h"
#include "server/integrate/ida_failure.h"
#include "server/integrate/state_health.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace sundials {

namespace {

int ResidualCallback(sunrealtype t, N_Vector y, N_Vector yp, N_Vector r, void* user_data) noexcept {
  auto* callbacks = static_cast<IdaCallbacks*>(user_data);
  return callbacks->Residual(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                             N_VGetArrayPointer(r));
}

// The iteration matrix by coloured finite differences (residual calls that may throw).
int FillJacobian(IdaCallbacks* callbacks, sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp,
                 N_Vector r, SUNMatrix jac, N_Vector tmp1) {
  double h = 0.0;
  if (IDAGetCurrentStep(callbacks->solver, &h) != IDA_SUCCESS) return -1;
  if (IDAGetErrWeights(callbacks->solver, tmp1) != IDA_SUCCESS) return -1;
  const DaeSystem& system = callbacks->system();
  const std::vector<int>& starts = system.JacobianColumnStarts();
  const std::vector<int>& rows = system.JacobianRowIndices();
  const int n = system.size();
  if (!callbacks->dense) {
    // IDA zeroes the whole sparse matrix (pattern included) before each call.
    sunindextype* pointers = SUNSparseMatrix_IndexPointers(jac);
    sunindextype* indices = SUNSparseMatrix_IndexValues(jac);
    for (int j = 0; j <= n; ++j) pointers[j] = starts[j];
    for (size_t k = 0; k < rows.size(); ++k) indices[k] = rows[k];
    return callbacks->jacobian().Evaluate(t, cj, h, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                          N_VGetArrayPointer(r), N_VGetArrayPointer(tmp1),
                                          SUNSparseMatrix_Data(jac));
  }
  double* values = callbacks->values.data();
  const int code =
      callbacks->jacobian().Evaluate(t, cj, h, N_VGetArrayPointer(y), N_VGetArrayPointer(yp),
                                     N_VGetArrayPointer(r), N_VGetArrayPointer(tmp1), values);
  if (code != 0) return code;
  double* dense = SUNDenseMatrix_Data(jac);
  std::fill(dense, dense + static_cast<size_t>(n) * n, 0.0);
  for (int j = 0; j < n; ++j) {
    for (int k = starts[j]; k < starts[j + 1]; ++k)
      dense[static_cast<size_t>(j) * n + rows[k]] = values[k];
  }
  return 0;
}

int JacobianCallback(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector r,
                     SUNMatrix jac, void* user_data, N_Vector tmp1, N_Vector /*tmp2*/,
                     N_Vector /*tmp3*/) noexcept {
  auto* callbacks = static_cast<IdaCallbacks*>(user_data);
  return AtCBoundary([&] { return FillJacobian(callbacks, t, cj, y, yp, r, jac, tmp1); },
                     [&](const char* what) { return callbacks->RecordException(t, what); });
}

Context CreateContext() {
  SUNContext context = nullptr;
  MBSTREAM_CHECK_MSG(SUNContext_Create(nullptr, &context) == 0 && context != nullptr,
                     "SUNContext_Create failed");
  return Context(context);
}

}  // namespace

IdaCallbacks::IdaCallbacks(DaeSystem& system, double divergence_limit)
    : system_(system), divergence_limit_(divergence_limit), jacobian_(system) {}

int IdaCallbacks::RecordException(double t, const char* what) noexcept {
  if (event_[0] == '\0') {
    std::snprintf(event_, sizeof(event_), "the residual failed at t = %.6g s: %s", t, what);
  }
  return -1;
}

int IdaCallbacks::Residual(double t, const double* y, const double* yp, double* r) noexcept {
  ++num_evals_;
  const int n = system_.size();
  if (!IsHealthyState(y, n, divergence_limit_)) {
    if (event_[0] == '\0') {
      std::snprintf(event_, sizeof(event_),
                    "the state became non-finite or beyond %.3g at t = %.6g s", divergence_limit_,
                    t);
    }
    return 1;
  }
  const int code = AtCBoundary([&] { return system_.Residual(t, y, yp, r); },
                               [&](const char* what) { return RecordException(t, what); });
  if (code != 0) return code;
  if (!IsFiniteState(r, n)) {
    if (event_[0] == '\0') {
      std::snprintf(event_, sizeof(event_), "the residual became non-finite at t = %.6g s", t);
    }
    return 1;
  }
  return 0;
}

IdaIntegrator::IdaIntegrator(DaeSystem& system, double t0, const double* y0, const double* yp0,
                             const IdaOptions& options)
    : IntegratorBase(system.size(), t0, y0, options.base),
      callbacks_(system, options.base.divergence_limit),
      ida_options_(options),
      context_(CreateContext()) {
  const int n = system.size();
  SUNContext ctx = context_.get();
  y0_.reset(N_VNew_Serial(n, ctx));
  yp0_.reset(N_VNew_Serial(n, ctx));
  id_.reset(N_VNew_Serial(n, ctx));
  yp_out_.reset(N_VNew_Serial(n, ctx));
  out_.reset(N_VMake_Serial(n, nullptr, ctx));
  MBSTREAM_CHECK_MSG(y0_ && yp0_ && id_ && yp_out_ && out_, "N_VNew_Serial failed");
  std::copy(y0, y0 + n, N_VGetArrayPointer(y0_.get()));
  std::copy(yp0, yp0 + n, N_VGetArrayPointer(yp0_.get()));
  std::copy(yp0, yp0 + n, N_VGetArrayPointer(yp_out_.get()));
  system.DifferentialIds(N_VGetArrayPointer(id_.get()));

  memory_ = IDACreate(ctx);
  MBSTREAM_CHECK_MSG(memory_ != nullptr, "IDACreate failed");
  callbacks_.solver = memory_;
  CheckSetup(IDASetErrHandlerFn(memory_, ErrorSink::Handle, &errors_), "IDASetErrHandlerFn");
  CheckSetup(IDAInit(memory_, ResidualCallback, t0, y0_.get(), yp0_.get()), "IDAInit");
  CheckSetup(IDASetUserData(memory_, &callbacks_), "IDASetUserData");
  const IntegratorOptions& base = options.base;
  {
    // IDA keeps a copy of the absolute tolerances.
    const Vector atols(N_VNew_Serial(n, ctx));
    MBSTREAM_CHECK_MSG(atols, "N_VNew_Serial failed");
    system.AbsoluteTolerances(base.atol, y0, N_VGetArrayPointer(atols.get()));
    CheckSetup(IDASVtolerances(memory_, base.rtol, atols.get()), "IDASVtolerances");
  }
  CheckSetup(IDASetId(memory_, id_.get()), "IDASetId");
  CheckSetup(IDASetSuppressAlg(memory_, options.suppress_algebraic ? SUNTRUE : SUNFALSE),
             "IDASetSuppressAlg");
  if (base.max_step > 0.0) CheckSetup(IDASetMaxStep(memory_, base.max_step), "IDASetMaxStep");
  if (std::isfinite(base.t_final)) {
    CheckSetup(IDASetStopTime(memory_, base.t_final), "IDASetStopTime");
  }
  min_step_ =
      options.min_step > 0.0
          ? options.min_step
          : 1e-12 * std::max(1.0, std::isfinite(base.t_final) ? std::abs(base.t_final) : 1.0);
  CheckSetup(IDASetMinStep(memory_, min_step_), "IDASetMinStep");
  if (options.initial_step > 0.0) {
    CheckSetup(IDASetInitStep(memory_, options.initial_step), "IDASetInitStep");
  }

  const int nnz = system.JacobianNonZeros();
  if (options.linear_solver == IdaOptions::LinearSolver::kKlu) {
    matrix_.reset(SUNSparseMatrix(n, n, nnz, CSC_MAT, ctx));
    MBSTREAM_CHECK_MSG(matrix_ != nullptr, "SUNSparseMatrix failed");
    linear_solver_.reset(SUNLinSol_KLU(y0_.get(), matrix_.get(), ctx));
  }
  if (!linear_solver_) {  // dense requested, or KLU unavailable: the dense fallback
    matrix_.reset(SUNDenseMatrix(n, n, ctx));
    MBSTREAM_CHECK_MSG(matrix_ != nullptr, "SUNDenseMatrix failed");
    linear_solver_.reset(SUNLinSol_Dense(y0_.get(), matrix_.get(), ctx));
    MBSTREAM_CHECK_MSG(linear_solver_ != nullptr, "SUNLinSol_Dense failed");
    callbacks_.dense = true;
    callbacks_.values.assign(static_cast<size_t>(nnz), 0.0);
  }
  CheckSetup(IDASetLinearSolver(memory_, linear_solver_.get(), matrix_.get()),
             "IDASetLinearSolver");
  CheckSetup(IDASetJacFn(memory_, JacobianCallback), "IDASetJacFn");
}

IdaIntegrator::~IdaIntegrator() {
  if (memory_ != nullptr) IDAFree(&memory_);
}

void IdaIntegrator::CheckSetup(int flag, const char* call) const {
  if (flag >= 0) return;
  MBSTREAM_CHECK_MSG(false, FormatString("%s returned %d (%s)", call, flag, errors_.message()));
}

const char* IdaIntegrator::name() const {
  return callbacks_.dense ? "IDA (dense)" : "IDA (KLU sparse)";
}

const double* IdaIntegrator::derivative() const { return N_VGetArrayPointer(yp_out_.get()); }

long IdaIntegrator::NumSteps() const {
  long steps = 0;
  IDAGetNumSteps(memory_, &steps);
  return steps;
}

double IdaIntegrator::CurrentTime() const {
  double t = last_time();
  IDAGetCurrentTime(memory_, &t);
  return t;
}

void IdaIntegrator::LimitSteps(long steps) {
  CheckSetup(IDASetMaxNumSteps(memory_, steps), "IDASetMaxNumSteps");
}

int IdaIntegrator::Solve(double t_out, double* t_reached) {
  return IDASolve(memory_, t_out, t_reached, out_.get(), yp_out_.get(), IDA_NORMAL);
}

int IdaIntegrator::TooMuchWorkFlag() const { return IDA_TOO_MUCH_WORK; }

AdvanceResult IdaIntegrator::DoAdvance(double t_out, double* y) {
  errors_.Clear();
  N_VSetArrayPointer(y, out_.get());
  const ChunkedSolve solve = SolveInChunks(t_out, y, *this);
  if (solve.flag >= 0) return {IntegratorStatus::kOk, t_out, {}};
  const SolverStats s = stats();
  IdaFailureContext context{solve.flag,
                            solve.t_reached,
                            t_out,
                            options().max_steps,
                            s.last_step,
                            min_step_,
                            s.error_test_failures,
                            s.convergence_failures,
                            callbacks_.event(),
                            errors_.message()};
  AdvanceResult result = IdaFailureResult(context);
  if (solve.cpu_spent) result.message = CpuBudgetMessage("IDA", result.t, t_out);
  return result;
}

SolverStats IdaIntegrator::stats() const {
  SolverStats stats;
  IDAGetNumSteps(memory_, &stats.steps);
  stats.rhs_evals = callbacks_.num_residual_evals();
  IDAGetNumJacEvals(memory_, &stats.jac_evals);
  IDAGetNumNonlinSolvIters(memory_, &stats.nonlinear_iterations);
  IDAGetNumErrTestFails(memory_, &stats.error_test_failures);
  IDAGetNumNonlinSolvConvFails(memory_, &stats.convergence_failures);
  IDAGetLastStep(memory_, &stats.last_step);
  IDAGetLastOrder(memory_, &stats.last_order);
  return stats;
}

}  // namespace sundials

std::unique_ptr<sundials::IdaIntegrator> MakeIdaIntegrator(DaeSystem& system, double t0,
                                                           const double* y0, const double* yp0,
                                                           const IdaOptions& options) {
  const IntegratorOptions& o = options.base;
  MBSTREAM_CHECK_MSG(system.size() > 0 && y0 != nullptr && yp0 != nullptr,
                     "a DAE system needs unknowns");
  if (!std::isfinite(t0) || std::isnan(o.t_final) || !(o.t_final > t0)) {
    throw InputError(FormatString(
        "integrator: the end time t_final = %g s must come after the start time t0 = %g s "
        "(check the run's duration)",
        o.t_final, t0));
  }
  if (!IsFiniteState(y0, system.size()) || !IsFiniteState(yp0, system.size())) {
    throw InputError(
        "integrator: the initial state is not finite; check the initial positions and "
        "velocities");
  }
  IntegratorOptions checked = o;
  checked.method = Method::kIda;  // the tolerances, step budget and table checks of ida
  CheckIntegratorOptions(checked);
  return std::make_unique<sundials::IdaIntegrator>(system, t0, y0, yp0, options);
}

}  // namespace mbstream
