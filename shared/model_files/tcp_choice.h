// The link whose origin is a model's TCP (tool centre point).
#pragma once

#include <string>
#include <vector>

#include <urdf_model/model.h>

#include "shared/model_files/joint_order.h"

namespace mbstream::model_files {

// The first link (in `link_order`, document order) named "tcp" in any case; else the link
// "tool0"; else the first leaf link (in joint order) on a fixed joint of the last moving
// body (the link the last moving joint moves, with everything fixed to it); "" when there
// is none.
std::string ChooseTcpLink(const urdf::ModelInterface& model, const JointOrder& order,
                          const std::vector<std::string>& link_order);

// The last moving link of `order` ("" when nothing moves): for messages.
std::string LastMovingLink(const JointOrder& order);

}  // namespace mbstream::model_files
