// The surface of each primitive part of a scene script, in the part's frame (mm).
#pragma once

#include "viewer/model/mesh.h"
#include "viewer/script/commands.h"

namespace mbstream::viewer {

Mesh CylinderMesh(const scene_script::CylinderShape& cylinder);
Mesh ConeMesh(const scene_script::ConeShape& cone);
Mesh CubeMesh(const scene_script::CubeShape& cube);
Mesh SphereMesh(const scene_script::SphereShape& sphere);
// Needs an outline that translated without errors.
Mesh PolyprismMesh(const scene_script::PolyprismShape& prism);
// Faces as written (their orientation may be mixed; the VTK scene makes it consistent).
Mesh ModuleMesh(const scene_script::ModuleShape& module);

}  // namespace mbstream::viewer
