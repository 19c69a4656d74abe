// A scene from a URDF's visual elements (box, cylinder, sphere, mesh files), for robots that
// come without a scene script. Parsed with urdfdom through shared/model_files, the reading the
// server's importer shares: the same joint order (the degree-of-freedom order), the same TCP
// link and the same mesh lookup. The viewer links no server code.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "viewer/model/mesh_finder.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

// Throws InputError "FILE: what is wrong; what to do" on bad input: unreadable
// file, XML/URDF urdfdom rejects, planar joints, a floating joint whose parent is not the
// root link (the world), a zero axis, joints that form a loop. A floating joint from the
// root is a free joint of seven values (x y z qw qx qy qz: the child's pose in the root, as
// the server's); `floating_base` (the bundle's, --floating-base) frees the root link itself:
// frame 0 is then "world" and a free joint named after the root moves it. A mesh is looked up by
// `find_mesh` (mesh_finder.h): a file on disk as `mbstream submit` finds it (SceneFromUrdfFile,
// with the --package-path folders `package_path`), a bundle's file below `asset_directory` as the
// server stored it; a mesh that is not found becomes a tinted placeholder box of the link's inertia
// size (with a warning in SceneDescription::warnings). Colours: a URDF <material> colour (inline or
// by name) wins; else the mesh file's own material colours; else grey. The TCP link
// (model_files::ChooseTcpLink) gets a probe "tcp" reported in the base link's frame.
SceneDescription SceneFromUrdfFile(const std::filesystem::path& path,
                                   const std::vector<std::string>& package_path = {});
SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const std::filesystem::path& asset_directory);
SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const MeshFinder& find_mesh, bool floating_base = false);

}  // namespace mbstream::viewer
