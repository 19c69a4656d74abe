// A scene from an SDFormat file's visuals (a model, or a world of several) (box, cylinder, sphere,
// mesh files) with their materials and poses, for `mbstream-viewer --model FILE.sdf` and for a run
// of an SDFormat model the server sends. Read through shared/model_files/sdf_reading.h, the reading
// the server's importer shares: the same spanning tree (its joints are the chain's, in the server's
// order; the cut joints close loops the server solves and are not drawn as joints), the
// same link frames, the same mesh lookup. The viewer links no server code.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "shared/model_files/sdf_includes.h"
#include "viewer/model/mesh_finder.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

// Throws InputError "FILE[:LINE]: what is wrong; what to do" for input the server's importer
// refuses too (model_files::SdfFile, ChooseSdfTree). Colours: the <material>'s diffuse,
// else its ambient, else the mesh file's own, else grey. A mesh `find_mesh` does not find is
// drawn as a tinted placeholder cube (with a warning). A link named tcp or tool0 (any
// case) gets a probe "tcp" reported in the world frame, as the server's TCP.
// `includes`: where an <include> is found (the viewer's --model); none: an <include> is
// refused (a bundle from the server holds none). A world's models are named as the server
// names them (MODEL::NAME, docs/worlds.md); a free body's chain joint takes its seven values
// (position, unit quaternion), a static model's links are fixed where they stand.
SceneDescription SceneFromSdf(const std::string& text, const std::string& source,
                              const MeshFinder& find_mesh,
                              const std::optional<model_files::SdfIncludePath>& includes = {});

}  // namespace mbstream::viewer
