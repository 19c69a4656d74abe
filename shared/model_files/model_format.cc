#include "shared/model_files/model_format.h"

namespace mbstream::model_files {

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

}  // namespace mbstream::model_files
