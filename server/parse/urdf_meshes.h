// Mesh files referenced by a URDF: are they supplied, and where are they on disk.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <urdf_model/link.h>

#include "server/parse/urdf_diagnostics.h"

namespace mbstream {

// True if `filename` (a URDF <mesh filename>) is in `assets` under one of the names
// UrdfMeshAssetNames gives (asset_references.h: urdf_reading::MeshAssetKeys, the names the
// viewer looks the mesh up by too).
bool MeshSupplied(const std::string& filename, const std::set<std::string>& assets);

// Warns, naming the link and the file, about a visual mesh of `link` that is not supplied
// (the physics never reads a mesh; viewers draw a placeholder) and about scaled meshes;
// counts the collision meshes that are not supplied in `*missing_collision` (the caller
// warns once: they are only attached on request).
void CheckMeshes(const urdf::Link& link, const std::set<std::string>& assets,
                 const UrdfDiagnostics& diagnostics, int* missing_collision);

// The files among `mesh_files` (as written in the URDF) that exist relative to
// `directory`, looked up as urdf_reading::FindMeshFile does (the viewer's lookup too).
std::set<std::string> ExistingMeshFiles(const std::vector<std::string>& mesh_files,
                                        const std::filesystem::path& directory);

}  // namespace mbstream
