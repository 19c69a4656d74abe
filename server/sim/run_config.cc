#include "server/sim/run_config.h"

#include <array>
#include <utility>

namespace mbstream {

namespace {

constexpr std::array<std::pair<Formulation, const char*>, 6> kFormulations{{
    {Formulation::kAuto, "auto"},
    {Formulation::kKinematic, "kinematic"},
    {Formulation::kJoint, "joint"},
    {Formulation::kBodyIndex3, "body-index3"},
    {Formulation::kBodyIndex2, "body-index2"},
    {Formulation::kBodyBaumgarte, "body-baumgarte"},
}};

constexpr std::array<std::pair<Method, const char*>, 7> kMethods{{
    {Method::kBdf, "bdf"},
    {Method::kAdams, "adams"},
    {Method::kErk, "erk"},
    {Method::kDirk, "dirk"},
    {Method::kIda, "ida"},
    {Method::kRk4, "rk4"},
    {Method::kEuler, "euler"},
}};

template <typename Enum, size_t N>
const char* NameOf(const std::array<std::pair<Enum, const char*>, N>& table, Enum value) {
  for (const auto& [e, name] : table) {
    if (e == value) return name;
  }
  return "unknown";
}

template <typename Enum, size_t N>
bool Parse(const std::array<std::pair<Enum, const char*>, N>& table, const std::string& name,
           Enum* value) {
  for (const auto& [e, n] : table) {
    if (name == n) {
      *value = e;
      return true;
    }
  }
  return false;
}

}  // namespace

const char* FormulationName(Formulation formulation) { return NameOf(kFormulations, formulation); }
const char* MethodName(Method method) { return NameOf(kMethods, method); }
bool ParseFormulation(const std::string& name, Formulation* formulation) {
  return Parse(kFormulations, name, formulation);
}
bool ParseMethod(const std::string& name, Method* method) { return Parse(kMethods, name, method); }

}  // namespace mbstream
