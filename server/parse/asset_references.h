// Which of a model bundle's assets a reference means: a URDF <mesh filename> or a scene
// script's `Part NAME`. The one place where asset names are matched to references (the
// server's mesh check and its refusal of unreferenced assets both use it; package://
// resolution belongs here).
#pragma once

#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace mbstream {

// The asset names a URDF mesh `filename` may be supplied under, best first: as written,
// without its package:// or file:// prefix, for package://PKG/REST also REST, and its base
// name (model_files::MeshAssetKeys, which the viewer's lookup uses too).
std::vector<std::string> UrdfMeshAssetNames(const std::string& filename);

// The asset names a scene script's `Part NAME` may be supplied under, as the viewer looks
// them up: NAME.stl, NAME.STL and NAME.
std::vector<std::string> ScenePartAssetNames(const std::string& name);

// The file names of the `Part NAME;` commands of a scene script (keyword in any case;
// `!` line comments and `$ ... $` comment blocks skipped), as the viewer's lexer reads them.
// Generous: any word after a word `Part` counts.
std::vector<std::string> ScenePartNames(std::string_view scene_script);

// True if one of `names` (from the two functions above) is in `assets`.
bool AnySupplied(const std::vector<std::string>& names, const std::set<std::string>& assets);

// The names among `asset_names` that no mesh of `urdf_mesh_files` and no Part of
// `scene_script` refers to, in the order given. When a mesh of `urdf_mesh_files` is of a
// format that names other files (an OBJ its .mtl and their images, a Collada or glTF its
// images and buffers: mesh_dependencies.h), the materials, images and buffers of the bundle
// count as referenced: `mbstream submit` attaches the ones its meshes name (the check is by
// name, the server does not read the meshes here), so an unrelated file is still dropped.
std::vector<std::string> UnreferencedAssets(const std::vector<std::string>& asset_names,
                                            const std::vector<std::string>& urdf_mesh_files,
                                            std::string_view scene_script);

}  // namespace mbstream
