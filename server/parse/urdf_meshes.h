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
// UrdfMeshAssetNames gives (asset_references.h: model_files::MeshAssetKeys, the names the
// viewer looks the mesh up by too).
bool MeshSupplied(const std::string& filename, const std::set<std::string>& assets);

// The meshes of a model that are not supplied: the physics never reads a mesh, so they are
// said once per model (WarnMissingMeshes), not once per mesh (a humanoid has 90).
struct MissingMeshes {
  std::vector<std::string> visual;  // "link 'NAME' (line N): FILE" of each missing visual mesh
  std::string first_file;           // the first missing visual mesh's file, for the advice
  int collision = 0;                // collision meshes are only attached on request
};

// Warns, naming the link and the file, about scaled meshes of `link`; notes its meshes that
// are not supplied in `*missing`.
void CheckMeshes(const urdf::Link& link, const std::set<std::string>& assets,
                 const UrdfDiagnostics& diagnostics, MissingMeshes* missing);

// One warning for the missing visual meshes (each named when there is one, the count and the
// first three otherwise) and one for the missing collision meshes.
void WarnMissingMeshes(const MissingMeshes& missing, const UrdfDiagnostics& diagnostics);

// The files among `mesh_files` (as written in the URDF) that exist for a URDF in
// `directory`, looked up as `mbstream submit` and the viewer's --model look them up
// (model_files::MeshFileSearch, with $MBSTREAM_PACKAGE_PATH).
std::set<std::string> ExistingMeshFiles(const std::vector<std::string>& mesh_files,
                                        const std::filesystem::path& directory);

}  // namespace mbstream
