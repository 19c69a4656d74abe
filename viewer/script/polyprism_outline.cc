#include "viewer/script/polyprism_outline.h"

#include <cmath>
#include <numbers>
#include <string>

namespace mbstream::scene_script {

namespace {

std::string Point(const Eigen::Vector2d& p) {
  return "(" + FormatNumber(p.x()) + ", " + FormatNumber(p.y()) + ")";
}

// Appends the arc's points after `from` (which is already in `out`), ending at step.to.
bool AppendArc(const Eigen::Vector2d& from, const PolyprismStep& step,
               std::vector<Eigen::Vector2d>* out, Diagnostics* diagnostics) {
  if (step.radius == 0) return false;  // reported by the parser
  const Eigen::Vector2d d = step.to - from;
  const double chord = d.norm();
  const double r = std::abs(step.radius);
  if (chord < 1e-9) {
    diagnostics->Error(step.position, "Arc to " + Point(step.to) +
                                          " ends where it starts; give a different end point");
    return false;
  }
  const double half = chord / 2;
  if (r < half * (1 - 1e-9)) {
    diagnostics->Error(step.position, "Arc to " + Point(step.to) + ": radius " + FormatNumber(r) +
                                          " is shorter than half the chord (" + FormatNumber(half) +
                                          "); use a radius of at least " + FormatNumber(half));
    return false;
  }
  const double h = std::sqrt(std::max(0.0, r * r - half * half));
  const Eigen::Vector2d right(d.y() / chord, -d.x() / chord);
  const bool clockwise = step.radius > 0;
  const bool centre_right = clockwise != step.large;
  const Eigen::Vector2d centre = (from + step.to) / 2 + (centre_right ? h : -h) * right;
  const double a0 = std::atan2(from.y() - centre.y(), from.x() - centre.x());
  const double a1 = std::atan2(step.to.y() - centre.y(), step.to.x() - centre.x());
  constexpr double kTwoPi = 2 * std::numbers::pi;
  double sweep = a1 - a0;
  if (clockwise) {
    while (sweep > 0) sweep -= kTwoPi;
    while (sweep <= -kTwoPi) sweep += kTwoPi;
  } else {
    while (sweep < 0) sweep += kTwoPi;
    while (sweep >= kTwoPi) sweep -= kTwoPi;
  }
  for (int i = 1; i < step.resolution; ++i) {
    const double a = a0 + sweep * i / step.resolution;
    out->push_back(centre + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  out->push_back(step.to);
  return true;
}

}  // namespace

double TwiceSignedArea(const std::vector<Eigen::Vector2d>& polygon) {
  double area = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  return area;
}

std::vector<Eigen::Vector2d> PolyprismOutline(const PolyprismShape& prism,
                                              Diagnostics* diagnostics) {
  std::vector<Eigen::Vector2d> outline;
  bool ok = true;
  for (const PolyprismStep& step : prism.steps) {
    if (step.arc && !outline.empty()) {
      ok = AppendArc(outline.back(), step, &outline, diagnostics) && ok;
    } else {
      outline.push_back(step.to);
    }
  }
  // A closing point equal to the first one is dropped: the outline closes itself.
  if (outline.size() > 1 && (outline.back() - outline.front()).norm() < 1e-9) outline.pop_back();
  if (ok && outline.size() >= 3 && std::abs(TwiceSignedArea(outline)) < 1e-9) {
    diagnostics->Error(prism.steps.front().position,
                       "the Polyprism outline encloses no area; check its points");
  }
  return outline;
}

}  // namespace mbstream::scene_script
