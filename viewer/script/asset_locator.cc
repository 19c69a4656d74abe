#include "viewer/script/asset_locator.h"

#include <cstdint>
#include <cstring>
#include <fstream>

namespace mbstream::scene_script {

std::optional<std::filesystem::path> DirectoryAssetLocator::Find(std::string_view name) const {
  const std::string base(name);
  for (const std::filesystem::path& directory : directories_) {
    for (const std::string& candidate : {base + ".stl", base + ".STL", base}) {
      const std::filesystem::path path = directory / candidate;
      std::error_code error;
      if (std::filesystem::is_regular_file(path, error)) return path;
    }
  }
  return std::nullopt;
}

std::string DirectoryAssetLocator::Describe() const {
  if (directories_.empty()) return "no asset directory given";
  std::string text = "looked in ";
  for (size_t i = 0; i < directories_.size(); ++i) {
    text += (i ? ", " : "") + directories_[i].string();
  }
  return text;
}

std::optional<std::string> StlFileProblem(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot be opened";
  std::string head(84, '\0');
  in.read(head.data(), 84);
  const std::streamsize got = in.gcount();
  if (got == 0) return "is empty";
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (got == 84) {
    std::uint32_t triangles = 0;
    std::memcpy(&triangles, head.data() + 80, 4);
    if (size == 84 + 50ull * triangles) {
      return triangles == 0 ? std::optional<std::string>("holds no triangles") : std::nullopt;
    }
  }
  const size_t first = head.find_first_not_of(" \t\r\n");
  if (first != std::string::npos && head.compare(first, 5, "solid") == 0 && size > 20) {
    return std::nullopt;
  }
  return "is not an STL file (neither ASCII 'solid ...' nor binary with a matching size)";
}

}  // namespace mbstream::scene_script
