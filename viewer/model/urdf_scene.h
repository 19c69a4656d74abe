// A scene from a URDF's visual elements (box, cylinder, sphere, STL mesh), for robots that
// come without a scene script. Parsed with urdfdom directly (the viewer links no server
// code). Joint values follow the URDF's joint order (document order, a joint after the
// joint that places its parent link), the server's degree-of-freedom order.
#pragma once

#include <filesystem>
#include <string>

#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

// Throws std::runtime_error "FILE: what is wrong; what to do" on bad input: unreadable
// file, XML/URDF urdfdom rejects, floating/planar joints, a mesh that is not STL or is not
// found (looked up relative to the URDF's directory, package:// and file:// stripped).
// A link named "tcp" or "tool0" gets a probe "tcp" reported in the base link's frame.
SceneDescription SceneFromUrdfFile(const std::filesystem::path& path);
SceneDescription SceneFromUrdf(const std::string& text, const std::string& source,
                               const std::filesystem::path& asset_directory);

}  // namespace mbstream::viewer
