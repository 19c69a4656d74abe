// Where the import finds the bytes of the collision meshes a model names: the files of a
// submitted bundle (server/wire/bundle_mesh_source.h), or the user's disk for a model read
// from a file (`mbstream simulate`, the tests). The visual meshes are never read.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mbstream {

// The bytes of the mesh `filename` (a URDF <mesh filename> or an SDFormat <mesh><uri>, as
// written), or nullopt when it is not supplied. Empty: no mesh is supplied.
using MeshSource = std::function<std::optional<std::string>(const std::string& filename)>;

// The file found as `mbstream submit` finds it (model_files::MeshFileSearch from `directory`,
// the model file's folder, with `package_path` and $MBSTREAM_PACKAGE_PATH), read whole.
MeshSource DiskMeshSource(const std::filesystem::path& directory,
                          const std::vector<std::string>& package_path = {});

// The first asset that supplies `filename` (model_files::MeshAssetKeys, the names the viewer
// looks it up by): `asset(name)` gives an asset's bytes or null.
MeshSource AssetMeshSource(std::function<const std::string*(const std::string& name)> asset);

}  // namespace mbstream
