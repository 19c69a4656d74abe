#include "server/parse/urdf_meshes.h"

#include <memory>
#include <system_error>

#include "server/parse/asset_references.h"
#include "shared/common/check.h"
#include "shared/model_files/mesh_file_search.h"

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
                 const UrdfDiagnostics& diagnostics, MissingMeshes* missing) {
  const auto check = [&](const urdf::GeometrySharedPtr& geometry, const char* part) {
    const auto mesh = std::dynamic_pointer_cast<const urdf::Mesh>(geometry);
    if (mesh == nullptr) return;
    if (!MeshSupplied(mesh->filename, assets)) {
      if (std::string(part) == "collision") {
        ++missing->collision;
        return;
      }
      if (missing->visual.empty()) missing->first_file = mesh->filename;
      missing->visual.push_back(diagnostics.Link(link.name) + ": " + part + " mesh '" +
                                mesh->filename + "'");
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

void WarnMissingMeshes(const MissingMeshes& missing, const UrdfDiagnostics& diagnostics) {
  const bool one = missing.visual.size() == 1;
  const std::string advice =
      std::string(one ? "; the physics does not need it and viewers draw a placeholder box"
                      : "; the physics does not need them and viewers draw placeholder boxes") +
      " (mbstream submit attaches the meshes it finds; pass --package-path DIR or --asset " +
      BaseName(missing.first_file) + ")";
  if (one) {
    diagnostics.Warn(missing.visual.front() + " is not supplied" + advice);
  } else if (!missing.visual.empty()) {
    std::string first;
    for (size_t i = 0; i < missing.visual.size() && i < 3; ++i) {
      first += (i == 0 ? "" : "; ") + missing.visual[i];
    }
    diagnostics.Warn(diagnostics.source() + ": " + std::to_string(missing.visual.size()) +
                     " visual meshes are not supplied (" + first +
                     (missing.visual.size() > 3 ? "; ..." : "") + ")" + advice);
  }
  if (missing.collision > 0) {
    diagnostics.Warn(diagnostics.source() + ": " + std::to_string(missing.collision) +
                     " collision mesh(es) not supplied; those collisions touch nothing "
                     "(mbstream submit --with-collision attaches them)");
  }
}

std::set<std::string> ExistingMeshFiles(const std::vector<std::string>& mesh_files,
                                        const std::filesystem::path& directory) {
  const model_files::MeshFileSearch search(directory, model_files::PackagePath({}));
  std::set<std::string> found;
  for (const std::string& filename : mesh_files) {
    if (!search.Find(filename).found.empty()) found.insert(filename);
  }
  return found;
}

}  // namespace mbstream
