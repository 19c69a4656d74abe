#include "server/spec/contact_spec.h"

#include <algorithm>
#include <cmath>

#include "server/sim/contact_validation.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

constexpr int kMaxFilterPairs = 10000;
constexpr size_t kMaxFilterNameBytes = 256;

double Finite(double value, const std::string& source, const char* field, const char* unit) {
  if (!std::isfinite(value)) {
    throw InputError(
        FormatString("%s: contact.%s: is %g, not a finite number; give a finite "
                     "value (%s)",
                     source.c_str(), field, value, unit));
  }
  return value;
}

const std::string& Name(const std::string& name, const std::string& source, int k,
                        const char* side) {
  const bool control = std::any_of(name.begin(), name.end(),
                                   [](char c) { return static_cast<unsigned char>(c) < 0x20; });
  if (name.empty() || name.size() > kMaxFilterNameBytes || control) {
    throw InputError(
        FormatString("%s: contact.collision_filter[%d].%s: give a link or collision "
                     "name of the model (1 to %d bytes, no control characters)",
                     source.c_str(), k, side, static_cast<int>(kMaxFilterNameBytes)));
  }
  return name;
}

}  // namespace

ContactSettings ToContactSettings(const v1::Contact& spec, const std::string& source) {
  ContactSettings s;
  if (spec.has_enabled()) s.enabled = spec.enabled();
  if (spec.has_stiffness_n_per_m()) {
    s.stiffness = Finite(spec.stiffness_n_per_m(), source, "stiffness_n_per_m", "N/m");
  }
  if (spec.has_dissipation_s_per_m()) {
    s.dissipation = Finite(spec.dissipation_s_per_m(), source, "dissipation_s_per_m", "s/m");
  }
  if (spec.has_mu_static()) s.mu_static = Finite(spec.mu_static(), source, "mu_static", "");
  if (spec.has_mu_dynamic()) s.mu_dynamic = Finite(spec.mu_dynamic(), source, "mu_dynamic", "");
  if (spec.has_stiction_tolerance_m_per_s()) {
    s.stiction_tolerance =
        Finite(spec.stiction_tolerance_m_per_s(), source, "stiction_tolerance_m_per_s", "m/s");
  }
  if (spec.has_hertz_modulus_pa()) {
    s.hertz_modulus = Finite(spec.hertz_modulus_pa(), source, "hertz_modulus_pa", "Pa");
  }
  if (spec.collision_filter_size() > kMaxFilterPairs) {
    throw InputError(
        FormatString("%s: contact.collision_filter: has %d pairs, more than %d; "
                     "filter by link rather than by collision",
                     source.c_str(), spec.collision_filter_size(), kMaxFilterPairs));
  }
  for (int k = 0; k < spec.collision_filter_size(); ++k) {
    const v1::CollisionFilter& pair = spec.collision_filter(k);
    s.filter.emplace_back(Name(pair.a(), source, k, "a"), Name(pair.b(), source, k, "b"));
  }
  return s;
}

void ToContactSpec(const ContactSettings& s, v1::Contact* spec) {
  spec->set_enabled(s.enabled);
  spec->set_stiffness_n_per_m(s.stiffness);
  spec->set_dissipation_s_per_m(s.dissipation);
  spec->set_mu_static(s.mu_static);
  spec->set_mu_dynamic(s.mu_dynamic);
  spec->set_stiction_tolerance_m_per_s(s.stiction_tolerance);
  if (s.hertz_modulus != 0.0) spec->set_hertz_modulus_pa(s.hertz_modulus);
  for (const auto& [a, b] : s.filter) {
    v1::CollisionFilter* pair = spec->add_collision_filter();
    pair->set_a(a);
    pair->set_b(b);
  }
}

}  // namespace mbstream
