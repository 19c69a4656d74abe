// Fuzzes the URDF import (server/parse), without and with repairs (and a link limit, and
// <mimic> joints coupled: every coupling between two distinct moving joints, finite): any
// text either imports or throws InputError (or LimitError) with a message; nothing else (a
// crash, a sanitizer report, another exception) is allowed. Seeds with deep nesting and
// attribute floods (fuzz/seeds/urdf) exercise the shape check before TinyXML.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>

#include "server/parse/urdf_import.h"
#include "shared/common/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  // Two supplied meshes, so that mesh references can both resolve and fail.
  static const std::set<std::string> kAssets = {"base.stl", "meshes/link1.stl"};
  // As submitted, and with the repairs a user can ask for (a different path for the same
  // defects).
  for (const bool repair : {false, true}) {
    try {
      const mbstream::UrdfImport imported = mbstream::ImportUrdf(
          text, "fuzz.urdf", kAssets,
          {.repair = repair, .max_links = repair ? 64 : 0, .couple_mimic = repair});
      if (imported.model.num_dofs() < 0) std::abort();
      for (const mbstream::LoopClosure& coupling : imported.loops) {  // <mimic>, coupled
        if (coupling.body_a < 0 || coupling.body_a >= imported.model.num_bodies() ||
            coupling.body_b < 0 || coupling.body_b >= imported.model.num_bodies() ||
            coupling.body_a == coupling.body_b || !std::isfinite(coupling.multiplier) ||
            !std::isfinite(coupling.offset)) {
          std::abort();
        }
      }
      for (const std::string& warning : imported.warnings) {
        if (warning.empty()) std::abort();
      }
    } catch (const mbstream::InputError& error) {
      if (std::string(error.what()).empty()) std::abort();
    }
  }
  return 0;
}
