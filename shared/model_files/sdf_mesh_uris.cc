#include "shared/model_files/sdf_mesh_uris.h"

#include "shared/model_files/mesh_file_search.h"

namespace mbstream::model_files {

namespace {

namespace fs = std::filesystem;

constexpr char kModelScheme[] = "model://";

bool IsRelativePath(const std::string& uri) {
  return !uri.empty() && uri.find("://") == std::string::npos && uri.front() != '/';
}

// `path` relative to `dir` when it lies below it, else empty.
fs::path Below(const fs::path& path, const fs::path& dir) {
  const fs::path relative = path.lexically_relative(dir);
  if (relative.empty() || *relative.begin() == "..") return {};
  return relative;
}

}  // namespace

std::string IncludedMeshUri(const std::string& uri, const fs::path& file,
                            const SdfIncludePath& path, const SdfIncludedModels& models) {
  if (!IsRelativePath(uri)) return uri;
  const fs::path model_file = fs::absolute(file).lexically_normal();
  const fs::path folder = model_file.parent_path();
  const fs::path mesh = (folder / uri).lexically_normal();
  // The model's name: the one its <include> gave, else its folder's.
  const auto named = models.find(folder);
  const std::string name = named != models.end() ? named->second : folder.filename().string();
  const fs::path in_model = Below(mesh, folder);
  if (!name.empty() && !in_model.empty()) {
    // model://NAME must find this folder from the world, as the world's reader looks.
    const MeshFileSearch search(path.file_dir, path.package_path);
    const std::string candidate = kModelScheme + name + "/" + model_file.filename().string();
    if (search.Find(candidate).found == model_file) {
      return kModelScheme + name + "/" + in_model.generic_string();
    }
  }
  const fs::path world_dir = fs::absolute(path.file_dir).lexically_normal();
  if (const fs::path in_world = Below(mesh, world_dir); !in_world.empty()) {
    return in_world.generic_string();
  }
  return "file://" + mesh.generic_string();
}

void RewriteIncludedMeshUris(const sdf::ElementPtr& element, const SdfIncludePath& path,
                             const SdfIncludedModels& models) {
  if (element == nullptr) return;
  if (element->GetName() == "mesh" && element->HasElement("uri")) {
    const sdf::ElementPtr uri = element->GetElement("uri");
    const std::string& file = uri->FilePath();
    if (!file.empty() && file.front() != '<') {  // not the "<data-string>" of the world's text
      const std::string written = uri->Get<std::string>();
      const std::string rewritten = IncludedMeshUri(written, file, path, models);
      if (rewritten != written) uri->Set(rewritten);
    }
  }
  for (sdf::ElementPtr child = element->GetFirstElement(); child != nullptr;
       child = child->GetNextElement()) {
    RewriteIncludedMeshUris(child, path, models);
  }
}

}  // namespace mbstream::model_files
