// Mesh files read once per content: two parts (or two scenes, run after run) that draw the
// same bytes share one MeshFileContents. Thread-safe.
#pragma once

#include <filesystem>
#include <memory>

#include "viewer/scene/mesh_file_reader.h"

namespace mbstream::viewer {

// The contents of `path`, decimated to at most about `max_triangles` (0 = as read), unless
// a file with the same bytes (and, for formats that read side files such as OBJ's .mtl,
// glTF's .bin or a Collada's texture images, in the same folder) was read (and decimated to the
// same size) before. Throws SceneError as ReadMeshFile.
std::shared_ptr<const MeshFileContents> CachedMeshFile(const std::filesystem::path& path,
                                                       long long max_triangles = 0);

// Entries in the cache and files actually read since the start: for tests and logs.
struct MeshCacheStats {
  int entries = 0;
  long long reads = 0;
};
MeshCacheStats MeshCacheStatistics();

// Forgets every entry (parts that hold one keep it): for benchmarks that time reading.
void ClearMeshCache();

}  // namespace mbstream::viewer
