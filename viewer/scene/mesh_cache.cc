#include "viewer/scene/mesh_cache.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <tuple>

#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

namespace {

// Entries that only the cache holds are dropped beyond this many.
constexpr size_t kMaxIdleEntries = 64;

using Key = std::tuple<std::uint64_t, std::uint64_t, std::string, std::string, long long>;

struct Cache {
  std::mutex mutex;
  std::map<Key, std::shared_ptr<const MeshFileContents>> entries;
  long long reads = 0;
};

Cache& TheCache() {
  static Cache cache;
  return cache;
}

// FNV-1a, 64 bits.
std::uint64_t Hash(const std::string& bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

std::string LowerExtension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void DropIdleEntries(Cache& cache) {
  size_t idle = 0;
  for (const auto& [key, contents] : cache.entries) idle += contents.use_count() == 1 ? 1 : 0;
  for (auto it = cache.entries.begin(); it != cache.entries.end() && idle > kMaxIdleEntries;) {
    if (it->second.use_count() == 1) {
      it = cache.entries.erase(it);
      --idle;
    } else {
      ++it;
    }
  }
}

}  // namespace

std::shared_ptr<const MeshFileContents> CachedMeshFile(const std::filesystem::path& path,
                                                       long long max_triangles) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path.string() + ": cannot open the mesh file; check the path");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string extension = LowerExtension(path);
  // Side files (OBJ's .mtl, glTF's .bin, texture images of OBJ and Collada) are read from
  // the folder: the same bytes in another folder may draw differently.
  const bool side_files = extension == ".obj" || extension == ".gltf" || extension == ".dae";
  const Key key{Hash(bytes), bytes.size(), extension,
                side_files ? path.parent_path().lexically_normal().string() : std::string(), 0};
  Cache& cache = TheCache();
  std::shared_ptr<const MeshFileContents> raw;
  Key decimated_key = key;
  std::get<4>(decimated_key) = max_triangles;
  {
    const std::lock_guard<std::mutex> lock(cache.mutex);
    if (const auto it = cache.entries.find(decimated_key); it != cache.entries.end()) {
      return it->second;
    }
    if (const auto it = cache.entries.find(key); it != cache.entries.end()) raw = it->second;
  }
  if (!raw) {
    raw = std::make_shared<const MeshFileContents>(ReadMeshFile(path));
    const std::lock_guard<std::mutex> lock(cache.mutex);
    ++cache.reads;
    raw = cache.entries.emplace(key, raw).first->second;
  }
  if (max_triangles <= 0 || raw->triangle_count <= max_triangles) return raw;
  auto decimated = std::make_shared<const MeshFileContents>(Decimate(*raw, max_triangles));
  const std::lock_guard<std::mutex> lock(cache.mutex);
  const auto [it, inserted] = cache.entries.emplace(decimated_key, decimated);
  DropIdleEntries(cache);
  return it->second;
}

void ClearMeshCache() {
  Cache& cache = TheCache();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  cache.entries.clear();
}

MeshCacheStats MeshCacheStatistics() {
  Cache& cache = TheCache();
  const std::lock_guard<std::mutex> lock(cache.mutex);
  return {static_cast<int>(cache.entries.size()), cache.reads};
}

}  // namespace mbstream::viewer
