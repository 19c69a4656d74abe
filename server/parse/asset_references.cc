#include "server/parse/asset_references.h"

#include <algorithm>
#include <cctype>

#include "server/parse/mesh_dependencies.h"
#include "shared/common/ascii.h"
#include "shared/model_files/mesh_lookup.h"

namespace mbstream {

namespace {

// The scene lexer's rules (viewer/script/lexer.h): white space separates; ( ) ; , are tokens
// of their own; ! starts a line comment and $ ... $ is a comment block.
bool IsSeparator(char c) {
  return std::isspace(static_cast<unsigned char>(c)) || c == '(' || c == ')' || c == ';' ||
         c == ',' || c == '!' || c == '$';
}

std::vector<std::string_view> SceneTokens(std::string_view text) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < text.size()) {
    const char c = text[i];
    if (std::isspace(static_cast<unsigned char>(c))) {
      ++i;
    } else if (c == '!') {
      while (i < text.size() && text[i] != '\n') ++i;
    } else if (c == '$') {
      const size_t close = text.find('$', i + 1);
      i = close == std::string_view::npos ? text.size() : close + 1;
    } else if (c == '(' || c == ')' || c == ';' || c == ',') {
      tokens.push_back(text.substr(i, 1));
      ++i;
    } else {
      const size_t start = i;
      while (i < text.size() && !IsSeparator(text[i])) ++i;
      tokens.push_back(text.substr(start, i - start));
    }
  }
  return tokens;
}

bool IsWord(std::string_view token) {
  return !token.empty() && !(token.size() == 1 && IsSeparator(token[0]));
}

}  // namespace

std::vector<std::string> UrdfMeshAssetNames(const std::string& filename) {
  return model_files::MeshAssetKeys(filename);
}

std::vector<std::string> ScenePartAssetNames(const std::string& name) {
  return {name + ".stl", name + ".STL", name};
}

std::vector<std::string> ScenePartNames(std::string_view scene_script) {
  const std::vector<std::string_view> tokens = SceneTokens(scene_script);
  std::vector<std::string> names;
  for (size_t i = 0; i + 1 < tokens.size(); ++i) {
    // Not only at the start of a command: keeping an asset too many is harmless.
    if (EqualsIgnoreCase(tokens[i], "Part") && IsWord(tokens[i + 1])) {
      names.emplace_back(tokens[i + 1]);
    }
  }
  return names;
}

bool AnySupplied(const std::vector<std::string>& names, const std::set<std::string>& assets) {
  for (const std::string& name : names) {
    if (assets.count(name) != 0) return true;
  }
  return false;
}

std::vector<std::string> UnreferencedAssets(const std::vector<std::string>& asset_names,
                                            const std::vector<std::string>& urdf_mesh_files,
                                            std::string_view scene_script) {
  std::set<std::string> referenced;
  for (const std::string& filename : urdf_mesh_files) {
    for (std::string& name : UrdfMeshAssetNames(filename)) referenced.insert(std::move(name));
  }
  for (const std::string& part : ScenePartNames(scene_script)) {
    for (std::string& name : ScenePartAssetNames(part)) referenced.insert(std::move(name));
  }
  // A mesh that may name files (OBJ, Collada, glTF) keeps the bundle's materials, images and
  // buffers: the server reads names only here, not the mesh's bytes.
  const bool companions =
      std::any_of(urdf_mesh_files.begin(), urdf_mesh_files.end(),
                  [](const std::string& file) { return MayReferenceFiles(file); });
  std::vector<std::string> unreferenced;
  for (const std::string& name : asset_names) {
    if (referenced.count(name) == 0 && !(companions && IsMeshCompanionName(name))) {
      unreferenced.push_back(name);
    }
  }
  return unreferenced;
}

}  // namespace mbstream
