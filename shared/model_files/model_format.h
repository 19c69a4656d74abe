// Which format a model file is in, told by its content: the root element <sdf> is SDFormat,
// anything else URDF. The server's import, `mbstream submit` and the viewer's local mode
// (`mbstream-viewer --model FILE`) all ask here.
#pragma once

#include <string>

namespace mbstream::model_files {

enum class ModelFormat { kUrdf, kSdf };

// The format of model file `text` by its first element (XML declarations, comments and
// DOCTYPEs skipped): SDFormat for <sdf>, URDF for anything else (the URDF reader then says
// what is wrong with it).
ModelFormat DetectModelFormat(const std::string& text);

}  // namespace mbstream::model_files
