#include "server/parse/mesh_dependencies.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "shared/common/ascii.h"

namespace mbstream {

namespace {

bool IsSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

std::string_view Trimmed(std::string_view text) {
  while (!text.empty() && IsSpace(text.front())) text.remove_prefix(1);
  while (!text.empty() && IsSpace(text.back())) text.remove_suffix(1);
  return text;
}

bool HasExtension(std::string_view name, std::string_view ext) {
  return name.size() >= ext.size() && EqualsIgnoreCase(name.substr(name.size() - ext.size()), ext);
}

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// A reference as a file name: file:// dropped, %XX undone, backslashes as slashes; empty for
// embedded data and URLs.
std::string FileName(std::string_view written) {
  std::string_view text = Trimmed(written);
  if (text.starts_with("file://")) text.remove_prefix(7);
  if (text.empty() || text.starts_with("data:") || text.find("://") != std::string_view::npos) {
    return "";
  }
  std::string name;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && HexDigit(text[i + 1]) >= 0 &&
        HexDigit(text[i + 2]) >= 0) {
      name += static_cast<char>(HexDigit(text[i + 1]) * 16 + HexDigit(text[i + 2]));
      i += 2;
    } else {
      name += text[i] == '\\' ? '/' : text[i];
    }
  }
  return name;
}

void AddOnce(std::vector<std::string>* names, std::string_view written) {
  std::string name = FileName(written);
  if (!name.empty() && std::find(names->begin(), names->end(), name) == names->end()) {
    names->push_back(std::move(name));
  }
}

std::vector<std::string_view> Lines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    lines.push_back(Trimmed(text.substr(start, end - start)));
    start = end + 1;
  }
  return lines;
}

// The first word of `line` and the rest, trimmed.
std::pair<std::string_view, std::string_view> Split(std::string_view line) {
  size_t end = 0;
  while (end < line.size() && !IsSpace(line[end])) ++end;
  return {line.substr(0, end), Trimmed(line.substr(end))};
}

// `mtllib NAME` (the rest of the line, as Assimp reads it).
void ObjReferences(std::string_view data, std::vector<std::string>* names) {
  for (std::string_view line : Lines(data)) {
    const auto [keyword, rest] = Split(line);
    if (keyword == "mtllib") AddOnce(names, rest);
  }
}

// map_Kd, map_Ks, ..., bump, disp, decal, refl, norm: the file is the last word (options such
// as `-s 1 1 1` come before it).
void MtlReferences(std::string_view data, std::vector<std::string>* names) {
  for (std::string_view line : Lines(data)) {
    const auto [keyword, rest] = Split(line);
    const bool image = (keyword.size() > 4 && EqualsIgnoreCase(keyword.substr(0, 4), "map_")) ||
                       EqualsIgnoreCase(keyword, "bump") || EqualsIgnoreCase(keyword, "disp") ||
                       EqualsIgnoreCase(keyword, "decal") || EqualsIgnoreCase(keyword, "refl") ||
                       EqualsIgnoreCase(keyword, "norm");
    if (!image || rest.empty()) continue;
    size_t start = rest.size();
    while (start > 0 && !IsSpace(rest[start - 1])) --start;
    AddOnce(names, rest.substr(start));
  }
}

// Every <init_from> (COLLADA 1.5: its <ref>) inside <library_images>: an effect's
// <surface><init_from> names an image element, not a file.
void ColladaReferences(std::string_view data, std::vector<std::string>* names) {
  size_t at = 0;
  while ((at = data.find("<library_images", at)) != std::string_view::npos) {
    const size_t end = std::min(data.find("</library_images", at), data.size());
    std::string_view images = data.substr(at, end - at);
    size_t open = 0;
    while ((open = images.find("<init_from>", open)) != std::string_view::npos) {
      open += 11;
      const size_t close = images.find("</init_from>", open);
      if (close == std::string_view::npos) break;
      std::string_view value = Trimmed(images.substr(open, close - open));
      if (value.starts_with("<ref>") && value.ends_with("</ref>")) {
        value = value.substr(5, value.size() - 11);
      }
      AddOnce(names, value);
      open = close;
    }
    at = end;
  }
}

// Every "uri": "..." (buffers and images; JSON's \/ undone).
void GltfReferences(std::string_view data, std::vector<std::string>* names) {
  size_t at = 0;
  while ((at = data.find("\"uri\"", at)) != std::string_view::npos) {
    at += 5;
    while (at < data.size() && (IsSpace(data[at]) || data[at] == ':')) ++at;
    if (at >= data.size() || data[at] != '"') continue;
    const size_t close = data.find('"', at + 1);
    if (close == std::string_view::npos) break;
    std::string uri(data.substr(at + 1, close - at - 1));
    for (size_t slash; (slash = uri.find("\\/")) != std::string::npos;) uri.erase(slash, 1);
    AddOnce(names, uri);
    at = close + 1;
  }
}

}  // namespace

std::vector<std::string> MeshFileReferences(std::string_view file_name, std::string_view data) {
  std::vector<std::string> names;
  if (HasExtension(file_name, ".obj")) ObjReferences(data, &names);
  if (HasExtension(file_name, ".mtl")) MtlReferences(data, &names);
  if (HasExtension(file_name, ".dae")) ColladaReferences(data, &names);
  if (HasExtension(file_name, ".gltf")) GltfReferences(data, &names);
  return names;
}

bool MayReferenceFiles(std::string_view file_name) {
  for (std::string_view ext : {".obj", ".mtl", ".dae", ".gltf"}) {
    if (HasExtension(file_name, ext)) return true;
  }
  return false;
}

bool IsMeshCompanionName(std::string_view file_name) {
  for (std::string_view ext : {".mtl", ".png", ".jpg", ".jpeg", ".bmp", ".tga", ".tif", ".tiff",
                               ".gif", ".dds", ".ktx", ".ktx2", ".webp", ".bin"}) {
    if (HasExtension(file_name, ext)) return true;
  }
  return false;
}

std::string CompanionAssetName(const std::string& mesh_asset, const std::string& reference) {
  const std::filesystem::path written(reference);
  if (reference.empty() || written.has_root_path() ||
      (reference.size() > 1 && reference[1] == ':')) {  // also C:/... of another system
    return "";
  }
  const std::filesystem::path name =
      (std::filesystem::path(mesh_asset).parent_path() / written).lexically_normal();
  if (name.empty() || name == "." || *name.begin() == ".." || name.filename().empty()) return "";
  return name.generic_string();
}

}  // namespace mbstream
