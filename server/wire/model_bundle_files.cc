#include "server/wire/model_bundle_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "server/parse/asset_references.h"
#include "server/parse/mesh_dependencies.h"
#include "server/parse/model_file.h"
#include "server/parse/sdf_import.h"
#include "shared/common/check.h"
#include "shared/common/utf8.h"
#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/mesh_lookup.h"
#include "shared/model_files/sdf_reading.h"
#include "shared/model_files/urdf_outline.h"

namespace mbstream {

namespace {

namespace fs = std::filesystem;

constexpr int kMaxUrdfDepth = 4;  // folder levels searched below a model folder for a .urdf

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read " + path.string() + ": check the path and permissions");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// A text file of the bundle (URDF, scene script): protobuf's `string` fields hold UTF-8
// only, so anything else is named here, by file and line, before it could be sent.
std::string ReadTextFile(const fs::path& path) {
  std::string text = ReadFile(path);
  if (const auto bad = FirstInvalidUtf8(text)) {
    const bool utf16 = text.find('\0') != std::string::npos;
    throw InputError(path.string() + ": " +
                     (utf16 ? "the file is UTF-16 or UTF-32, not UTF-8" : NotUtf8At(text, *bad)) +
                     "; convert the file to UTF-8 (e.g. iconv -f latin1 -t utf-8)");
  }
  return text;
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool IsXacro(const fs::path& path) { return EndsWith(Lower(path.filename().string()), ".xacro"); }

[[noreturn]] void RefuseXacro(const fs::path& xacro) {
  std::string urdf = xacro.filename().string();
  urdf = urdf.substr(0, urdf.size() - 6);  // without .xacro
  if (!EndsWith(Lower(urdf), ".urdf")) urdf += ".urdf";
  throw InputError(xacro.string() +
                   ": is a xacro macro file, not a URDF; expand it first with ROS's xacro "
                   "(`xacro " +
                   xacro.string() + " > " + urdf + "`) and submit " + urdf);
}

// Files directly in `dir` with extension `ext` (lower case, with the dot), sorted.
std::vector<fs::path> FilesWithExtension(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && EndsWith(Lower(entry.path().filename().string()), ext)) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Files below `dir` (at most kMaxUrdfDepth levels, hidden folders skipped) ending in `ext`.
std::vector<fs::path> FilesBelow(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> files;
  std::error_code error;
  for (auto it = fs::recursive_directory_iterator(dir, error);
       !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (it->is_directory(error) && (name.starts_with(".") || it.depth() >= kMaxUrdfDepth)) {
      it.disable_recursion_pending();
    } else if (it->is_regular_file(error) && EndsWith(Lower(name), ext)) {
      files.push_back(it->path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string Joined(const std::vector<fs::path>& paths) {
  std::string text;
  for (const fs::path& path : paths) text += (text.empty() ? "" : ", ") + path.string();
  return text;
}

// Whether the SDFormat file at `path` holds a <world>.
bool HoldsWorld(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str().find("<world") != std::string::npos;
}

// The model file of a model folder: its one URDF, else its one SDFormat file; a world's
// folder (one .sdf holding a <world> directly in it) gives that world, whatever its models'
// folders hold.
fs::path UrdfOfFolder(const fs::path& dir) {
  std::vector<fs::path> urdfs = FilesWithExtension(dir, ".urdf");
  if (const std::vector<fs::path> direct = FilesWithExtension(dir, ".sdf");
      urdfs.empty() && direct.size() == 1 && HoldsWorld(direct[0])) {
    return direct[0];
  }
  if (urdfs.empty()) urdfs = FilesBelow(dir, ".urdf");
  if (urdfs.size() == 1) return urdfs[0];
  if (urdfs.empty()) {
    std::vector<fs::path> sdfs = FilesWithExtension(dir, ".sdf");
    if (sdfs.empty()) sdfs = FilesBelow(dir, ".sdf");
    if (sdfs.size() == 1) return sdfs[0];
    if (sdfs.size() > 1) {
      throw InputError(dir.string() + ": a model directory needs exactly one .urdf or .sdf " +
                       "file, found " + std::to_string(sdfs.size()) + " .sdf files (" +
                       Joined(sdfs) + "); name the model file instead");
    }
  }
  if (urdfs.empty()) {
    const std::vector<fs::path> xacros = FilesBelow(dir, ".xacro");
    for (const fs::path& xacro : xacros) {
      if (EndsWith(Lower(xacro.filename().string()), ".urdf.xacro")) RefuseXacro(xacro);
    }
    if (!xacros.empty()) RefuseXacro(xacros[0]);
  }
  throw InputError(dir.string() + ": a model directory needs exactly one .urdf file, found " +
                   std::to_string(urdfs.size()) +
                   (urdfs.empty() ? std::string() : " (" + Joined(urdfs) + ")") +
                   "; name the URDF file instead (or give a folder with one .sdf file)");
}

// The assets of a bundle being read: one per name, each from one file.
class AssetSet {
 public:
  explicit AssetSet(v1::ModelBundle* bundle) : bundle_(bundle) {}

  // The data of the file, or nullptr when it was added before.
  const std::string* Add(const std::string& name, const fs::path& path,
                         const std::string& reference) {
    const fs::path file = fs::weakly_canonical(path);
    const auto [it, inserted] = files_.emplace(name, std::make_pair(file, reference));
    if (!inserted) {
      if (it->second.first == file) return nullptr;  // the same file again: stored once
      throw InputError("asset '" + name + "' would hold two files: " + it->second.first.string() +
                       " (for '" + it->second.second + "') and " + file.string() + " (for '" +
                       reference + "'); rename one of the files");
    }
    v1::Asset* asset = bundle_->add_assets();
    asset->set_name(name);
    asset->set_data(ReadFile(path));
    return &asset->data();
  }

 private:
  v1::ModelBundle* bundle_;
  std::map<std::string, std::pair<fs::path, std::string>> files_;
};

// The files the mesh (or material library) at `path`, stored as `name` with the bytes `data`,
// names (mesh_dependencies.h), attached beside it, an OBJ's .mtl with its images in turn: as
// written relative to the mesh, else by their file name alone beside it (exported files often
// name a folder of the author's machine; the viewer looks there too). A reference that leaves
// the bundle or is nowhere is a warning, and the mesh is drawn in its material colour.
void AttachReferencedFiles(AssetSet* assets, const std::string& name, const fs::path& path,
                           const std::string& data, std::vector<std::string>* warnings) {
  for (const std::string& reference : MeshFileReferences(name, data)) {
    const fs::path folder = path.parent_path();
    const std::string base = fs::path(reference).filename().string();
    std::vector<std::pair<std::string, fs::path>> candidates;  // asset name, file
    if (std::string as = CompanionAssetName(name, reference); !as.empty()) {
      candidates.emplace_back(std::move(as), folder / reference);
    }
    if (std::string as = CompanionAssetName(name, base); !as.empty() && base != reference) {
      candidates.emplace_back(std::move(as), folder / base);
    }
    std::error_code error;
    const auto found = std::find_if(candidates.begin(), candidates.end(), [&](const auto& c) {
      return fs::is_regular_file(c.second, error);
    });
    if (found == candidates.end()) {
      warnings->push_back(path.string() + " names '" + reference + "', which is not in " +
                          folder.string() +
                          " (the model is sent without it; a texture shows its material colour)");
      continue;
    }
    const std::string* added = assets->Add(found->first, found->second, path.string());
    if (added != nullptr && MayReferenceFiles(found->first)) {
      AttachReferencedFiles(assets, found->first, found->second, *added, warnings);
    }
  }
}

std::string NotFound(const std::string& what, const std::string& filename,
                     const std::vector<fs::path>& tried, const std::string& note) {
  std::string message = what + " '" + filename + "' was not found; tried " + Joined(tried);
  if (!note.empty()) message += "; " + note;
  if (filename.starts_with("package://") || filename.starts_with("model://")) {
    message +=
        "; add --package-path DIR (a folder holding the package) or set "
        "MBSTREAM_PACKAGE_PATH";
  }
  return message + " (the model is sent without it)";
}

}  // namespace

BundleRead ReadModelBundle(const BundleFiles& files) {
  BundleRead read;
  v1::ModelBundle& bundle = read.bundle;
  bundle.set_name(files.name);
  fs::path urdf_path = files.model_path;
  fs::path scene_path = files.scene_path;
  std::error_code error;
  if (fs::is_directory(urdf_path, error)) {
    const fs::path dir = urdf_path;
    urdf_path = UrdfOfFolder(dir);
    const std::vector<fs::path> scenes = FilesWithExtension(dir, ".scene");
    if (scenes.size() == 1 && scene_path.empty()) scene_path = scenes[0];
  }
  if (IsXacro(urdf_path)) RefuseXacro(urdf_path);
  bundle.set_urdf(ReadTextFile(urdf_path));
  if (DetectModelFormat(bundle.urdf()) == ModelFormat::kSdf &&
      bundle.urdf().find("<include") != std::string::npos) {
    // The server reads no file a model names: the included models go inside the world
    // (found as shared/model_files/sdf_includes.h says; errors name the file and line here).
    const model_files::SdfFile world(
        bundle.urdf(), urdf_path.string(),
        {.includes = model_files::SdfIncludePath{
             urdf_path.parent_path().empty() ? fs::path(".") : urdf_path.parent_path(),
             model_files::PackagePath(files.package_paths)}});
    bundle.set_urdf(world.ExpandedText());
  }
  bundle.set_urdf_file_name(urdf_path.string());
  if (!scene_path.empty()) bundle.set_scene_script(ReadTextFile(scene_path));

  AssetSet assets(&bundle);
  // The meshes the model refers to: SDFormat's <mesh><uri> or the URDF's <mesh filename>,
  // found alike. A file the reader cannot read has none here: the server names its error.
  std::optional<model_files::UrdfOutline> outline;
  if (DetectModelFormat(bundle.urdf()) == ModelFormat::kSdf) {
    SdfMeshes sdf = ReadSdfMeshes(bundle.urdf());
    outline.emplace();
    outline->visual_meshes = std::move(sdf.visual);
    outline->collision_meshes = std::move(sdf.collision);
  } else {
    std::string outline_error;
    outline = model_files::ReadUrdfOutline(bundle.urdf(), &outline_error);
  }
  if (outline) {
    const model_files::MeshFileSearch search(urdf_path.parent_path(),
                                             model_files::PackagePath(files.package_paths));
    std::set<std::string> seen;  // each reference looked up once
    const auto attach = [&](const std::vector<std::string>& meshes, const std::string& what) {
      for (const std::string& filename : meshes) {
        const std::string name = model_files::BundleAssetName(filename);
        if (name.empty() || !seen.insert(filename).second) continue;
        const model_files::MeshSearch found = search.Find(filename);
        if (found.found.empty()) {
          read.warnings.push_back(urdf_path.string() + ": " +
                                  NotFound(what, filename, found.tried, found.note));
        } else if (const std::string* data = assets.Add(name, found.found, filename)) {
          AttachReferencedFiles(&assets, name, found.found, *data, &read.warnings);
        }
      }
    };
    attach(outline->visual_meshes, "visual mesh");
    if (files.with_collision) attach(outline->collision_meshes, "collision mesh");
  }
  if (!bundle.scene_script().empty()) {
    const fs::path scene_dir = scene_path.parent_path();
    for (const std::string& part : ScenePartNames(bundle.scene_script())) {
      for (const std::string& name : ScenePartAssetNames(part)) {
        if (fs::is_regular_file(scene_dir / name, error)) {
          assets.Add(name, scene_dir / name, "Part " + part);
          break;
        }
      }
    }
  }
  for (const std::string& path : files.asset_paths) {
    assets.Add(fs::path(path).filename().string(), path, path);
  }
  return read;
}

v1::ModelBundle ReadModelBundle(const std::string& model_path, const std::string& scene_path,
                                const std::vector<std::string>& asset_paths,
                                const std::string& name) {
  BundleFiles files;
  files.model_path = model_path;
  files.scene_path = scene_path;
  files.asset_paths = asset_paths;
  files.name = name;
  return ReadModelBundle(files).bundle;
}

}  // namespace mbstream
