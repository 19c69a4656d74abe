#include "server/choose/candidate.h"

namespace mbstream {

Candidate MakeCandidate(Method method, const std::string& table) {
  Candidate candidate;
  candidate.method = method;
  candidate.table = table;
  candidate.name = MethodName(method);
  if (!table.empty()) candidate.name += "-" + table;
  switch (method) {
    case Method::kErk:  // Dormand-Prince: 6 new stages a step (FSAL); Verner 8-5-6: 8
      candidate.stability_reach = table == "verner" ? 3.6 : 3.3;
      candidate.rhs_per_step = table == "verner" ? 8.0 : 6.0;
      // Dormand-Prince's error estimate is of order 4 (h^5), Verner 8-5-6's of order 5 (h^6)
      candidate.min_steps_exponent = table == "verner" ? 1.0 / 6.0 : 1.0 / 5.0;
      break;
    case Method::kAdams:  // functional iteration converges for h |lambda| below about 1
      candidate.stability_reach = 1.0;
      candidate.rhs_per_step = 2.0;
      candidate.min_steps_exponent = 1.0 / 13.0;  // CVODE's Adams: order up to 12
      break;
    case Method::kBdf:
    case Method::kIda:                           // IDA's variable-order BDF
      candidate.min_steps_exponent = 1.0 / 6.0;  // order up to 5
      break;
    case Method::kDirk:
      candidate.min_steps_exponent = 1.0 / 4.0;  // ARKODE's default DIRK: error estimate order 3
      break;
    default:
      break;
  }
  return candidate;
}

RunConfig WithCandidate(RunConfig config, const Candidate& candidate, double rtol) {
  config.method = candidate.method;
  config.erk_table = candidate.table;
  config.rtol = rtol;
  config.atol = rtol / 100.0;
  config.method_auto = false;
  config.target = AccuracyTarget{};
  return config;
}

std::shared_ptr<const RunPrefix> PilotToContinue(const Candidate& candidate, double rtol) {
  std::shared_ptr<const RunPrefix> chosen;
  for (const std::shared_ptr<const RunPrefix>& pilot : candidate.pilots) {
    if (pilot != nullptr && pilot->rtol <= rtol && pilot->HasIntegration() &&
        (chosen == nullptr || pilot->rtol > chosen->rtol)) {
      chosen = pilot;
    }
  }
  return chosen;
}

}  // namespace mbstream
