#include <iostream>

#include "viewer/app/commands.h"
#include "viewer/app/scene_loading.h"
#include "viewer/app/script_summary.h"

namespace mbstream::viewer {

int RunCheck(const std::string& file, const std::vector<std::string>& asset_dirs) {
  const scene_script::Translation translation = TranslateForCommandLine(file, asset_dirs);
  if (!translation.ok()) {
    std::cerr << file << ": " << translation.errors.size() << " error(s)\n";
    return 1;
  }
  std::cout << ScriptSummary(file, translation.script);
  return 0;
}

}  // namespace mbstream::viewer
