#include "server/sim/contact_log.h"

#include <algorithm>
#include <limits>

#include "shared/common/format.h"

namespace mbstream {

void ContactLog::Start(const ContactForces& forces) {
  active = true;
  link.clear();
  collision.clear();
  for (const CollisionGeometry& g : forces.model().collisions) {
    link.push_back(g.link);
    collision.push_back(g.name);
    size.push_back(ShapeHalfSize(g.shape));
  }
}

void ContactLog::Record(double t, const ContactForces& forces) {
  const std::vector<ContactPoint>& contacts = forces.contacts();
  count_peak = std::max(count_peak, static_cast<int>(contacts.size()));
  if (!keep_records) records.clear();  // the latest frame's only (capacity kept)
  for (const ContactPoint& c : contacts) {
    depth_max = std::max(depth_max, c.depth);
    const double relative = c.depth / std::min(size[c.geometry_a], size[c.geometry_b]);
    if (relative > relative_max) {
      relative_max = relative;
      relative_t = t;
      relative_a = c.geometry_a;
      relative_b = c.geometry_b;
    }
    ContactRecord r;
    r.t = t;
    r.geometry_a = c.geometry_a;
    r.geometry_b = c.geometry_b;
    for (int k = 0; k < 3; ++k) {
      r.point[k] = c.point(k);
      r.normal[k] = c.normal(k);
      r.friction[k] = c.friction_force(k);
    }
    r.depth = c.depth;
    r.normal_force = c.normal_force;
    records.push_back(r);
  }
}

std::string ContactLog::DeepContactWarning() const {
  if (!(relative_max > kDeepContact) || relative_a < 0) return "";
  const auto name = [&](int g) {
    return "'" + link[g] + (collision[g].empty() ? "" : "' ('" + collision[g] + "')") +
           (collision[g].empty() ? "'" : "");
  };
  return FormatString(
      "contact: the penetration between %s and %s reached %.3g %% of the smaller geometry's size "
      "(%g m) at t = %g s, more than %g %%: the compliant contact is too soft for this load; "
      "raise the stiffness (contact.stiffness_n_per_m, drake:point_contact_stiffness)",
      name(relative_a).c_str(), name(relative_b).c_str(), 100.0 * relative_max,
      std::min(size[relative_a], size[relative_b]), relative_t, 100.0 * kDeepContact);
}

}  // namespace mbstream
