// The <collision> shapes of a model file, URDF or SDFormat, into Model::collisions
// (server/model/collision_geometry.h): sphere, box, cylinder, capsule (SDFormat) and plane
// (SDFormat), and meshes (URDF <mesh filename scale>, SDFormat <mesh><uri><scale>) as convex
// pieces (collision_meshes.h: one geometry per piece, each its hull; a piece that is not
// convex is a warning naming the file: its hull is used). A mesh `meshes` does not supply is
// skipped (one warning for all); a mesh that cannot be read, or without volume, is an
// InputError naming the file and the <collision>. Other shapes are skipped with a warning.
// Surface parameters: drake:point_contact_stiffness,
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
#include "server/parse/mesh_source.h"
#include "shared/model_files/sdf_reading.h"

namespace mbstream {

// Appends the collisions of every link of `file` to model->collisions. `link_frames` is each
// link's frame in the Model, in the world, at the default pose (the import's F_L), by
// scoped name; the model must have every link as a frame.
void ReadSdfCollisions(const model_files::SdfFile& file,
                       const std::map<std::string, Pose>& link_frames, const MeshSource& meshes,
                       Model* model, std::vector<std::string>* warnings);

// Appends the collisions of every <link> of URDF `text` (`source` names it) to
// model->collisions; the model must have every link as a frame (the link frame of a URDF is
// the frame the Model keeps). URDF has no capsule or plane (urdfdom refuses them).
void ReadUrdfCollisions(const std::string& text, const std::string& source,
                        const MeshSource& meshes, Model* model, std::vector<std::string>* warnings);

}  // namespace mbstream
