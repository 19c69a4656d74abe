// The names of a model's coordinates, as results files, the wire and run specs show them: a
// one-coordinate joint by its name; a free joint NAME (model.h) by NAME.x .y .z .qw .qx .qy .qz
// (positions) and NAME.vx .vy .vz .wx .wy .wz (velocities and forces), a ball joint NAME by
// NAME.qw .qx .qy .qz and NAME.wx .wy .wz, MuJoCo's order.
#pragma once

#include <string>
#include <vector>

#include "server/model/model.h"

namespace mbstream {

// The suffixes of a free joint's coordinates.
inline constexpr const char* kFreePositionSuffixes[kFreeNq] = {".x",  ".y",  ".z", ".qw",
                                                               ".qx", ".qy", ".qz"};
inline constexpr const char* kFreeVelocitySuffixes[kFreeNv] = {".vx", ".vy", ".vz",
                                                               ".wx", ".wy", ".wz"};
// The suffixes of a ball joint's coordinates.
inline constexpr const char* kBallPositionSuffixes[kBallNq] = {".qw", ".qx", ".qy", ".qz"};
inline constexpr const char* kBallVelocitySuffixes[kBallNv] = {".wx", ".wy", ".wz"};

// model.nq() names, in q's order.
std::vector<std::string> PositionNames(const Model& model);

// model.nv() names, in qd's (and tau's) order: one per body without quaternions.
std::vector<std::string> VelocityNames(const Model& model);

}  // namespace mbstream
