#include "server/choose/choice_json.h"

#include <cmath>

#include <nlohmann/json.hpp>

namespace mbstream {

namespace {

using Json = nlohmann::ordered_json;

// A figure, or null when not measured (negative) or not finite.
Json Figure(double value) { return value >= 0.0 && std::isfinite(value) ? Json(value) : Json(); }

Json Errors(const ErrorFigures& e) {
  return {{"tcp_m", Figure(e.tcp_m)},
          {"joint_rad", Figure(e.joint_rad)},
          {"energy_rel", Figure(e.energy_rel)}};
}

Json CandidateJson(const Candidate& c) {
  Json j = {{"name", c.name}, {"piloted", c.piloted}, {"usable", c.usable}};
  if (!c.verdict.empty()) j["verdict"] = c.verdict;
  if (c.explicit_cpu_floor_s >= 0.0) j["explicit_cpu_floor_s"] = Figure(c.explicit_cpu_floor_s);
  if (c.piloted) {
    j["pilot"] = {{"rtol", {c.rtol[0], c.rtol[1]}},    {"steps", {c.steps[0], c.steps[1]}},
                  {"cpu_s", {c.cpu_s[0], c.cpu_s[1]}}, {"error_at_rtol0", Errors(c.error)},
                  {"growth_to_end", Errors(c.growth)}, {"steps_exponent", c.steps_exponent},
                  {"cpu_per_step_s", c.cpu_per_step_s}};
  }
  if (c.usable) {
    j["predicted"] = {{"run_rtol", c.run_rtol},
                      {"run_cpu_s", Figure(c.run_cpu_s)},
                      {"check_rtol", c.check_rtol},
                      {"check_cpu_s", Figure(c.check_cpu_s)},
                      {"resolvable", c.resolvable}};
  }
  return j;
}

// Where a run took its first frames from a pilot (PilotLink::prefix) and integrated on.
Json Continuation(const RunPrefix& prefix, double from_s) {
  return {{"from_s", from_s},
          {"method", prefix.method},
          {"rtol", prefix.rtol},
          {"note",
           "the frames up to from_s are this pilot's (computed during the choice, its CPU "
           "time counted there); the pilot's integration went on from there at this run's "
           "tolerance"}};
}

}  // namespace

std::string ChoiceJson(const RunConfig& asked, const MethodChoice& choice,
                       const Verification& verification, const RunStats& run) {
  const double run_cpu_s = run.cpu_s;
  Json j;
  j["target"] = {
      {"tcp_error_m", Figure(asked.target.tcp_error_m > 0 ? asked.target.tcp_error_m : -1)},
      {"joint_error_rad",
       Figure(asked.target.joint_error_rad > 0 ? asked.target.joint_error_rad : -1)},
      {"energy_error_rel",
       Figure(asked.target.energy_error_rel > 0 ? asked.target.energy_error_rel : -1)}};
  j["formulation"] = choice.formulation;
  j["formulation_reason"] = choice.formulation_reason;
  if (choice.closed_form) {
    j["pick"] = {{"formulation", "kinematic"}, {"method", "none"}};
  } else {
    j["pilot"] = {{"span_s", choice.pilot.span_s}, {"interval_s", choice.pilot.interval_s}};
    Json samples = Json::array();
    for (size_t k = 0; k < choice.stiffness.times.size(); ++k) {
      samples.push_back({{"t_s", choice.stiffness.times[k]},
                         {"eigenvalue_max_per_s", Figure(choice.stiffness.eigenvalues[k])}});
    }
    j["stiffness"] = {{"samples", samples},
                      {"eigenvalue_max_per_s", Figure(choice.stiffness.largest)},
                      {"separation_rate_per_s", choice.stiffness.separation_rate},
                      {"error_growth_rate_used_per_s", choice.separation_rate_used},
                      {"rhs_cost_s", choice.stiffness.rhs_cost_s},
                      {"bdf_mean_step_s", Figure(choice.bdf_mean_step_s)},
                      {"explicit_step_limit_s",
                       Figure(choice.stiffness.largest > 0 ? 3.3 / choice.stiffness.largest : -1)}};
    Json candidates = Json::array();
    for (const Candidate& c : choice.candidates) candidates.push_back(CandidateJson(c));
    j["candidates"] = candidates;
    j["pick"] = {{"formulation", FormulationName(choice.run.formulation)},
                 {"method", MethodName(choice.run.method)},
                 {"erk_table", choice.run.erk_table},
                 {"rtol", choice.run.rtol},
                 {"atol", choice.run.atol},
                 {"resolvable", choice.resolvable}};
    if (run.continued_from_s > 0.0)
      j["pick"]["continues_pilot"] = Continuation(*choice.continues, run.continued_from_s);
  }
  j["reason"] = choice.reason;
  j["verification"] = {{"how", verification.how},
                       {"ran", verification.ran},
                       {"rtol", Figure(verification.ran ? verification.rtol : -1)},
                       {"budget_cpu_s", Figure(verification.ran ? verification.budget_cpu_s : -1)},
                       {"achieved", Errors(verification.achieved)},
                       {"target_met", verification.met ? Json(*verification.met) : Json()},
                       {"horizon_s", Figure(verification.horizon_s)},
                       {"message", verification.message}};
  if (verification.continued_from_s > 0.0 && verification.prefix != nullptr) {
    j["verification"]["continues_pilot"] =
        Continuation(*verification.prefix, verification.continued_from_s);
  }
  j["cpu_s"] = {{"choice", choice.cpu_s},
                {"run", run_cpu_s},
                {"verification", verification.cpu_s},
                {"total", choice.cpu_s + run_cpu_s + verification.cpu_s}};
  return j.dump();
}

}  // namespace mbstream
