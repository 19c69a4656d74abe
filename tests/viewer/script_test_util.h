// Helpers for the scene script tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "viewer/script/translator.h"

namespace mbstream::scene_script::testing {

// Every error as "LINE:COL: message".
inline std::vector<std::string> ErrorsOf(const Translation& translation) {
  std::vector<std::string> errors;
  for (const Diagnostic& d : translation.errors) {
    errors.push_back(std::to_string(d.position.line) + ":" + std::to_string(d.position.column) +
                     ": " + d.message);
  }
  return errors;
}

inline std::vector<std::string> Errors(const std::string& text,
                                       const TranslateOptions& options = {}) {
  return ErrorsOf(TranslateScript(text, options));
}

inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

inline std::filesystem::path SourcePath(const std::string& relative) {
  return std::filesystem::path(MBSTREAM_SOURCE_DIR) / relative;
}

// A binary STL file with one triangle.
inline void WriteTinyStl(const std::filesystem::path& path) {
  std::ofstream out(path, std::ios::binary);
  std::string header(80, ' ');
  out.write(header.data(), 80);
  const std::uint32_t count = 1;
  out.write(reinterpret_cast<const char*>(&count), 4);
  const float data[12] = {0, 0, 1, 0, 0, 0, 100, 0, 0, 0, 100, 0};
  out.write(reinterpret_cast<const char*>(data), sizeof(data));
  const std::uint16_t attribute = 0;
  out.write(reinterpret_cast<const char*>(&attribute), 2);
}

// The seed's device block (as the seed chapter printed it) with a probe on the TCP in the base
// frame.
inline const char* kSeedDevice = R"(Device IRB1600 (euler -90.0 -90.0 0.0 lbox 1200)
  Joint 1 revolute z
  Joint 2 (shift x 150 z 486.5) revolute y
  Joint 3 (shift z 475) revolute y
  Joint 4 (shift x 600) revolute x
  Joint 5 revolute y
  Joint 6 revolute x
  Tcp (shift x 65)
  initial (0.0 0.0 0.0 0.0 0.0 0.0);
)";

}  // namespace mbstream::scene_script::testing
