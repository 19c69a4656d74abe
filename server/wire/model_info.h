// A compiled model's description on the wire (ModelInfo), from the core's Model.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"
#include "server/model/model.h"

namespace mbstream {

// Fills dofs, positions and the coordinates' names (coordinate_names.h), joints (unlimited
// ranges as 0: the wire carries no infinities), TCP, links, mass and the sizes of the
// formulations. Leaves id, name, bundle-derived and time fields.
void DescribeModel(const Model& model, const std::vector<std::string>& warnings,
                   v1::ModelInfo* info);

// The model's joint names in its joint order (the order of q on the wire): VelocityNames, one
// per velocity coordinate (the order of qd; of q too without free bodies).
std::vector<std::string> JointNames(const Model& model);

}  // namespace mbstream
