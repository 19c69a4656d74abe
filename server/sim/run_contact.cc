#include "server/sim/run_contact.h"

#include <vector>

#include "shared/common/format.h"

namespace mbstream {

void AddContactReason(const Model& model, const ContactSettings& settings,
                      const ContactForces* contact, double max_step, RunStats* stats) {
  if (contact != nullptr) {
    stats->formulation_reason += FormatString(
        "; contact on: %d geometry pair(s) may touch (compliant point contact), adaptive steps "
        "at most %g s",
        contact->num_allowed_pairs(), max_step);
  } else if (!model.collisions.empty()) {
    stats->formulation_reason +=
        settings.enabled ? "; contact off: no pair of the model's collision geometries may "
                           "touch (same or adjacent bodies, bitmasks, filter)"
                         : "; contact off (contact.enabled false)";
  }
}

void StartContactLog(const ContactForces* contact, const FrameSink* sink, ContactLog* log) {
  if (contact == nullptr) return;
  log->Start(*contact);
  log->keep_records = sink == nullptr || !sink->KeepsFrames();
}

void FinishContactLog(const ContactLog& log, RunStats* stats) {
  if (log.active) stats->contact = log.Stats();
  if (const std::string deep = log.DeepContactWarning(); !deep.empty()) {
    stats->warnings.push_back(deep);
  }
}

std::string DeepestContactNote(const ContactForces& contact) {
  const ContactPoint* deepest = nullptr;
  for (const ContactPoint& c : contact.contacts()) {
    if (deepest == nullptr || !(c.depth <= deepest->depth)) deepest = &c;
  }
  if (deepest == nullptr) return "; no contact at the last evaluation";
  const std::vector<CollisionGeometry>& g = contact.model().collisions;
  return FormatString(
      "; the deepest contact at the last evaluation: '%s' (%s) against '%s' (%s), %g m deep, "
      "normal force %g N (a stiff contact needs an implicit method, bdf or dirk, or a lower "
      "contact.stiffness_n_per_m)",
      g[deepest->geometry_a].link.c_str(), g[deepest->geometry_a].name.c_str(),
      g[deepest->geometry_b].link.c_str(), g[deepest->geometry_b].name.c_str(), deepest->depth,
      deepest->normal_force);
}

}  // namespace mbstream
