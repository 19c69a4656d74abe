// Fuzzes the RunSpec JSON parser and its validation (server/spec): any text parses or
// throws InputError; a spec that validates for the IRB 1600's six joints converts to a
// RunConfig whose recorded spec (ToRunSpec) validates again and prints as JSON that parses.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "server/spec/run_spec_json.h"
#include "shared/common/check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<std::string> kJoints = {"joint1", "joint2", "joint3",
                                                   "joint4", "joint5", "joint6"};
  const std::string text(reinterpret_cast<const char*>(data), size);
  mbstream::v1::RunSpec spec;
  try {
    spec = mbstream::ParseRunSpecJson(text, "fuzz.json");
  } catch (const mbstream::InputError&) {
    return 0;
  }
  mbstream::RunConfig config;
  try {
    config = mbstream::ToRunConfig(spec, kJoints, "fuzz.json");
  } catch (const mbstream::InputError&) {
    return 0;
  }
  // What a run records must be accepted again, and the JSON printer's output must parse.
  const mbstream::v1::RunSpec recorded = mbstream::ToRunSpec(config);
  (void)mbstream::ToRunConfig(recorded, kJoints, "recorded");
  (void)mbstream::ParseRunSpecJson(mbstream::RunSpecToJson(spec), "printed");
  return 0;
}
