// Finds the STL file of a `Part` command. The CLI looks in directories; the network link
// will write the assets received from the server to a directory and use the same class.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace mbstream::scene_script {

class AssetLocator {
 public:
  virtual ~AssetLocator() = default;
  // The file for part `name` (written without .stl in the script), or nullopt.
  virtual std::optional<std::filesystem::path> Find(std::string_view name) const = 0;
  // Where it looked, for messages: "looked in models/irb1600" or "no asset directory given".
  virtual std::string Describe() const = 0;
};

// Looks for NAME.stl, NAME.STL and NAME in each directory, in order.
class DirectoryAssetLocator : public AssetLocator {
 public:
  explicit DirectoryAssetLocator(std::vector<std::filesystem::path> directories)
      : directories_(std::move(directories)) {}
  std::optional<std::filesystem::path> Find(std::string_view name) const override;
  std::string Describe() const override;

 private:
  std::vector<std::filesystem::path> directories_;
};

// What is wrong with an STL file ("is empty", "is not an STL file: ..."), or nullopt when it
// looks like ASCII STL ("solid ...") or binary STL whose size matches its triangle count.
std::optional<std::string> StlFileProblem(const std::filesystem::path& path);

}  // namespace mbstream::scene_script
