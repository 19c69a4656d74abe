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
      break;
    case Method::kAdams:  // functional iteration converges for h |lambda| below about 1
      candidate.stability_reach = 1.0;
      candidate.rhs_per_step = 2.0;
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

}  // namespace mbstream
