// Phase 2 of translation: checks the commands against each other (names defined before
// use and only once, device links and frames that exist, STL files found, polyprism
// outlines that close) and groups them into a Script.
#pragma once

#include <vector>

#include "viewer/script/commands.h"
#include "viewer/script/diagnostics.h"
#include "viewer/script/script.h"
#include "viewer/script/translator.h"

namespace mbstream::scene_script {

Script ResolveScript(std::vector<Command> commands, const TranslateOptions& options,
                     Diagnostics* diagnostics);

}  // namespace mbstream::scene_script
