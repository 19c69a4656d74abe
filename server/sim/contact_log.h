// A run's contacts at its output frames (contacts.csv, docs/contact.md) and their summary:
// the largest penetration and the peak contact count. Filled by the joint-space run from the
// contacts of each output state; allocates as it grows (once per output frame, never in a
// time step).
#pragma once

#include <string>
#include <vector>

#include "server/contact/contact_forces.h"

namespace mbstream {

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

  // Starts the log for the geometries of `forces`' model.
  void Start(const ContactForces& forces);
  // Appends the contacts of the last evaluation at output time t.
  void Record(double t, const ContactForces& forces);
};

}  // namespace mbstream
