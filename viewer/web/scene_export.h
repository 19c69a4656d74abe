// The viewer's scene as the browser page draws it: the geometry the VTK pipeline built (every
// part actor's triangles, already in its frame's axes, and its colour), the probes (a point
// in a frame, reported in another), the camera as the VTK viewer placed it, and the ghost's
// opacity. One JSON text per scene, sent once per model to every page; the poses follow as frame
// messages (frame_message.h).
#pragma once

#include <cstdint>
#include <string>

#include "viewer/scene/scene.h"

namespace mbstream::viewer {

// Render thread (reads the scene's VTK pipelines). `version` numbers the scene; frame
// messages name it. Meshes are little-endian float32 positions and uint32 indices, base64;
// a textured part adds float32 "uvs" (two per position) and its image as "texture_png".
// "missing_meshes" is the scene's HUD line naming meshes drawn as placeholders ("" if none).
std::string ExportSceneJson(Scene& scene, std::uint64_t version);

// Standard base64 (RFC 4648, with padding) of `size` bytes.
std::string Base64(const void* data, std::size_t size);

}  // namespace mbstream::viewer
