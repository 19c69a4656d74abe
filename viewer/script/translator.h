// Entry points of the scene script translator.
//
// Translation has two phases, like the seed's tool: the whole script is read and checked
// first, collecting EVERY error with its line and column; a scene may be built only from
// a Translation whose ok() is true.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "viewer/script/asset_locator.h"
#include "viewer/script/diagnostics.h"
#include "viewer/script/script.h"

namespace mbstream::scene_script {

struct TranslateOptions {
  // Finds the STL files of Part commands; null = none can be found.
  const AssetLocator* assets = nullptr;
  // Ends the message about a missing STL file (what the user should do).
  std::string missing_asset_advice = "supply the STL file or build the part from primitives";
};

struct Translation {
  Script script;
  std::vector<Diagnostic> errors;  // sorted by position
  bool ok() const { return errors.empty(); }
};

Translation TranslateScript(std::string_view text, const TranslateOptions& options = {});

// Reads and translates a file; an unreadable file gives one error at 1:1.
Translation TranslateScriptFile(const std::filesystem::path& path,
                                const TranslateOptions& options = {});

}  // namespace mbstream::scene_script
