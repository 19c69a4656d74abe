// What a run says of contact (the run spec's `contact` section, docs/contact.md): on or off,
// the defaults of the surface parameters a model file does not give, the stiction tolerance,
// and the pairs that never touch. A plain value, comparable; validated at the edge
// (ValidateRun), never here.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace mbstream {

struct ContactSettings {
  // Contact forces act when the model has collision geometry and this is true.
  bool enabled = true;
  // Defaults for a geometry whose model file gives no value (collision_geometry.h).
  double stiffness = 1e5;            // N/m, point-contact stiffness k
  double dissipation = 0.2;          // s/m, Hunt-Crossley dissipation d
  double mu_static = 0.6;            // static friction coefficient
  double mu_dynamic = 0.5;           // dynamic friction coefficient (<= mu_static)
  double stiction_tolerance = 1e-4;  // m/s, v_s of the Stribeck function
  // Pa, the effective modulus E* of Hertz contact: > 0, a sphere against a sphere or a plane
  // takes f_n = (4/3) E* sqrt(R*) delta^1.5 (1 + d delta') instead of k delta (1 + d delta')
  // (contact_law.h; R* = R1 R2 / (R1 + R2), a plane's R infinite). 0: point contact for all.
  double hertz_modulus = 0.0;
  // Pairs that never touch, each side a link name or a collision name (either order).
  std::vector<std::pair<std::string, std::string>> filter;

  bool operator==(const ContactSettings&) const = default;
};

}  // namespace mbstream
