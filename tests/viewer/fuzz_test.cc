// Malformed scripts never crash the translator; those that translate build a scene.
#include <gtest/gtest.h>

#include <random>

#include "tests/viewer/script_test_util.h"
#include "viewer/model/script_scene.h"

namespace mbstream::scene_script {
namespace {

using namespace testing;  // NOLINT

void TranslateAndBuild(const std::string& text) {
  const Translation translation = TranslateScript(text);
  for (const Diagnostic& d : translation.errors) {
    EXPECT_GE(d.position.line, 1);
    EXPECT_GE(d.position.column, 1);
    EXPECT_FALSE(d.message.empty());
  }
  if (translation.ok()) (void)viewer::SceneFromScript(translation.script);
}

TEST(Fuzz, HandPickedMalformedScripts) {
  for (const char* text : {"",
                           ";",
                           ";;;",
                           "Device",
                           "Device ;",
                           "Device D (",
                           "Device D (lbox",
                           "(((",
                           ")))",
                           "$",
                           "$$",
                           "!",
                           "Module M Points",
                           "Module M Points 0",
                           "Module M Points 0 1 2 3 Polygons (",
                           "Polyprism P Height",
                           "Polyprism P Height 1 0 0 1 0 1 1 Arc",
                           "Set",
                           "Set S add",
                           "Render",
                           "Render X color",
                           "Probe",
                           "Probe P",
                           "Probe P X refer",
                           "Cone K (Center",
                           "Cylinder C dia 1e308 len 1e308",
                           "Sphere S radius 1e-300 res 3",
                           "Part",
                           "Device D Joint 1 revolute z Extend 99 Joint 2 revolute y;",
                           "Device D Joint 1 (x 1 x 2 euler 1) revolute q;",
                           "Cube A 1 1 1; Set A#1 add A;",
                           "\x01\x02\xff\xfe;",
                           "Cube \xc3\xa9 1 1 1;",
                           "Cube A 1 1 1 ; Render A color 0 0 0 0;"}) {
    TranslateAndBuild(text);
  }
}

std::string Mutate(const std::string& text, std::mt19937& rng) {
  static const std::string kPieces[] = {";",   "(",   ")",     "$",   "!",   ",",
                                        " ",   "\n",  "x",     "-",   "#",   "0",
                                        "1e9", "Arc", "Joint", "Set", "add", "IRB1600#9"};
  std::string out = text;
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !out.empty(); ++e) {
    const size_t at = rng() % out.size();
    switch (rng() % 4) {
      case 0:
        out.erase(at, 1 + rng() % 8);
        break;
      case 1:
        out.insert(at, kPieces[rng() % std::size(kPieces)]);
        break;
      case 2:
        out[at] = static_cast<char>(rng() % 128);
        break;
      default: {
        const size_t from = rng() % out.size();
        out.insert(at, out.substr(from, 1 + rng() % 20));
        break;
      }
    }
  }
  return out;
}

TEST(Fuzz, RandomMutationsOfTheShippedScripts) {
  std::mt19937 rng(7);
  for (const char* file : {"models/irb1600/irb1600.scene", "tests/viewer/data/seed_script.txt"}) {
    const std::string text = ReadFile(SourcePath(file));
    ASSERT_FALSE(text.empty());
    for (int i = 0; i < 1500; ++i) TranslateAndBuild(Mutate(text, rng));
  }
}

}  // namespace
}  // namespace mbstream::scene_script
