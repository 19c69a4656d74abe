// Phase 1 of translation: reads every command of a script, collecting every syntax error
// (after an error it skips to the next ';' or the next command keyword starting a line).
#pragma once

#include <string_view>
#include <vector>

#include "viewer/script/commands.h"
#include "viewer/script/diagnostics.h"

namespace mbstream::scene_script {

// The commands of `text` in order; commands with errors are left out.
std::vector<Command> ParseScript(std::string_view text, Diagnostics* diagnostics);

// The command keywords, canonical spelling ("Device", "Cylinder", ...).
const std::vector<std::string_view>& CommandKeywords();

}  // namespace mbstream::scene_script
