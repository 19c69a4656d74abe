#include "server/sim/run_result.h"

namespace mbstream {

RunStatus ToRunStatus(IntegratorStatus status) {
  switch (status) {
    case IntegratorStatus::kOk:
      return RunStatus::kFinished;
    case IntegratorStatus::kDiverged:
      return RunStatus::kDiverged;
    case IntegratorStatus::kTooMuchWork:
      return RunStatus::kTooMuchWork;
    case IntegratorStatus::kErrorTestFailures:
      return RunStatus::kErrorTestFailures;
    case IntegratorStatus::kConvergenceFailures:
      return RunStatus::kConvergenceFailures;
    case IntegratorStatus::kRhsFailure:
    case IntegratorStatus::kSetupFailure:
      return RunStatus::kFailed;
  }
  return RunStatus::kFailed;
}

const char* RunStatusName(RunStatus status) {
  switch (status) {
    case RunStatus::kFinished:
      return "FINISHED";
    case RunStatus::kDiverged:
      return "DIVERGED";
    case RunStatus::kTooMuchWork:
      return "TOO_MUCH_WORK";
    case RunStatus::kErrorTestFailures:
      return "ERROR_TEST_FAILURES";
    case RunStatus::kConvergenceFailures:
      return "CONVERGENCE_FAILURES";
    case RunStatus::kFailed:
      return "FAILED";
    case RunStatus::kCancelled:
      return "CANCELLED";
    case RunStatus::kInterrupted:
      return "INTERRUPTED";
  }
  return "FAILED";
}

const char* TrustName(Trust trust) {
  switch (trust) {
    case Trust::kNotAssessed:
      return "";
    case Trust::kOk:
      return "ok";
    case Trust::kLow:
      return "low";
  }
  return "";
}

}  // namespace mbstream
