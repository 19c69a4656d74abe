// Content-addressed model ids.
#pragma once

#include <string>

#include "mbstream/v1/model.pb.h"

namespace mbstream {

// "m-" + the first 24 hex digits of SHA-256 over the bundle's URDF, scene script and assets
// (sorted by name; each field length-prefixed). The display name is not part of the id, so
// the same bundle submitted twice, under any name, gets the same id.
std::string ModelContentId(const v1::ModelBundle& bundle);

}  // namespace mbstream
