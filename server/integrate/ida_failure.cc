#include "server/integrate/ida_failure.h"

#include <ida/ida.h>

#include "server/integrate/failure_messages.h"
#include "shared/common/format.h"

namespace mbstream::sundials {

namespace {

struct Classified {
  IntegratorStatus status;
  const char* flag_name;
  const char* what;
};

Classified Classify(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK:
      return {IntegratorStatus::kTooMuchWork, "IDA_TOO_MUCH_WORK", "the step budget ran out"};
    case IDA_TOO_MUCH_ACC:
      return {IntegratorStatus::kErrorTestFailures, "IDA_TOO_MUCH_ACC",
              "the tolerance is below what double precision resolves"};
    case IDA_ERR_FAIL:
      return {IntegratorStatus::kErrorTestFailures, "IDA_ERR_FAIL",
              "the local error test failed repeatedly (or with the smallest step allowed)"};
    case IDA_CONV_FAIL:
      return {IntegratorStatus::kConvergenceFailures, "IDA_CONV_FAIL",
              "the Newton iteration failed to converge repeatedly"};
    case IDA_NLS_FAIL:
      return {IntegratorStatus::kConvergenceFailures, "IDA_NLS_FAIL",
              "the nonlinear solver failed"};
    case IDA_LSETUP_FAIL:
      return {IntegratorStatus::kConvergenceFailures, "IDA_LSETUP_FAIL",
              "the iteration matrix could not be factored (singular)"};
    case IDA_LSOLVE_FAIL:
      return {IntegratorStatus::kConvergenceFailures, "IDA_LSOLVE_FAIL", "the linear solve failed"};
    case IDA_RES_FAIL:
      return {IntegratorStatus::kRhsFailure, "IDA_RES_FAIL", "the residual failed unrecoverably"};
    case IDA_REP_RES_ERR:
      return {IntegratorStatus::kConvergenceFailures, "IDA_REP_RES_ERR",
              "the residual failed repeatedly (non-finite values)"};
    case IDA_FIRST_RES_FAIL:
      return {IntegratorStatus::kRhsFailure, "IDA_FIRST_RES_FAIL",
              "the residual failed at the first call"};
    case IDA_CONSTR_FAIL:
      return {IntegratorStatus::kConvergenceFailures, "IDA_CONSTR_FAIL",
              "the inequality constraints could not be met"};
    default:
      return {IntegratorStatus::kSetupFailure, "IDA_ERROR", "an internal solver failure"};
  }
}

}  // namespace

AdvanceResult IdaFailureResult(const IdaFailureContext& c) {
  const Classified k = Classify(c.flag);
  std::string message;
  if (k.status == IntegratorStatus::kTooMuchWork) {
    message = TooMuchWorkMessage("IDA", c.max_steps, c.t_reached, c.t_out, /*implicit=*/true);
  } else {
    message = FormatString(
        "IDA stopped at t = %.6g s (asked for %.6g s): %s (%s; last step %.3g s, smallest "
        "allowed %.3g s; %ld error-test and %ld convergence failures so far)",
        c.t_reached, c.t_out, k.what, k.flag_name, c.last_step, c.min_step, c.error_test_failures,
        c.convergence_failures);
    if (c.residual_event[0] != '\0') message += std::string("; ") + c.residual_event;
    if (c.solver_message[0] != '\0') message += std::string("; IDA said: ") + c.solver_message;
  }
  return {k.status, c.t_reached, message};
}

}  // namespace mbstream::sundials
