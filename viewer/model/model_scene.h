// A scene from a model file, URDF or SDFormat, told apart by its content as the server tells
// them (shared/model_files/model_format.h): `mbstream-viewer --model FILE` and the model a run's
// bundle carries.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "viewer/model/mesh_finder.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

// SceneFromUrdf or SceneFromSdf of `text` (a bundle's: an <include> is refused);
// `source` names it in messages; `floating_base`: a URDF's root moves freely.
SceneDescription SceneFromModelText(const std::string& text, const std::string& source,
                                    const MeshFinder& find_mesh, bool floating_base = false);

// Reads the file at `path`; its meshes (and an SDFormat world's <include>s) are found on disk
// as `mbstream submit` finds them (DiskMeshFinder with `package_path`). Throws InputError
// for an unreadable file.
SceneDescription SceneFromModelFile(const std::filesystem::path& path,
                                    const std::vector<std::string>& package_path = {},
                                    bool floating_base = false);

}  // namespace mbstream::viewer
