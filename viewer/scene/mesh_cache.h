// Mesh files read once per content: two parts (or two scenes, run after run) that draw the
// same bytes share one MeshFileContents. Thread-safe.
#pragma once

#include <filesystem>
#include <memory>

#include "viewer/scene/mesh_file_reader.h"

namespace mbstream::viewer {

// The contents of `path`, read with `options` unless a file with the same bytes (and, for
// formats that read side files such as OBJ's .mtl or glTF's .bin, in the same folder) was
// read with the same options before. Throws SceneError as ReadMeshFile.
std::shared_ptr<const MeshFileContents> CachedMeshFile(const std::filesystem::path& path,
                                                       const MeshReadOptions& options);

// Entries in the cache and files actually read since the start: for tests and logs.
struct MeshCacheStats {
  int entries = 0;
  long long reads = 0;
};
MeshCacheStats MeshCacheStatistics();

}  // namespace mbstream::viewer
