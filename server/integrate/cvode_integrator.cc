#include "server/integrate/cvode_integrator.h"

#include <cmath>
#include <exception>

#include <cvode/cvode.h>
#include <cvode/cvode_ls.h>
#include <cvode/cvode_proj.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "server/integrate/fast_serial_ops.h"
#include "server/integrate/manifold_projection.h"

namespace mbstream::sundials {

namespace {

// CVProjFn: the system's correction for its own states, none for appended quadratures.
int ProjectionCallback(sunrealtype t, N_Vector y, N_Vector correction, sunrealtype /*eps*/,
                       N_Vector /*err*/, void* user_data) noexcept {
  auto* data = static_cast<CallbackData*>(user_data);
  OdeSystem& system = data->rhs->system();
  double* c = N_VGetArrayPointer(correction);
  for (sunindextype i = system.size(); i < N_VGetLength(correction); ++i) c[i] = 0.0;
  try {
    return ProjectionOf(system)->Project(t, N_VGetArrayPointer(y), c);
  } catch (const std::exception& error) {
    return data->rhs->RecordException(t, error.what());
  }
}

}  // namespace

CvodeIntegrator::CvodeIntegrator(Variant variant, OdeSystem& system, double t0, const double* y0,
                                 const IntegratorOptions& options)
    : SundialsIntegrator(system, t0, y0, options, Family::kCvode, variant == Variant::kBdf,
                         variant == Variant::kAdams),
      variant_(variant),
      memory_(CVodeCreate(variant == Variant::kBdf ? CV_BDF : CV_ADAMS, context()), CVodeFree) {
  void* cvode = memory_.get();
  CheckCreated(cvode, "CVodeCreate");
  CheckSetup(CVodeSetErrHandlerFn(cvode, ErrorSink::Handle, &errors()), "CVodeSetErrHandlerFn");
  CheckSetup(CVodeInit(cvode, RhsCallback, t0, initial_state()), "CVodeInit");
  callback_data().solver = cvode;
  CheckSetup(CVodeSetUserData(cvode, &callback_data()), "CVodeSetUserData");
  // The weights from callback_data() (its tolerances), so that Retune can change them.
  CheckSetup(CVodeWFtolerances(cvode, ErrorWeightCallback), "CVodeWFtolerances");
  if (options.max_step > 0.0) {
    CheckSetup(CVodeSetMaxStep(cvode, options.max_step), "CVodeSetMaxStep");
  }
  if (std::isfinite(options.t_final)) {
    CheckSetup(CVodeSetStopTime(cvode, options.t_final), "CVodeSetStopTime");
  }
  if (system.num_roots() > 0) {
    CheckSetup(CVodeRootInit(cvode, system.num_roots(), RootCallback), "CVodeRootInit");
    CheckSetup(CVodeSetNoInactiveRootWarn(cvode), "CVodeSetNoInactiveRootWarn");
  }
  const int n = system.size();
  if (variant == Variant::kBdf) {
    matrix_.reset(SUNDenseMatrix(n, n, context()));
    CheckCreated(matrix_.get(), "SUNDenseMatrix");
    InstallFastDenseMatrixOps(matrix_.get());
    linear_solver_.reset(SUNLinSol_Dense(initial_state(), matrix_.get(), context()));
    CheckCreated(linear_solver_.get(), "SUNLinSol_Dense");
    InstallFastDenseSolverOps(linear_solver_.get());
    CheckSetup(CVodeSetLinearSolver(cvode, linear_solver_.get(), matrix_.get()),
               "CVodeSetLinearSolver");
    CheckSetup(CVodeSetJacFn(cvode, DenseJacobianCallback), "CVodeSetJacFn");
    if (ProjectionOf(system) != nullptr) {  // CVODE projects with BDF only
      CheckSetup(CVodeSetProjFn(cvode, ProjectionCallback), "CVodeSetProjFn");
      CheckSetup(CVodeSetProjErrEst(cvode, SUNFALSE), "CVodeSetProjErrEst");
    }
  } else {
    nonlinear_solver_.reset(SUNNonlinSol_FixedPoint(initial_state(), 0, context()));
    CheckCreated(nonlinear_solver_.get(), "SUNNonlinSol_FixedPoint");
    CheckSetup(CVodeSetNonlinearSolver(cvode, nonlinear_solver_.get()), "CVodeSetNonlinearSolver");
  }
}

const char* CvodeIntegrator::name() const {
  return variant_ == Variant::kBdf ? "CVODE BDF" : "CVODE Adams";
}

long CvodeIntegrator::NumSteps() const {
  long steps = 0;
  CVodeGetNumSteps(memory_.get(), &steps);
  return steps;
}

double CvodeIntegrator::CurrentTime() const {
  double t = 0.0;
  CVodeGetCurrentTime(memory_.get(), &t);
  return t;
}

int CvodeIntegrator::SetMaxNumSteps(long steps) {
  return CVodeSetMaxNumSteps(memory_.get(), steps);
}

int CvodeIntegrator::Evolve(double t_out, N_Vector y, double* t_reached) {
  int flag = CV_ROOT_RETURN;
  while (flag == CV_ROOT_RETURN) {  // a root ends the step there; go on to t_out
    flag = CVode(memory_.get(), t_out, y, t_reached, CV_NORMAL);
    if (flag == CV_ROOT_RETURN) ++roots_found_;
  }
  return flag;
}

int CvodeIntegrator::SetStopTime(double t_final) {
  return CVodeSetStopTime(memory_.get(), t_final);
}

int CvodeIntegrator::ReInit(double t0) {
  roots_found_ = 0;
  return CVodeReInit(memory_.get(), t0, initial_state());
}

SolverStats CvodeIntegrator::stats() const {
  void* cvode = memory_.get();
  SolverStats stats;
  CVodeGetNumSteps(cvode, &stats.steps);
  stats.rhs_evals = rhs().num_evals();
  if (variant_ == Variant::kBdf) CVodeGetNumJacEvals(cvode, &stats.jac_evals);
  CVodeGetNumNonlinSolvIters(cvode, &stats.nonlinear_iterations);
  CVodeGetNumErrTestFails(cvode, &stats.error_test_failures);
  CVodeGetNumNonlinSolvConvFails(cvode, &stats.convergence_failures);
  CVodeGetLastStep(cvode, &stats.last_step);
  CVodeGetLastOrder(cvode, &stats.last_order);
  stats.roots_found = roots_found_;
  return stats;
}

}  // namespace mbstream::sundials
