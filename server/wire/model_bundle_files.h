// Model bundles from files: what `mbstream submit` sends and what the server loads from its
// built-in models directory.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"

namespace mbstream {

// Reads a bundle. `model_path` is a URDF file, or a directory holding exactly one *.urdf
// (then its *.scene file, if exactly one, is the scene script, and every *.stl below it is
// an asset named by its path relative to the directory). `scene_path` (may be empty)
// overrides the scene; each of `asset_paths` is added under its file name. Throws InputError
// naming the path when a file cannot be read or a directory is ambiguous.
v1::ModelBundle ReadModelBundle(const std::string& model_path, const std::string& scene_path,
                                const std::vector<std::string>& asset_paths,
                                const std::string& name);

}  // namespace mbstream
