#include "server/sim/contact_validation.h"

#include <cmath>

#include "server/sim/joint_integration.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

void Range(double value, double low, double high, bool low_open, const char* field,
           const char* unit, const char* advice) {
  const bool ok = std::isfinite(value) && (low_open ? value > low : value >= low) && value <= high;
  if (!ok) {
    throw InputError(FormatString("contact.%s = %g %s: must be finite and in %s%g, %g]; %s", field,
                                  value, unit, low_open ? "(" : "[", low, high, advice));
  }
}

bool Names(const Model& model, const std::string& name) {
  for (const CollisionGeometry& g : model.collisions) {
    if (g.link == name || (!g.name.empty() && g.name == name)) return true;
  }
  return model.FindFrame(name) >= 0;
}

}  // namespace

void CheckContact(const Model& model, const RunConfig& config,
                  const std::vector<LoopClosure>& loops) {
  const ContactSettings& c = config.contact;
  Range(c.stiffness, 0.0, kMaxContactStiffness, true, "stiffness_n_per_m", "N/m",
        "give a surface stiffness such as 1e5 (rubber on steel, a 1 kg body sinks 0.1 mm)");
  Range(c.dissipation, 0.0, kMaxContactDissipation, false, "dissipation_s_per_m", "s/m",
        "give a Hunt-Crossley dissipation such as 0.2 (0: elastic)");
  Range(c.mu_static, 0.0, kMaxFrictionCoefficient, false, "mu_static", "",
        "give a static friction coefficient such as 0.6");
  Range(c.mu_dynamic, 0.0, kMaxFrictionCoefficient, false, "mu_dynamic", "",
        "give a dynamic friction coefficient such as 0.5");
  if (c.mu_dynamic > c.mu_static) {
    throw InputError(FormatString(
        "contact.mu_dynamic = %g is above contact.mu_static = %g; give mu_dynamic <= mu_static",
        c.mu_dynamic, c.mu_static));
  }
  Range(c.stiction_tolerance, kMinStictionTolerance, kMaxStictionTolerance, false,
        "stiction_tolerance_m_per_s", "m/s",
        "give the slip speed below which friction holds, such as 1e-4");
  Range(c.hertz_modulus, 0.0, kMaxHertzModulus, false, "hertz_modulus_pa", "Pa",
        "give the effective modulus E* of Hertz contact for spheres, such as 1e7 (rubber), or "
        "0 for point contact");
  for (const auto& [a, b] : c.filter) {
    for (const std::string* name : {&a, &b}) {
      if (!Names(model, *name)) {
        throw InputError("contact.collision_filter: '" + *name +
                         "' is neither a link nor a collision of the model; give link or "
                         "collision names as the model spells them");
      }
    }
  }
  if (!MayTouch(model, config.contact)) return;
  // body-baumgarte (an ODE) has the contact forces (server/body/body_contact.h); the body
  // DAEs for IDA do not yet.
  if (config.formulation == Formulation::kBodyIndex3 ||
      config.formulation == Formulation::kBodyIndex2) {
    throw InputError(std::string("formulation ") + FormulationName(config.formulation) +
                     " (a DAE for IDA) has no contact forces yet, and the model's collision "
                     "geometry may touch: use formulation body-baumgarte (an ODE, with contact), "
                     "joint (or auto), or contact.enabled false");
  }
  // Closed loops: the joint-space ODE (closed_loop_ode.h) has the contact forces; the loops'
  // index-2 DAE (method ida) does not yet.
  if (!loops.empty() && config.method == Method::kIda) {
    throw InputError(
        "method ida (the closed loops' index-2 DAE) has no contact forces yet, and the model's "
        "collision geometry may touch: use method bdf (the closed loops' joint-space ODE, "
        "projected onto the loops after each step, has contact), or adams, erk, dirk; or give "
        "contact.enabled false");
  }
}

}  // namespace mbstream
