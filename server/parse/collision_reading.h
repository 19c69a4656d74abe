// The <collision> shapes of a model file, URDF or SDFormat, into Model::collisions
// (server/model/collision_geometry.h): sphere, box, cylinder, capsule (SDFormat) and plane
// (SDFormat); a mesh is skipped with a warning naming its file (its convex hull is not
// computed yet), as any other shape. Surface parameters: drake:point_contact_stiffness,
// drake:hunt_crossley_dissipation, drake:mu_static and drake:mu_dynamic inside
// <drake:proximity_properties>; SDFormat <surface><friction><ode><mu> (the dynamic
// coefficient, and the static one unless drake:mu_static gives it) and
// <surface><contact><collide_bitmask>. A negative or non-finite value, or a shape of
// non-positive size, is an InputError "FILE:LINE: link 'L': collision 'C': what; what to do".
#pragma once

#include <map>
#include <string>
#include <vector>

#include "server/model/model.h"
#include "shared/model_files/sdf_reading.h"

namespace mbstream {

// Appends the collisions of every link of `file` to model->collisions. `link_frames` is each
// link's frame in the Model, in the world, at the default pose (the import's F_L), by
// scoped name; the model must have every link as a frame.
void ReadSdfCollisions(const model_files::SdfFile& file,
                       const std::map<std::string, Pose>& link_frames, Model* model,
                       std::vector<std::string>* warnings);

// Appends the collisions of every <link> of URDF `text` (`source` names it) to
// model->collisions; the model must have every link as a frame (the link frame of a URDF is
// the frame the Model keeps). URDF has no capsule or plane (urdfdom refuses them).
void ReadUrdfCollisions(const std::string& text, const std::string& source, Model* model,
                        std::vector<std::string>* warnings);

}  // namespace mbstream
