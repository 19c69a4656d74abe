// Where the viewer finds the file of a model's mesh reference (a URDF <mesh filename> or an
// SDFormat <mesh><uri>): in a bundle the server sent, as the server stored it
// (model_files::FindMeshFile), or on the user's disk for the local mode exactly as
// `mbstream submit` finds it (model_files::MeshFileSearch: relative paths, the package path,
// package://PKG/REST under each of the model file's ancestors).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mbstream::viewer {

// The file for `filename` as written in the model, or an empty path when there is none.
using MeshFinder = std::function<std::filesystem::path(const std::string& filename)>;

// Meshes of a bundle written below `directory`.
MeshFinder BundleMeshFinder(const std::filesystem::path& directory);

// Meshes on disk for a model file in `model_directory`, with `package_path` (the
// --package-path folders; $MBSTREAM_PACKAGE_PATH is added after them).
MeshFinder DiskMeshFinder(const std::filesystem::path& model_directory,
                          const std::vector<std::string>& package_path);

}  // namespace mbstream::viewer
