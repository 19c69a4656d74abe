#include "server/integrate/integrator_base.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "server/integrate/failure_messages.h"
#include "server/integrate/state_health.h"
#include "shared/common/check.h"

namespace mbstream {

IntegratorBase::IntegratorBase(int size, double t0, const double* y0,
                               const IntegratorOptions& options)
    : size_(size),
      options_(options),
      cpu_deadline_(options.cpu_deadline_s),
      last_t_(t0),
      last_y_(y0, y0 + size) {}

void IntegratorBase::ReplaceOptions(const IntegratorOptions& options) {
  options_ = options;
  cpu_deadline_ = CpuDeadline(options.cpu_deadline_s);
}

ChunkedSolve IntegratorBase::SolveInChunks(double t_out, double* y, ChunkedSolver& solver) {
  const long max_steps = options_.max_steps;
  const bool cpu_budget = std::isfinite(options_.cpu_deadline_s);
  ChunkedSolve solve;
  for (;;) {
    const long remaining = max_steps - solver.NumSteps();
    const bool beyond = t_out > solver.CurrentTime();  // steps are needed to reach t_out
    solve.cpu_spent = cpu_budget && beyond && cpu_deadline_.Passed();
    if ((remaining <= 0 && beyond) || solve.cpu_spent) {
      // A budget is spent and t_out lies beyond the last internal step: stop at the last
      // output (or where the last chunk stopped).
      solve.flag = solver.TooMuchWorkFlag();
      if (!solve.evolved) {
        solve.t_reached = last_t_;
        std::copy(last_y_.begin(), last_y_.end(), y);
      }
      return solve;
    }
    const long chunk = cpu_budget ? cpu_check_pacer_.Chunk(remaining) : remaining;
    solver.LimitSteps(std::max(chunk, 1L));
    const long steps_before = solver.NumSteps();
    cpu_check_pacer_.Start();
    std::fill(y, y + size_, std::numeric_limits<double>::quiet_NaN());
    solve.t_reached = std::numeric_limits<double>::quiet_NaN();
    solve.flag = solver.Solve(t_out, &solve.t_reached);
    cpu_check_pacer_.Finish(solver.NumSteps() - steps_before);
    if (solve.flag >= 0) return solve;
    solve.evolved = true;
    // Only the chunk ran out: go on.
    if (solve.flag != solver.TooMuchWorkFlag() || chunk >= remaining) return solve;
  }
}

bool IntegratorBase::Restart(double t0, const double* y0, const IntegratorOptions& next) {
  const IntegratorOptions& now = options_;
  if (next.method != now.method || next.erk_table != now.erk_table ||
      next.fixed_step != now.fixed_step || next.max_step != now.max_step ||
      next.divergence_limit != now.divergence_limit || next.error_states != now.error_states ||
      !std::isfinite(t0) || !(next.t_final > t0) ||
      (std::isfinite(now.t_final) && !std::isfinite(next.t_final)) || next.max_steps <= 0) {
    return false;
  }
  for (int i = 0; i < size_; ++i) {
    if (!std::isfinite(y0[i])) return false;
  }
  if (!DoRestart(t0, y0, next)) return false;
  ReplaceOptions(next);
  last_t_ = t0;
  std::copy(y0, y0 + size_, last_y_.begin());
  failed_ = false;
  failure_.status = IntegratorStatus::kOk;
  failure_.message.clear();
  return true;
}

AdvanceResult IntegratorBase::AdvanceTo(double t_out, double* y) {
  MBSTREAM_CHECK_MSG(std::isfinite(t_out) && t_out >= last_t_,
                     "AdvanceTo needs finite, non-decreasing output times");
  const double t_final = options_.t_final;
  MBSTREAM_CHECK_MSG(t_out <= t_final + 1e-12 * std::max(1.0, std::abs(t_final)),
                     "AdvanceTo may not go past IntegratorOptions::t_final");
  t_out = std::min(t_out, t_final);

  if (failed_) {
    std::copy(last_y_.begin(), last_y_.end(), y);
    return failure_;
  }
  if (t_out == last_t_) {
    std::copy(last_y_.begin(), last_y_.end(), y);
    return {IntegratorStatus::kOk, t_out, {}};
  }

  AdvanceResult result = DoAdvance(t_out, y);
  const double limit = options_.divergence_limit;
  const int limited = LimitedStates(size_, options_.error_states);
  if (result.status == IntegratorStatus::kOk) {
    if (IsHealthyState(y, size_, limited, limit)) {
      std::copy(y, y + size_, last_y_.begin());
      last_t_ = t_out;
      result.t = t_out;
      return result;
    }
    result = {IntegratorStatus::kDiverged, last_t_,
              DivergedMessage(name(), t_out, limit, method_kind())};
  }

  // Failure: y must hold the last good state, at result.t.
  if (!(result.t >= last_t_ && result.t <= t_out) || !IsHealthyState(y, size_, limited, limit)) {
    std::copy(last_y_.begin(), last_y_.end(), y);
    result.t = last_t_;
  } else {
    std::copy(y, y + size_, last_y_.begin());
    last_t_ = result.t;
  }
  failed_ = true;
  failure_ = result;
  return result;
}

}  // namespace mbstream
