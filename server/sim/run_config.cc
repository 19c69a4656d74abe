#include "server/sim/run_config.h"

#include "common/name_table.h"

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

}  // namespace

const char* FormulationName(Formulation formulation) { return NameOf(kFormulations, formulation); }
bool ParseFormulation(const std::string& name, Formulation* formulation) {
  return ParseName(kFormulations, name, formulation);
}

}  // namespace mbstream
