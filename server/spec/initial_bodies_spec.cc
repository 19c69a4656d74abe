#include "server/spec/initial_bodies_spec.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "server/drives/pose_motion.h"
#include "server/model/coordinate_names.h"
#include "shared/common/check.h"
#include "shared/common/did_you_mean.h"
#include "shared/common/format.h"

namespace mbstream {

namespace {

constexpr int kMaxInitialBodies = 10000;     // entries of initial_bodies
constexpr size_t kMaxBodyNameBytes = 256;    // as the spec's other names
constexpr double kMaxBodyPosition = 1e6;     // m from the world's origin
constexpr double kMaxBodySpeed = 1e6;        // m/s and rad/s
constexpr double kBodyUnitTolerance = 1e-6;  // |norm - 1| of a quaternion
constexpr double kMaxBodyAngle = 1e3;        // rad, roll, pitch and yaw
// A quaternion's components: finite (its norm is checked then).
constexpr double kAnyFinite = std::numeric_limits<double>::infinity();

class BodyChecker {
 public:
  BodyChecker(const std::string& source, int k)
      : prefix_(source + ": initial_bodies[" + std::to_string(k) + "]") {}

  [[noreturn]] void Fail(const std::string& field, const std::string& problem) const {
    throw InputError(prefix_ + (field.empty() ? "" : "." + field) + ": " + problem);
  }

  double Value(double value, const std::string& field, const char* unit, double bound) const {
    if (!std::isfinite(value)) {
      Fail(field,
           FormatString("is %g, not a finite number; give a finite value (%s)", value, unit));
    }
    if (std::abs(value) > bound) {
      Fail(field, FormatString("is %g %s, beyond +-%g %s; give a value within that", value, unit,
                               bound, unit));
    }
    return value;
  }

  Eigen::Vector3d Vector(const v1::Vector3& v, const std::string& field, const char* unit,
                         double bound) const {
    return {Value(v.x(), field + ".x", unit, bound), Value(v.y(), field + ".y", unit, bound),
            Value(v.z(), field + ".z", unit, bound)};
  }

