#include "server/integrate/sundials_failure.h"

#include <arkode/arkode.h>
#include <cvode/cvode.h>

#include "server/integrate/failure_messages.h"
#include "shared/common/format.h"

namespace mbstream::sundials {

namespace {

// The kinds of solver failure, common to CVODE and ARKODE.
enum class Kind {
  kTooMuchWork,
  kTooMuchAccuracy,
  kErrorTest,
  kConvergence,
  kLinearSolver,
  kRhsFailure,
  kFirstRhs,
  kRepeatedRhs,
  kSetup,
};

struct Classified {
  Kind kind;
  const char* flag_name;
};

Classified ClassifyCvode(int flag) {
  switch (flag) {
    case CV_TOO_MUCH_WORK:
      return {Kind::kTooMuchWork, "CV_TOO_MUCH_WORK"};
    case CV_TOO_MUCH_ACC:
      return {Kind::kTooMuchAccuracy, "CV_TOO_MUCH_ACC"};
    case CV_ERR_FAILURE:
      return {Kind::kErrorTest, "CV_ERR_FAILURE"};
    case CV_CONV_FAILURE:
      return {Kind::kConvergence, "CV_CONV_FAILURE"};
    case CV_NLS_SETUP_FAIL:
      return {Kind::kConvergence, "CV_NLS_SETUP_FAIL"};
    case CV_NLS_FAIL:
      return {Kind::kConvergence, "CV_NLS_FAIL"};
    case CV_LSETUP_FAIL:
      return {Kind::kLinearSolver, "CV_LSETUP_FAIL"};
    case CV_LSOLVE_FAIL:
      return {Kind::kLinearSolver, "CV_LSOLVE_FAIL"};
    case CV_RHSFUNC_FAIL:
      return {Kind::kRhsFailure, "CV_RHSFUNC_FAIL"};
    case CV_UNREC_RHSFUNC_ERR:
      return {Kind::kRhsFailure, "CV_UNREC_RHSFUNC_ERR"};
    case CV_FIRST_RHSFUNC_ERR:
      return {Kind::kFirstRhs, "CV_FIRST_RHSFUNC_ERR"};
    case CV_REPTD_RHSFUNC_ERR:
      return {Kind::kRepeatedRhs, "CV_REPTD_RHSFUNC_ERR"};
    case CV_LINIT_FAIL:
      return {Kind::kSetup, "CV_LINIT_FAIL"};
    case CV_NLS_INIT_FAIL:
      return {Kind::kSetup, "CV_NLS_INIT_FAIL"};
    case CV_ILL_INPUT:
      return {Kind::kSetup, "CV_ILL_INPUT"};
    case CV_MEM_FAIL:
      return {Kind::kSetup, "CV_MEM_FAIL"};
    case CV_MEM_NULL:
      return {Kind::kSetup, "CV_MEM_NULL"};
    case CV_NO_MALLOC:
      return {Kind::kSetup, "CV_NO_MALLOC"};
    case CV_BAD_T:
      return {Kind::kSetup, "CV_BAD_T"};
    case CV_TOO_CLOSE:
      return {Kind::kSetup, "CV_TOO_CLOSE"};
    case CV_VECTOROP_ERR:
      return {Kind::kSetup, "CV_VECTOROP_ERR"};
    case CV_CONTEXT_ERR:
      return {Kind::kSetup, "CV_CONTEXT_ERR"};
    default:
      return {Kind::kSetup, "CV_UNRECOGNIZED_ERR"};
  }
}

Classified ClassifyArkode(int flag) {
  switch (flag) {
    case ARK_TOO_MUCH_WORK:
      return {Kind::kTooMuchWork, "ARK_TOO_MUCH_WORK"};
    case ARK_TOO_MUCH_ACC:
      return {Kind::kTooMuchAccuracy, "ARK_TOO_MUCH_ACC"};
    case ARK_ERR_FAILURE:
      return {Kind::kErrorTest, "ARK_ERR_FAILURE"};
    case ARK_CONV_FAILURE:
      return {Kind::kConvergence, "ARK_CONV_FAILURE"};
    case ARK_NLS_SETUP_FAIL:
      return {Kind::kConvergence, "ARK_NLS_SETUP_FAIL"};
    case ARK_NLS_SETUP_RECVR:
      return {Kind::kConvergence, "ARK_NLS_SETUP_RECVR"};
    case ARK_NLS_OP_ERR:
      return {Kind::kConvergence, "ARK_NLS_OP_ERR"};
    case ARK_LSETUP_FAIL:
      return {Kind::kLinearSolver, "ARK_LSETUP_FAIL"};
    case ARK_LSOLVE_FAIL:
      return {Kind::kLinearSolver, "ARK_LSOLVE_FAIL"};
    case ARK_RHSFUNC_FAIL:
      return {Kind::kRhsFailure, "ARK_RHSFUNC_FAIL"};
    case ARK_UNREC_RHSFUNC_ERR:
      return {Kind::kRhsFailure, "ARK_UNREC_RHSFUNC_ERR"};
    case ARK_FIRST_RHSFUNC_ERR:
      return {Kind::kFirstRhs, "ARK_FIRST_RHSFUNC_ERR"};
    case ARK_REPTD_RHSFUNC_ERR:
      return {Kind::kRepeatedRhs, "ARK_REPTD_RHSFUNC_ERR"};
    case ARK_LINIT_FAIL:
      return {Kind::kSetup, "ARK_LINIT_FAIL"};
    case ARK_NLS_INIT_FAIL:
      return {Kind::kSetup, "ARK_NLS_INIT_FAIL"};
    case ARK_ILL_INPUT:
      return {Kind::kSetup, "ARK_ILL_INPUT"};
    case ARK_MEM_FAIL:
      return {Kind::kSetup, "ARK_MEM_FAIL"};
    case ARK_MEM_NULL:
      return {Kind::kSetup, "ARK_MEM_NULL"};
    case ARK_NO_MALLOC:
      return {Kind::kSetup, "ARK_NO_MALLOC"};
    case ARK_BAD_T:
      return {Kind::kSetup, "ARK_BAD_T"};
    case ARK_TOO_CLOSE:
      return {Kind::kSetup, "ARK_TOO_CLOSE"};
    case ARK_VECTOROP_ERR:
      return {Kind::kSetup, "ARK_VECTOROP_ERR"};
    case ARK_INTERP_FAIL:
      return {Kind::kSetup, "ARK_INTERP_FAIL"};
    case ARK_INVALID_TABLE:
      return {Kind::kSetup, "ARK_INVALID_TABLE"};
    case ARK_CONTEXT_ERR:
      return {Kind::kSetup, "ARK_CONTEXT_ERR"};
    default:
      return {Kind::kSetup, "ARK_UNRECOGNIZED_ERROR"};
  }
}

// Appends " [FLAG; SUNDIALS: message]".
std::string Detail(const char* flag_name, const char* solver_message) {
  if (solver_message == nullptr || solver_message[0] == '\0') {
    return FormatString(" [%s]", flag_name);
  }
  return FormatString(" [%s; SUNDIALS: %s]", flag_name, solver_message);
}

// The status and message of a classified failure (the flag's own detail is added after).
struct Outcome {
  IntegratorStatus status = IntegratorStatus::kSetupFailure;
  std::string message;
};
Outcome KindOutcome(Kind kind, const FailureContext& c) {
  const double t = c.t_reached;
  IntegratorStatus status = IntegratorStatus::kSetupFailure;
  std::string message;
  switch (kind) {
    case Kind::kTooMuchWork:
      status = IntegratorStatus::kTooMuchWork;
      message = TooMuchWorkMessage(c.solver, c.max_steps, t, c.t_out, c.implicit);
      break;
    case Kind::kTooMuchAccuracy:
      status = IntegratorStatus::kErrorTestFailures;
      message = FormatString(
          "%s: the requested accuracy cannot be reached in double precision at t = %.9g s; "
          "loosen rtol/atol",
          c.solver, t);
      break;
    case Kind::kErrorTest:
      status = IntegratorStatus::kErrorTestFailures;
      message = FormatString(
          "%s: the local error test failed repeatedly (or with the smallest step) at t = "
          "%.9g s; the solution may be discontinuous or singular there: check the model "
          "(e.g. a discontinuous force or a singular configuration), set a smaller max_step, "
          "loosen rtol/atol, or try an implicit method (bdf, dirk)",
          c.solver, t);
      break;
    case Kind::kConvergence:
      status = IntegratorStatus::kConvergenceFailures;
      message = FormatString(
          "%s: the nonlinear %s iteration failed to converge repeatedly at t = %.9g s; %s",
          c.solver, c.fixed_point ? "fixed-point" : "Newton", t,
          c.fixed_point ? "the problem is probably stiff: use method bdf or dirk"
                        : "check the model (and its Jacobian, if it has one), set a smaller "
                          "max_step or loosen rtol/atol");
      break;
    case Kind::kLinearSolver:
      status = IntegratorStatus::kConvergenceFailures;
      message = FormatString(
          "%s: the linear solver failed at t = %.9g s (a singular iteration matrix, or the "
          "model's Jacobian function failed); check the model (e.g. a singular mass matrix) "
          "and its Jacobian, or set a smaller max_step",
          c.solver, t);
      break;
    case Kind::kRhsFailure:
      status = IntegratorStatus::kRhsFailure;
      if (c.rhs != nullptr && c.rhs->last_recoverable_code() != 0) {
        message = FormatString(
            "%s: the model's right-hand side failed (recoverably, code %d, at t = %.9g s) and "
            "the solver could not recover; stopped at t = %.9g s; check the model",
            c.solver, c.rhs->last_recoverable_code(), c.rhs->last_recoverable_time(), t);
      } else {
        message = FormatString(
            "%s: the model's right-hand side failed at t = %.9g s; check the model", c.solver, t);
      }
      break;
    case Kind::kFirstRhs:
      status = IntegratorStatus::kRhsFailure;
      message = FormatString(
          "%s: the model's right-hand side failed (recoverably, code %d) at the initial time "
          "t = %.9g s; check the initial state and the model",
          c.solver, c.rhs != nullptr ? c.rhs->last_recoverable_code() : 0, t);
      break;
    case Kind::kRepeatedRhs:
      status = IntegratorStatus::kRhsFailure;
      message = FormatString(
          "%s: the model's right-hand side kept failing (recoverably, code %d, last at t = "
          "%.9g s) even with smaller steps; stopped at t = %.9g s; check the model at that "
          "time",
          c.solver, c.rhs != nullptr ? c.rhs->last_recoverable_code() : 0,
          c.rhs != nullptr ? c.rhs->last_recoverable_time() : t, t);
      break;
    case Kind::kSetup:
      status = IntegratorStatus::kSetupFailure;
      message = FormatString(
          "%s: the solver refused its input or failed internally at t = %.9g s; check the "
          "solver options (rtol, atol, max_step) — otherwise this is a bug in mbstream",
          c.solver, t);
      break;
  }
  return {status, message};
}

}  // namespace

AdvanceResult FailureResult(const FailureContext& c) {
  const Classified classified =
      c.family == Family::kCvode ? ClassifyCvode(c.flag) : ClassifyArkode(c.flag);
  const std::string detail = Detail(classified.flag_name, c.solver_message);

  // A failure the right-hand side adapter recorded (divergence, non-finite derivative, the
  // model's own unrecoverable failure) explains any flag it led to.
  if (c.rhs != nullptr && c.rhs->event() != RhsAdapter::Event::kNone) {
    AdvanceResult result = RhsEventResult(
        c.solver, *c.rhs, c.t_reached, c.implicit ? MethodKind::kImplicit : MethodKind::kExplicit);
    result.message += detail;
    return result;
  }

  const Outcome outcome = KindOutcome(classified.kind, c);
  return {outcome.status, c.t_reached, outcome.message + detail};
}

}  // namespace mbstream::sundials
