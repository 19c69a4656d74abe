// The run spec's `initial_bodies` (proto/mbstream/v1/run_spec.proto BodyState,
// docs/free_bodies.md) to the physics core's InitialBodyState and back. Each name must be a
// free body's, as the model's position names show it (NAME.x ... NAME.qz), given once; every
// value finite; a quaternion unit within 1e-6; an rpy becomes its quaternion.
#pragma once

#include <string>
#include <vector>

#include "google/protobuf/repeated_ptr_field.h"
#include "mbstream/v1/run_spec.pb.h"
#include "server/sim/initial_bodies.h"

namespace mbstream {

// The free bodies' names among `position_names` (a model's PositionNames): each NAME whose
// seven coordinates NAME.x .y .z .qw .qx .qy .qz follow one another, in the model's order.
std::vector<std::string> FreeBodyNames(const std::vector<std::string>& position_names);

// Throws InputError "<source>: initial_bodies[K].FIELD: <problem>; <what to do>".
std::vector<InitialBodyState> ToInitialBodies(
    const google::protobuf::RepeatedPtrField<v1::BodyState>& spec,
    const std::vector<std::string>& position_names, const std::string& source);

// Each part as the config holds it (absent parts stay absent), the orientation as a quaternion.
void ToBodyStateSpecs(const std::vector<InitialBodyState>& bodies,
                      google::protobuf::RepeatedPtrField<v1::BodyState>* spec);

}  // namespace mbstream
