#include "server/integrate/failure_messages.h"

namespace mbstream {

std::string DivergedMessage(const char* solver, double t, double limit, MethodKind kind) {
  const char* advice = "";
  switch (kind) {
    case MethodKind::kFixedStep:
      advice =
          "the step is beyond the method's stability limit or the model is unstable: use a "
          "smaller step (--step) or an implicit method (bdf, dirk)";
      break;
    case MethodKind::kExplicit:
      advice =
          "the model is unstable or its solution blows up: check the model (e.g. negative "
          "damping, a singular mass matrix), or try an implicit method (bdf, dirk), tighter "
          "tolerances (rtol, atol) or a smaller max_step";
      break;
    case MethodKind::kImplicit:
      advice =
          "the model is unstable or its solution blows up: check the model (e.g. negative "
          "damping, a singular mass matrix), or try tighter tolerances (rtol, atol) or a "
          "smaller max_step";
      break;
  }
  return FormatString("%s: the state became non-finite or exceeded %g at t = %.9g s; %s", solver,
                      limit, t, advice);
}

std::string TooMuchWorkMessage(const char* solver, long max_steps, double t_reached, double t_out,
                               bool implicit) {
  const char* advice =
      implicit ? "the solution may vary very fast or the tolerances be too tight: raise "
                 "max_steps or loosen rtol/atol"
               : "the problem may be stiff: try method bdf or dirk, or raise max_steps";
  return FormatString(
      "%s: took more than max_steps = %ld steps before t = %.9g s (stopped at t = %.9g s); %s",
      solver, max_steps, t_out, t_reached, advice);
}

std::string CpuBudgetMessage(const char* solver, double t_reached, double t_out) {
  return FormatString(
      "%s: the run's CPU budget ran out before t = %.9g s (stopped at t = %.9g s); raise "
      "max_cpu_s, or make the run cheaper (a looser rtol/atol, an implicit method for a stiff "
      "scene)",
      solver, t_out, t_reached);
}

AdvanceResult RhsEventResult(const char* solver, const RhsAdapter& rhs, double t_good,
                             MethodKind kind) {
  switch (rhs.event()) {
    case RhsAdapter::Event::kDiverged:
      return {IntegratorStatus::kDiverged, t_good,
              DivergedMessage(solver, rhs.event_time(), rhs.divergence_limit(), kind)};
    case RhsAdapter::Event::kNonFiniteDerivative:
      return {IntegratorStatus::kRhsFailure, t_good,
              FormatString("%s: the model returned a non-finite derivative at t = %.9g s "
                           "(with a finite state); check the model (e.g. a singular mass "
                           "matrix, a division by zero)",
                           solver, rhs.event_time())};
    case RhsAdapter::Event::kFailed:
      return {IntegratorStatus::kRhsFailure, t_good,
              FormatString("%s: the model's right-hand side failed unrecoverably (code %d) at "
                           "t = %.9g s; check the model and its inputs at that time",
                           solver, rhs.event_code(), rhs.event_time())};
    case RhsAdapter::Event::kThrew:
      return {IntegratorStatus::kRhsFailure, t_good,
              FormatString("%s: the model's right-hand side failed at t = %.9g s: %s", solver,
                           rhs.event_time(), rhs.event_what())};
    case RhsAdapter::Event::kNone:
      break;
  }
  return {IntegratorStatus::kRhsFailure, t_good,
          FormatString("%s: the model's right-hand side failed at t = %.9g s", solver, t_good)};
}

}  // namespace mbstream
