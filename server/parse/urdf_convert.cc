#include "server/parse/urdf_convert.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <optional>

#include "server/model/model_builder.h"
#include "server/parse/urdf_repairs.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string Format(const Vector3d& v) {
  return "(" + FormatNumber(v.x()) + " " + FormatNumber(v.y()) + " " + FormatNumber(v.z()) + ")";
}

// The principal moments of a symmetric tensor, ascending: "(a b c)".
std::string PrincipalMoments(const Matrix3d& I) {
  return Format(
      Eigen::SelfAdjointEigenSolver<Matrix3d>(0.5 * (I + I.transpose()), Eigen::EigenvaluesOnly)
          .eigenvalues());
}

struct Units {
  const char* position;
  const char* velocity;
  const char* effort;
  const char* damping;
};

Units UnitsOf(JointType type) {
  return type == JointType::kRevolute ? Units{"rad", "rad/s", "N*m", "N*m*s/rad"}
                                      : Units{"m", "m/s", "N", "N*s/m"};
}

JointType TypeOf(const urdf::Joint& joint, const std::string& where) {
  switch (joint.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      return JointType::kRevolute;
    case urdf::Joint::PRISMATIC:
      return JointType::kPrismatic;
    case urdf::Joint::FLOATING:
    case urdf::Joint::PLANAR: {
      const std::string type = joint.type == urdf::Joint::FLOATING ? "floating" : "planar";
      throw InputError(where + ": type '" + type + "' is not supported; mbstream simulates " +
                       "fixed-base trees of revolute, continuous, prismatic and fixed joints: " +
                       "make it 'fixed' to fix the base, or build the motion from revolute " +
                       "and prismatic joints");
    }
    default:
      break;
  }
  throw InternalError(where + ": unexpected joint type " + std::to_string(joint.type));
}

Vector3d UnitAxis(const urdf::Joint& joint, const std::string& where,
                  const UrdfDiagnostics& diagnostics) {
  const Vector3d axis(joint.axis.x, joint.axis.y, joint.axis.z);
  const double norm = axis.norm();
  if (!axis.allFinite() || !(norm > 1e-12)) {
    throw InputError(where + ": axis " + Format(axis) +
                     " is zero or not finite; give the direction of motion in the joint " +
                     "frame, e.g. <axis xyz=\"0 0 1\"/>");
  }
  if (std::abs(norm - 1.0) > 1e-6) {
    diagnostics.Warn(where + ": axis " + Format(axis) + " is not a unit vector; normalised to " +
                     Format(axis / norm));
  }
  return axis / norm;
}

// A velocity or effort limit: negative is an error, 0 means "not given" (unlimited).
double RateLimit(double value, const char* what, const char* unit, const std::string& where,
                 const UrdfDiagnostics& diagnostics) {
  if (value < 0.0 && diagnostics.repair()) {
    diagnostics.Warn(where + ": repaired: " + what + " limit " + FormatNumber(value) + " " + unit +
                     " is negative; read as no limit");
    return kInfinity;
  }
  if (value < 0.0) {
    throw InputError(where + ": " + what + " limit " + FormatNumber(value) + " " + unit +
                     " is negative; give the largest " + what + " as a number > 0" + kRepairHint);
  }
  if (value == 0.0) {
    diagnostics.Warn(where + ": " + what + " limit is 0, read as no limit (taken literally " +
                     "it would forbid any motion or drive); give the real limit in " + unit);
    return kInfinity;
  }
  return value;
}

JointLimits LimitsOf(const urdf::Joint& joint, const Units& units, const std::string& where,
                     const UrdfDiagnostics& diagnostics) {
  JointLimits limits;
  if (joint.limits == nullptr) return limits;  // continuous joint without <limit>
  const urdf::JointLimits& given = *joint.limits;
  if (joint.type == urdf::Joint::CONTINUOUS) {
    if (given.lower != 0.0 || given.upper != 0.0) {
      diagnostics.Warn(where + ": position limits of a continuous joint are ignored; use " +
                       "type=\"revolute\" to enforce them");
    }
  } else {
    if (given.lower > given.upper) {
      throw InputError(where + ": lower limit " + FormatNumber(given.lower) + " " + units.position +
                       " is above upper limit " + FormatNumber(given.upper) + " " + units.position +
                       "; swap or correct them");
    }
    if (given.lower == given.upper) {
      diagnostics.Warn(
          where + ": position range is empty (lower = upper = " + FormatNumber(given.lower) + " " +
          units.position + "), so the limits " +
          "lock the joint; give lower < upper (a missing lower or upper reads " + "as 0)");
    }
    limits.lower = given.lower;
    limits.upper = given.upper;
  }
  limits.velocity = RateLimit(given.velocity, "velocity", units.velocity, where, diagnostics);
  limits.effort = RateLimit(given.effort, "effort", units.effort, where, diagnostics);
  return limits;
}

}  // namespace

