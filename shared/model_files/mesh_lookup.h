// Where a URDF <mesh filename="..."> is looked for, the same way by the server (is the
// mesh among a bundle's assets, does it exist beside the URDF) and by the viewer (which
// file of the bundle it draws).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mbstream::model_files {

// `filename` without its package://, model:// (SDFormat's) or file:// prefix.
std::string WithoutScheme(const std::string& filename);

// The name under which `mbstream submit` stores the file of `filename`: the path the URDF
// writes, without its scheme, lexically normalised, as a relative path inside the bundle
// (a leading '/' and leading '..' steps dropped): "package://demo/meshes/a.stl" ->
// "demo/meshes/a.stl", "../meshes/visual/a.stl" -> "meshes/visual/a.stl". Empty for an
// empty filename.
std::string BundleAssetName(const std::string& filename);

// The asset names that supply `filename`, best first, without repeats: as written; without
// its scheme; BundleAssetName; for package://PKG/REST also REST; the base name.
std::vector<std::string> MeshAssetKeys(const std::string& filename);

// The files that may hold `filename` for a URDF in `directory`, best first: an absolute
// path as written (file:///abs); each relative key of MeshAssetKeys in `directory`; for
// package://PKG/REST also REST in `directory`'s parent (a URDF in PKG/urdf/).
std::vector<std::filesystem::path> MeshFileCandidates(const std::string& filename,
                                                      const std::filesystem::path& directory);

// The first candidate that is a regular file, or an empty path.
std::filesystem::path FindMeshFile(const std::string& filename,
                                   const std::filesystem::path& directory);

}  // namespace mbstream::model_files