 private:
  std::string prefix_;
};

std::string ListedBodies(const std::vector<std::string>& names) {
  constexpr size_t kListed = 20;
  std::string joined;
  for (size_t i = 0; i < names.size() && i < kListed; ++i) {
    joined += (i == 0 ? "" : ", ") + names[i];
  }
  if (names.size() > kListed) joined += ", ... (" + std::to_string(names.size()) + " in all)";
  return joined;
}

std::string CheckedBodyName(const std::string& name, const std::vector<std::string>& free_bodies,
                            const BodyChecker& check) {
  const bool control = std::any_of(name.begin(), name.end(),
                                   [](char c) { return static_cast<unsigned char>(c) < 0x20; });
  if (name.empty() || name.size() > kMaxBodyNameBytes || control) {
    check.Fail("name", "give a free body's name (1 to 256 bytes, no control characters)" +
                           std::string(free_bodies.empty() ? "" : ": one of ") +
                           ListedBodies(free_bodies));
  }
  if (std::find(free_bodies.begin(), free_bodies.end(), name) != free_bodies.end()) return name;
  const std::string shown = name.size() <= 64 ? name : name.substr(0, 64) + "...";
  if (free_bodies.empty()) {
    check.Fail("name", "'" + shown +
                           "': the model has no free bodies (every body is attached to the "
                           "world); give initial_q and initial_qd for its joints instead");
  }
  check.Fail("name", "'" + shown + "' is no free body of the model" +
                         DidYouMean(name, free_bodies) + "; give one of " +
                         ListedBodies(free_bodies) +
                         " (a free joint's name, as the position names NAME.x ... NAME.qz show)");
}

Eigen::Vector4d OrientationOf(const v1::BodyState& body, const BodyChecker& check) {
  if (body.has_rpy()) {
    const double roll = check.Value(body.rpy().roll(), "rpy.roll", "rad", kMaxBodyAngle);
    const double pitch = check.Value(body.rpy().pitch(), "rpy.pitch", "rad", kMaxBodyAngle);
    const double yaw = check.Value(body.rpy().yaw(), "rpy.yaw", "rad", kMaxBodyAngle);
    Eigen::Vector4d quat;
    pose_motion::Quaternion(roll, pitch, yaw, quat.data());
    return quat;
  }
  const v1::Quaternion& q = body.quaternion();
  const Eigen::Vector4d quat{check.Value(q.w(), "quaternion.w", "dimensionless", kAnyFinite),
                             check.Value(q.x(), "quaternion.x", "dimensionless", kAnyFinite),
                             check.Value(q.y(), "quaternion.y", "dimensionless", kAnyFinite),
                             check.Value(q.z(), "quaternion.z", "dimensionless", kAnyFinite)};
  const double norm = quat.norm();
  if (!(std::abs(norm - 1.0) <= kBodyUnitTolerance)) {
    check.Fail("quaternion", FormatString("(w x y z) = (%g, %g, %g, %g) has norm %.9g; give a "
                                          "unit quaternion (norm 1 within 1e-6), or rpy",
                                          quat[0], quat[1], quat[2], quat[3], norm));
  }
  return quat;
}

}  // namespace

std::vector<std::string> FreeBodyNames(const std::vector<std::string>& position_names) {
  std::vector<std::string> names;
  const std::string first = kFreePositionSuffixes[0];
  for (size_t i = 0; i + kFreeNq <= position_names.size(); ++i) {
    const std::string& x = position_names[i];
    if (x.size() <= first.size() || x.compare(x.size() - first.size(), first.size(), first) != 0) {
      continue;
    }
    const std::string name = x.substr(0, x.size() - first.size());
    bool all = true;
    for (int k = 1; k < kFreeNq && all; ++k) {
      all = position_names[i + k] == name + kFreePositionSuffixes[k];
    }
    if (!all) continue;
    names.push_back(name);
    i += kFreeNq - 1;
  }
  return names;
}

std::vector<InitialBodyState> ToInitialBodies(
    const google::protobuf::RepeatedPtrField<v1::BodyState>& spec,
    const std::vector<std::string>& position_names, const std::string& source) {
  if (spec.empty()) return {};
  if (spec.size() > kMaxInitialBodies) {
    throw InputError(
        FormatString("%s: initial_bodies: has %d entries, more than %d; give one per "
                     "free body",
                     source.c_str(), spec.size(), kMaxInitialBodies));
  }
  const std::vector<std::string> free_bodies = FreeBodyNames(position_names);
  std::vector<InitialBodyState> bodies;
  for (int k = 0; k < spec.size(); ++k) {
    const v1::BodyState& body = spec[k];
    const BodyChecker check(source, k);
    InitialBodyState state;
    state.name = CheckedBodyName(body.name(), free_bodies, check);
    for (size_t j = 0; j < bodies.size(); ++j) {
      if (bodies[j].name == state.name) {
        check.Fail("name", "'" + state.name + "' is given already by initial_bodies[" +
                               std::to_string(j) + "]; give each body once");
      }
    }
    if (body.has_position_m()) {
      state.position = check.Vector(body.position_m(), "position_m", "m", kMaxBodyPosition);
    }
    if (body.has_quaternion() || body.has_rpy()) state.quaternion = OrientationOf(body, check);
    if (body.has_linear_velocity_m_per_s()) {
      state.linear_velocity = check.Vector(body.linear_velocity_m_per_s(),
                                           "linear_velocity_m_per_s", "m/s", kMaxBodySpeed);
    }
    if (body.has_angular_velocity_rad_per_s()) {
      state.angular_velocity = check.Vector(body.angular_velocity_rad_per_s(),
                                            "angular_velocity_rad_per_s", "rad/s", kMaxBodySpeed);
    }
    bodies.push_back(std::move(state));
  }
  return bodies;
}

void ToBodyStateSpecs(const std::vector<InitialBodyState>& bodies,
                      google::protobuf::RepeatedPtrField<v1::BodyState>* spec) {
  const auto set = [](const Eigen::Vector3d& from, v1::Vector3* to) {
    to->set_x(from.x());
    to->set_y(from.y());
    to->set_z(from.z());
  };
  for (const InitialBodyState& state : bodies) {
    v1::BodyState* body = spec->Add();
    body->set_name(state.name);
    if (state.position) set(*state.position, body->mutable_position_m());
    if (state.quaternion) {
      v1::Quaternion* quat = body->mutable_quaternion();
      quat->set_w((*state.quaternion)[0]);
      quat->set_x((*state.quaternion)[1]);
      quat->set_y((*state.quaternion)[2]);
      quat->set_z((*state.quaternion)[3]);
    }
    if (state.linear_velocity) set(*state.linear_velocity, body->mutable_linear_velocity_m_per_s());
    if (state.angular_velocity) {
      set(*state.angular_velocity, body->mutable_angular_velocity_rad_per_s());
    }
  }
}

}  // namespace mbstream
