// Converting urdfdom's joints and inertials to mbstream's types, with the checks and
// warnings that belong to each element.
//
// Errors (InputError): a floating or planar joint; a zero or non-finite axis; a lower
// limit above the upper; a negative effort limit, velocity limit or damping; a moving link
// without <inertial> or with a mass <= 0; a negative mass; an inertia tensor that is not
// positive definite or breaks the triangle inequality.
// Warnings: a non-unit axis (normalised); an empty position range (lower = upper); a
// zero effort or velocity limit (read as no limit); position limits on a continuous joint,
// friction (both ignored); a mass below 1e-6 kg; an inertia on a zero mass. (<mimic>:
// urdf_mimic.h.)
#pragma once

#include <string>

#include <urdf_model/joint.h>
#include <urdf_model/link.h>

#include "server/math/rigid_inertia.h"
#include "server/model/joint.h"
#include "server/parse/urdf_diagnostics.h"

namespace mbstream {

// A URDF <origin> (xyz in m, rpy as R = Rz(yaw) Ry(pitch) Rx(roll)) as a Pose.
Pose ToPose(const urdf::Pose& origin);

// The mbstream joint for a revolute, continuous or prismatic URDF joint: X_PJ from its
// origin, unit axis, limits (continuous: no position limits), damping, and
// `rotor_inertia` (kg*m^2 or kg) as armature.
Joint ConvertJoint(const urdf::Joint& joint, double rotor_inertia,
                   const UrdfDiagnostics& diagnostics);

// The inertia of `link` in the link frame (com in m, inertia about the com in kg*m^2).
// `moving_joint` names the joint that moves the link: then a positive mass is required.
// Empty for a link on a fixed joint, which may have no <inertial> (zero mass).
RigidInertia ConvertInertia(const urdf::Link& link, const std::string& moving_joint,
                            const UrdfDiagnostics& diagnostics);

}  // namespace mbstream
