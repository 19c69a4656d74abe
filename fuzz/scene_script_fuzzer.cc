// Fuzzes the scene script translator (viewer/script): any text translates, or gives errors
// with a position and a message; a translation without errors builds a scene description.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "viewer/model/script_scene.h"
#include "viewer/script/translator.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const mbstream::scene_script::Translation translation =
      mbstream::scene_script::TranslateScript(text);
  for (const mbstream::scene_script::Diagnostic& d : translation.errors) {
    if (d.position.line < 1 || d.position.column < 1 || d.message.empty()) std::abort();
  }
  if (translation.ok()) (void)mbstream::viewer::SceneFromScript(translation.script);
  return 0;
}
