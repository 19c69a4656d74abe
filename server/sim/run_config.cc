#include "server/sim/run_config.h"

#include "shared/common/name_table.h"

namespace mbstream {

namespace {

constexpr NameTable<Formulation, 6> kFormulations{{
    {Formulation::kAuto, "auto"},
    {Formulation::kKinematic, "kinematic"},
    {Formulation::kJoint, "joint"},
    {Formulation::kBodyIndex3, "body-index3"},
    {Formulation::kBodyIndex2, "body-index2"},
    {Formulation::kBodyBaumgarte, "body-baumgarte"},
}};

bool SameVector(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() && (a.size() == 0 || a == b);
}

}  // namespace

bool RunConfig::operator==(const RunConfig& other) const {
  return duration == other.duration && output_interval == other.output_interval &&
         max_step == other.max_step && formulation == other.formulation && method == other.method &&
         erk_table == other.erk_table && rtol == other.rtol && atol == other.atol &&
         fixed_step == other.fixed_step && gravity == other.gravity && SameVector(q0, other.q0) &&
         SameVector(qd0, other.qd0) && initial_bodies == other.initial_bodies &&
         drives == other.drives && want_torques == other.want_torques &&
         want_loop_forces == other.want_loop_forces && baumgarte == other.baumgarte &&
         max_steps == other.max_steps && max_cpu_s == other.max_cpu_s && target == other.target &&
         method_auto == other.method_auto && verify == other.verify && keep == other.keep &&
         contact == other.contact && sensor_points == other.sensor_points;
}

const char* FormulationName(Formulation formulation) { return NameOf(kFormulations, formulation); }
bool ParseFormulation(const std::string& name, Formulation* formulation) {
  return ParseName(kFormulations, name, formulation);
}

}  // namespace mbstream
