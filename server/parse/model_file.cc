#include "server/parse/model_file.h"

#include <fstream>
#include <sstream>

#include "server/parse/sdf_import.h"

namespace mbstream {

ModelFormat DetectModelFormat(const std::string& text) {
  size_t at = 0;
  while ((at = text.find('<', at)) != std::string::npos) {
    if (text.compare(at, 2, "<?") == 0) {
      at = text.find("?>", at);
    } else if (text.compare(at, 4, "<!--") == 0) {
      at = text.find("-->", at);
    } else if (text.compare(at, 2, "<!") == 0) {
      at = text.find('>', at);
    } else {
      const size_t end = text.find_first_of(" \t\r\n/>", at + 1);
      const size_t length = end == std::string::npos ? std::string::npos : end - at - 1;
      return text.compare(at + 1, length, "sdf") == 0 ? ModelFormat::kSdf : ModelFormat::kUrdf;
    }
    if (at == std::string::npos) break;
  }
  return ModelFormat::kUrdf;
}

ModelFileImport ImportModelFile(const std::string& path, const UrdfImportOptions& urdf_options) {
  std::ifstream in(path);
  std::ostringstream buffer;
  if (in) buffer << in.rdbuf();  // unreadable: the URDF reader says so, as it always has
  const std::string text = buffer.str();
  ModelFileImport result;
  result.format = DetectModelFormat(text);
  if (result.format == ModelFormat::kUrdf) {
    UrdfImport urdf = ImportUrdfFile(path, urdf_options);
    result.model = std::move(urdf.model);
    result.warnings = std::move(urdf.warnings);
  } else {
    SdfImport sdf = ImportSdf(text, path, SdfImportOptions{.max_links = urdf_options.max_links});
    result.model = std::move(sdf.model);
    result.loops = std::move(sdf.loops);
    result.warnings = std::move(sdf.warnings);
  }
  return result;
}

}  // namespace mbstream
