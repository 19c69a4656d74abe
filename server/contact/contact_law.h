// The contact law (docs/contact.md), as Drake's continuous point contact: Hunt-Crossley normal
// force, parameters of two surfaces combined, and the regularised Stribeck friction
// coefficient. Pure functions, inline, no allocation.
#pragma once

#include <algorithm>
#include <cmath>

namespace mbstream::contact_law {

// f_n = k delta (1 + d delta'), clamped at 0 (N): delta the penetration (m, >= 0), delta'
// its rate (m/s, > 0 when approaching), k in N/m, d in s/m.
inline double NormalForce(double k, double d, double delta, double delta_rate) {
  return std::max(0.0, k * delta * (1.0 + d * delta_rate));
}

// Hertz contact of two spheres (or a sphere and a plane): f_n = K delta^1.5 (1 + d delta'),
// clamped at 0 (N), with K = (4/3) E* sqrt(R*) (HertzStiffness; N/m^1.5).
inline double HertzNormalForce(double K, double d, double delta, double delta_rate) {
  return std::max(0.0, K * delta * std::sqrt(delta) * (1.0 + d * delta_rate));
}

// K = (4/3) E* sqrt(R*) for the effective modulus E* (Pa) and the effective radius
// R* = R1 R2 / (R1 + R2) (m; a plane's R infinite: R* = the sphere's).
inline double HertzStiffness(double modulus, double r1, double r2) {
  const double r = std::isinf(r2) ? r1 : std::isinf(r1) ? r2 : r1 * r2 / (r1 + r2);
  return 4.0 / 3.0 * modulus * std::sqrt(r);
}

// Two stiffnesses in series: k = k1 k2 / (k1 + k2) (0 when both are 0).
inline double CombineStiffness(double k1, double k2) {
  return k1 + k2 == 0.0 ? 0.0 : k1 * k2 / (k1 + k2);
}

// Dissipation weighted by stiffness: d = (k2 d1 + k1 d2) / (k1 + k2).
inline double CombineDissipation(double k1, double d1, double k2, double d2) {
  return k1 + k2 == 0.0 ? 0.0 : (k2 * d1 + k1 * d2) / (k1 + k2);
}

// Friction coefficients: mu = 2 mu1 mu2 / (mu1 + mu2) (0 when both are 0).
inline double CombineFriction(double mu1, double mu2) {
  return mu1 + mu2 == 0.0 ? 0.0 : 2.0 * mu1 * mu2 / (mu1 + mu2);
}

// 10 x^3 - 15 x^4 + 6 x^5 for x in [0, 1]: 0 to 1 with zero slope and curvature at both ends.
inline double Step5(double x) {
  const double x3 = x * x * x;
  return x3 * (10.0 + x * (6.0 * x - 15.0));
}

// Drake's Stribeck friction coefficient at slip speed `speed` (m/s, >= 0) with stiction
// tolerance v_s (m/s): with s = speed / v_s,
//   s < 1:      mu_s step5(s)
//   1 <= s < 3: mu_s - (mu_s - mu_d) step5((s - 1) / 2)
//   s >= 3:     mu_d
inline double StribeckMu(double speed, double mu_s, double mu_d, double v_s) {
  const double s = speed / v_s;
  if (s >= 3.0) return mu_d;
  if (s >= 1.0) return mu_s - (mu_s - mu_d) * Step5((s - 1.0) / 2.0);
  return mu_s * Step5(s);
}

}  // namespace mbstream::contact_law
