// Which format a model file is in, told by its content (the root element <sdf> is
// SDFormat, anything else URDF), and one import for both.
#pragma once

#include <string>
#include <vector>

#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/parse/urdf_import.h"
#include "shared/model_files/model_format.h"

namespace mbstream {

// The format by content is shared/model_files's (the viewer's local mode asks there too).
using model_files::DetectModelFormat;
using model_files::ModelFormat;

struct ModelFileImport {
  ModelFormat format = ModelFormat::kUrdf;
  Model model;
  std::vector<LoopClosure> loops;  // SDFormat's cut joints; URDF's <mimic> couplings
  std::vector<std::string> warnings;
};

// Reads the file at `path` and imports it as URDF (with `urdf_options`) or SDFormat (its
// <include>s found beside it, its ancestors and in `package_path` then
// $MBSTREAM_PACKAGE_PATH: shared/model_files/sdf_includes.h).
ModelFileImport ImportModelFile(const std::string& path, const UrdfImportOptions& urdf_options = {},
                                const std::vector<std::string>& package_path = {});

}  // namespace mbstream
