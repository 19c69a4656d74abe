// The `--check` summary of a script that translated cleanly: device, links, parts, probes.
#pragma once

#include <string>

#include "viewer/script/script.h"

namespace mbstream::viewer {

std::string ScriptSummary(const std::string& file, const scene_script::Script& script);

}  // namespace mbstream::viewer
