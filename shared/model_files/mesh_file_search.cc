#include "shared/model_files/mesh_file_search.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <system_error>

#include "shared/model_files/mesh_lookup.h"

namespace mbstream::model_files {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kPackage = "package://";
constexpr std::string_view kModel = "model://";  // SDFormat's: MODEL/REST, found as a package
constexpr int kMaxPackageDepth = 6;  // subfolder levels searched below a package path entry

bool IsFile(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(path, error);
}

// The <name> of the package.xml in `dir`, or "".
std::string PackageXmlName(const fs::path& dir) {
  std::ifstream in(dir / "package.xml");
  if (!in) return "";
  std::ostringstream text;
  text << in.rdbuf();
  static const std::regex kName(R"(<name>\s*([^<\s]+)\s*</name>)");
  std::smatch match;
  const std::string xml = text.str();
  return std::regex_search(xml, match, kName) ? match[1].str() : "";
}

void CollectPackages(const fs::path& dir, const std::string& package, int depth,
                     std::vector<fs::path>* found) {
  if (PackageXmlName(dir) == package || dir.filename() == package) found->push_back(dir);
  if (depth >= kMaxPackageDepth) return;
  std::error_code error;
  std::vector<fs::path> children;
  for (fs::directory_iterator it(dir, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!name.empty() && name[0] != '.' && it->is_directory(error)) children.push_back(it->path());
  }
  std::sort(children.begin(), children.end());
  for (const fs::path& child : children) CollectPackages(child, package, depth + 1, found);
}

}  // namespace

MeshFileSearch::MeshFileSearch(fs::path urdf_dir, std::vector<fs::path> package_path)
    : urdf_dir_(std::move(urdf_dir)), package_path_(std::move(package_path)) {}

std::vector<fs::path> PackageFolders(const std::vector<fs::path>& package_path,
                                     const std::string& package) {
  std::vector<fs::path> found;
  for (const fs::path& root : package_path) {
    std::error_code error;
    if (fs::is_directory(root, error)) CollectPackages(root, package, 0, &found);
  }
  return found;
}

std::vector<fs::path> MeshFileSearch::PackageFolders(const std::string& package) const {
  return model_files::PackageFolders(package_path_, package);
}

MeshSearch MeshFileSearch::Find(const std::string& filename) const {
  MeshSearch search;
  const auto attempt = [&](const fs::path& candidate) {
    const fs::path normal = candidate.lexically_normal();
    if (std::find(search.tried.begin(), search.tried.end(), normal) != search.tried.end()) {
      return false;
    }
    search.tried.push_back(normal);
    if (!IsFile(normal)) return false;
    search.found = normal;
    return true;
  };
  const size_t scheme = filename.compare(0, kPackage.size(), kPackage) == 0 ? kPackage.size()
                        : filename.compare(0, kModel.size(), kModel) == 0   ? kModel.size()
                                                                            : 0;
  if (scheme > 0) {
    const std::string path = filename.substr(scheme);
    const size_t slash = path.find('/');
    const std::string package = path.substr(0, slash);
    const std::string rest = slash == std::string::npos ? "" : path.substr(slash + 1);
    const std::vector<fs::path> folders = PackageFolders(package);
    for (const fs::path& folder : folders) {
      if (attempt(folder / rest)) return search;
    }
    if (folders.empty()) {
      std::string roots;
      for (const fs::path& root : package_path_)
        roots += (roots.empty() ? "" : ", ") + root.string();
      search.note = roots.empty() ? "the package path is empty"
                                  : "no package '" + package +
                                        "' (a package.xml naming it, or a "
                                        "folder of that name) below " +
                                        roots;
    }
    if (scheme == kModel.size()) {
      // A world's included model folder beside it or beside an ancestor (sdf_includes.h).
      for (fs::path dir = fs::absolute(urdf_dir_).lexically_normal();; dir = dir.parent_path()) {
        if (attempt(dir / package / rest)) return search;
        if (dir == dir.parent_path()) break;
      }
    }
    for (fs::path dir = fs::absolute(urdf_dir_).lexically_normal();; dir = dir.parent_path()) {
      if (attempt(dir / rest)) return search;
      if (dir == dir.parent_path()) break;
    }
    return search;
  }
  const fs::path bare(WithoutScheme(filename));
  attempt(bare.is_absolute() ? bare : urdf_dir_ / bare);
  return search;
}

std::vector<fs::path> PackagePath(const std::vector<std::string>& flags) {
  std::vector<fs::path> path(flags.begin(), flags.end());
  if (const char* env = std::getenv("MBSTREAM_PACKAGE_PATH"); env != nullptr) {
    std::stringstream entries(env);
    for (std::string entry; std::getline(entries, entry, ':');) {
      if (!entry.empty()) path.emplace_back(entry);
    }
  }
  return path;
}

}  // namespace mbstream::model_files