Pose ToPose(const urdf::Pose& origin) {
  Pose pose;
  pose.p = Vector3d(origin.position.x, origin.position.y, origin.position.z);
  // urdfdom stores rpy as the quaternion of Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Quaterniond q(origin.rotation.w, origin.rotation.x, origin.rotation.y,
                             origin.rotation.z);
  pose.R = q.normalized().toRotationMatrix();
  return pose;
}

Joint ConvertJoint(const urdf::Joint& joint, double rotor_inertia,
                   const UrdfDiagnostics& diagnostics) {
  const std::string where = diagnostics.Joint(joint.name);
  Joint result;
  result.name = joint.name;
  result.type = TypeOf(joint, where);
  const Units units = UnitsOf(result.type);
  result.X_PJ = ToPose(joint.parent_to_joint_origin_transform);
  result.axis = UnitAxis(joint, where, diagnostics);
  result.limits = LimitsOf(joint, units, where, diagnostics);
  result.armature = rotor_inertia;
  if (joint.dynamics != nullptr) {
    if (joint.dynamics->damping < 0.0) {
      throw InputError(where + ": damping " + FormatNumber(joint.dynamics->damping) + " " +
                       units.damping + " is negative; give a value >= 0");
    }
    result.damping = joint.dynamics->damping;
    if (joint.dynamics->friction != 0.0) {
      diagnostics.Warn(where + ": friction " + FormatNumber(joint.dynamics->friction) +
                       " is ignored; mbstream models viscous damping only");
    }
  }
  return result;
}

RigidInertia ConvertInertia(const urdf::Link& link, const std::string& moving_joint,
                            const UrdfDiagnostics& diagnostics) {
  const std::string where = diagnostics.Link(link.name);
  const bool moving = !moving_joint.empty();
  const std::string moved_by = ", but joint '" + moving_joint + "' moves it";
  if (link.inertial == nullptr) {
    if (!moving) return RigidInertia{};
    throw InputError(where + ": has no <inertial>" + moved_by + "; a moving link needs a " +
                     "mass: add <inertial> with <mass value=\"...\"/> (kg, > 0) and " +
                     "<inertia .../> (kg*m^2)");
  }
  const urdf::Inertial& inertial = *link.inertial;
  const double mass = inertial.mass;
  if (moving && mass == 0.0 && diagnostics.repair()) {
    const StandInInertia stand_in = StandInForMasslessLink(link);
    diagnostics.Warn(where + ": repaired: mass 0 kg" + moved_by + "; given " +
                     FormatNumber(stand_in.mass) + " kg spread over a box of " +
                     Format(stand_in.size) + " m (its visual's, or 2 cm) at the link origin");
    return RigidInertia{stand_in.mass, Vector3d::Zero(), stand_in.inertia};
  }
  if (!std::isfinite(mass) || mass < 0.0 || (moving && mass == 0.0)) {
    throw InputError(where + ": mass is " + FormatNumber(mass) + " kg" +
                     (moving ? moved_by + "; a moving link needs a positive mass"
                             : std::string("; a mass cannot be negative")) +
                     ": give <mass value=\"...\"/> > 0 (kg)" +
                     (moving && mass == 0.0 ? kRepairHint : ""));
  }
  Matrix3d I;
  I << inertial.ixx, inertial.ixy, inertial.ixz,  //
      inertial.ixy, inertial.iyy, inertial.iyz,   //
      inertial.ixz, inertial.iyz, inertial.izz;
  if (mass == 0.0) {
    if (!I.isZero()) {
      diagnostics.Warn(where + ": has an inertia tensor but zero mass; the inertia is ignored");
    }
    return RigidInertia{};
  }
  if (mass < 1e-6) {
    diagnostics.Warn(where + ": mass " + FormatNumber(mass) + " kg is below 1e-6 kg; check " +
                     "the value and its unit (kg)");
  }
  const Pose X_LC = ToPose(inertial.origin);  // the inertial frame C in the link frame L
  Matrix3d I_L = X_LC.R * I * X_LC.R.transpose();
  if (I_L.allFinite()) {
    if (const std::optional<Matrix3d> nearest = NearestPhysicalInertia(I_L, mass)) {
      if (diagnostics.repair()) {
        diagnostics.Warn(where + ": repaired: inertia principal moments " + PrincipalMoments(I_L) +
                         " kg*m^2 moved to the nearest physical tensor, " +
                         PrincipalMoments(*nearest) + " kg*m^2 (same principal axes)");
        I_L = *nearest;
      } else {
        try {
          ValidateRigidInertia(RigidInertia{mass, X_LC.p, 0.5 * (I_L + I_L.transpose())}, where);
        } catch (const InputError& error) {
          throw InputError(error.what() + std::string(kRepairHint));
        }
      }
    }
  }
  const RigidInertia result{mass, X_LC.p, 0.5 * (I_L + I_L.transpose())};
  ValidateRigidInertia(result, where);
  return result;
}

}  // namespace mbstream
