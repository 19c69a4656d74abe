#include "server/sim/run_prefix.h"

#include <algorithm>
#include <utility>

#include "server/sim/joint_integration.h"

namespace mbstream {

std::shared_ptr<JointIntegration> RunPrefix::TakeIntegrationIf(
    const std::function<bool(JointIntegration&)>& fits) const {
  std::lock_guard<std::mutex> lock(mutex);
  if (integration == nullptr || !fits(*integration)) return nullptr;
  return std::exchange(integration, nullptr);
}

bool RunPrefix::HasIntegration() const {
  std::lock_guard<std::mutex> lock(mutex);
  return integration != nullptr;
}

std::shared_ptr<RunPrefix> MakePrefix(RunResult& result, double rtol, const char* method) {
  auto prefix = std::make_shared<RunPrefix>();
  prefix->num_dofs = result.num_dofs;
  prefix->t = result.t;
  prefix->q = result.q;
  prefix->qd = result.qd;
  prefix->work = result.work;
  prefix->rtol = rtol;
  prefix->method = method;
  prefix->integration = std::move(result.integration);
  return prefix;
}

std::size_t MatchingFrames(const RunPrefix& prefix, const std::vector<double>& times) {
  const std::size_t n = std::min(prefix.t.size(), times.size());
  std::size_t k = 0;
  while (k < n && prefix.t[k] == times[k]) ++k;
  return k;
}

}  // namespace mbstream
