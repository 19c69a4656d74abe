// The collision meshes of a submitted model bundle, for the import (server/parse/mesh_source.h):
// each mesh a model names found among the bundle's assets as the viewer finds it.
#pragma once

#include "mbstream/v1/model.pb.h"
#include "server/parse/mesh_source.h"

namespace mbstream {

// Looks `bundle`'s assets up by name; keeps a reference to `bundle`, which must outlive it.
MeshSource BundleMeshSource(const v1::ModelBundle& bundle);

}  // namespace mbstream
