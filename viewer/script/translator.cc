#include "viewer/script/translator.h"

#include <fstream>
#include <sstream>

#include "viewer/script/parser.h"
#include "viewer/script/resolver.h"

namespace mbstream::scene_script {

Translation TranslateScript(std::string_view text, const TranslateOptions& options) {
  Diagnostics diagnostics;
  std::vector<Command> commands = ParseScript(text, &diagnostics);
  Translation translation;
  translation.script = ResolveScript(std::move(commands), options, &diagnostics);
  translation.errors = diagnostics.Take();
  SortByPosition(&translation.errors);
  return translation;
}

Translation TranslateScriptFile(const std::filesystem::path& path,
                                const TranslateOptions& options) {
  std::error_code error;
  std::ifstream in(path, std::ios::binary);
  if (!std::filesystem::is_regular_file(path, error) || !in) {
    Translation failed;
    failed.errors.push_back({{1, 1}, "cannot read the scene script; check the path"});
    return failed;
  }
  std::ostringstream text;
  text << in.rdbuf();
  return TranslateScript(text.str(), options);
}

}  // namespace mbstream::scene_script
