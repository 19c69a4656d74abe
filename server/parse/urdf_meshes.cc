#include "server/parse/urdf_meshes.h"

#include <memory>
#include <system_error>

#include "common/check.h"
#include "server/parse/asset_references.h"
#include "urdf_reading/mesh_lookup.h"

namespace mbstream {

namespace {

std::string BaseName(const std::string& filename) {
  const size_t slash = filename.find_last_of('/');
  return slash == std::string::npos ? filename : filename.substr(slash + 1);
}

}  // namespace

bool MeshSupplied(const std::string& filename, const std::set<std::string>& assets) {
  return AnySupplied(UrdfMeshAssetNames(filename), assets);
}

void CheckMeshes(const urdf::Link& link, const std::set<std::string>& assets,
                 const UrdfDiagnostics& diagnostics, int* missing_collision) {
  const auto check = [&](const urdf::GeometrySharedPtr& geometry, const char* part) {
    const auto mesh = std::dynamic_pointer_cast<const urdf::Mesh>(geometry);
    if (mesh == nullptr) return;
    if (!MeshSupplied(mesh->filename, assets)) {
      if (std::string(part) == "collision") {
        ++*missing_collision;
        return;
      }
      diagnostics.Warn(diagnostics.Link(link.name) + ": " + part + " mesh '" + mesh->filename +
                       "' is not supplied; the physics does not need it and viewers draw a " +
                       "placeholder box (mbstream submit attaches the meshes it finds; pass " +
                       "--package-path DIR or --asset " + BaseName(mesh->filename) + ")");
      return;
    }
    const urdf::Vector3& s = mesh->scale;
    if (s.x != 1.0 || s.y != 1.0 || s.z != 1.0) {
      diagnostics.Warn(diagnostics.Link(link.name) + ": " + part + " mesh '" + mesh->filename +
                       "' is scaled by (" + FormatNumber(s.x) + " " + FormatNumber(s.y) + " " +
                       FormatNumber(s.z) + "); the server ignores mesh geometry, so make " +
                       "sure the viewer's scene draws it at that scale");
    }
  };
  for (const urdf::VisualSharedPtr& visual : link.visual_array) {
    if (visual != nullptr) check(visual->geometry, "visual");
  }
  for (const urdf::CollisionSharedPtr& collision : link.collision_array) {
    if (collision != nullptr) check(collision->geometry, "collision");
  }
}

std::set<std::string> ExistingMeshFiles(const std::vector<std::string>& mesh_files,
                                        const std::filesystem::path& directory) {
  std::set<std::string> found;
  for (const std::string& filename : mesh_files) {
    if (!urdf_reading::FindMeshFile(filename, directory).empty()) found.insert(filename);
  }
  return found;
}

}  // namespace mbstream
