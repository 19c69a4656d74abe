// Which format a model file is in, told by its content (the root element <sdf> is
// SDFormat, anything else URDF), and one import for both.
#pragma once

#include <string>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/parse/urdf_import.h"

namespace mbstream {

enum class ModelFormat { kUrdf, kSdf };

// The format of model file `text` by its first element: SDFormat for <sdf>, URDF for
// anything else (the URDF reader then says what is wrong with it, as it always has).
ModelFormat DetectModelFormat(const std::string& text);

struct ModelFileImport {
  ModelFormat format = ModelFormat::kUrdf;
  Model model;
  std::vector<LoopClosure> loops;  // SDFormat's cut joints; empty for URDF
  std::vector<std::string> warnings;
};

// Reads the file at `path` and imports it as URDF (with `urdf_options`) or SDFormat.
ModelFileImport ImportModelFile(const std::string& path,
                                const UrdfImportOptions& urdf_options = {});

}  // namespace mbstream
