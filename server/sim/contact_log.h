// A run's contacts at its output frames (contacts.csv, docs/contact.md) and their summary:
// the largest penetration and the peak contact count. Filled by the joint-space run from the
// contacts of each output state; allocates as it grows (once per output frame, never in a
// time step).
#pragma once

#include <string>
#include <vector>

#include "server/contact/contact_forces.h"

namespace mbstream {

// A run with contact forces (docs/contact.md), over every output frame it computed: the
// summary a remote client gets (RunStats.contact on the wire).
struct ContactStats {
  bool active = false;             // the run had contact forces
  double penetration_max_m = 0.0;  // m, the largest penetration
  int contacts_peak = 0;           // the most contacts at one output frame
  // The largest penetration relative to the size of the smaller geometry of its pair.
  double penetration_relative_max = 0.0;
  // J, the work the contact forces dissipated (Hunt-Crossley damping and friction; a
  // quadrature of their power, docs/contact.md), at the last frame.
  double dissipated_work_j = 0.0;
};

struct ContactRecord {
  double t = 0.0;                      // s, the output frame's time
  int geometry_a = 0, geometry_b = 0;  // indices into ContactLog::link / collision
  double point[3] = {0, 0, 0};         // m, world: midway between the surfaces
  double normal[3] = {0, 0, 1};        // unit, world, from b toward a
  double depth = 0.0;                  // m, penetration
  double normal_force = 0.0;           // N, on a (b: the opposite)
  double friction[3] = {0, 0, 0};      // N, world, on a (b: the opposite)
};

struct ContactLog {
  bool active = false;  // the run had contact forces
  // Keep every frame's records (false: the latest frame's only, for a run whose FrameSink keeps
  // the frames itself and whose result holds the latest frame alone).
  bool keep_records = true;
  std::vector<std::string> link;       // per geometry: its link
  std::vector<std::string> collision;  // per geometry: its <collision> name
  std::vector<ContactRecord> records;  // every output frame's contacts, in frame order
  double depth_max = 0.0;              // m, the largest penetration over the output frames
  int count_peak = 0;                  // the most contacts at one output frame
  // The largest penetration relative to the size of the smaller geometry of its pair (a
  // sphere's, cylinder's or capsule's radius, half a box's shortest edge), where and when.
  std::vector<double> size;  // per geometry, m (infinity for a plane)
  double relative_max = 0.0;
  double relative_t = 0.0;
  int relative_a = -1, relative_b = -1;
  // J, the work the contacts dissipated up to the last frame: the integral of
  // ContactForces::dissipated_power, a quadrature of the run's ODE.
  double dissipated_work = 0.0;

  // The run's summary (RunStats::contact).
  ContactStats Stats() const {
    return {true, depth_max, count_peak, relative_max, dissipated_work};
  }

  // "contact: ..." when relative_max exceeds kDeepContact, naming the pair, the time and what
  // to do; "" otherwise.
  static constexpr double kDeepContact = 0.1;
  std::string DeepContactWarning() const;

  // Starts the log for the geometries of `forces`' model.
  void Start(const ContactForces& forces);
  // Appends the contacts of the last evaluation at output time t.
  void Record(double t, const ContactForces& forces);
};

}  // namespace mbstream
