#include "server/sim/contact_log.h"

#include <algorithm>

namespace mbstream {

void ContactLog::Start(const ContactForces& forces) {
  active = true;
  link.clear();
  collision.clear();
  for (const CollisionGeometry& g : forces.model().collisions) {
    link.push_back(g.link);
    collision.push_back(g.name);
  }
}

void ContactLog::Record(double t, const ContactForces& forces) {
  const std::vector<ContactPoint>& contacts = forces.contacts();
  count_peak = std::max(count_peak, static_cast<int>(contacts.size()));
  if (!keep_records) records.clear();  // the latest frame's only (capacity kept)
  for (const ContactPoint& c : contacts) {
    depth_max = std::max(depth_max, c.depth);
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

}  // namespace mbstream
