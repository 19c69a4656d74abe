// Translation errors: each one points at a line and column of the script and says what was
// expected and, where it is obvious, what to do.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "viewer/script/source_position.h"

namespace mbstream::scene_script {

struct Diagnostic {
  SourcePosition position;
  std::string message;
};

// Collects every error of one translation, in the order found.
class Diagnostics {
 public:
  void Error(SourcePosition position, std::string message) {
    errors_.push_back({position, std::move(message)});
  }
  bool empty() const { return errors_.empty(); }
  const std::vector<Diagnostic>& errors() const { return errors_; }
  std::vector<Diagnostic> Take() { return std::move(errors_); }

 private:
  std::vector<Diagnostic> errors_;
};

// "FILE:LINE:COL: message" (the form compilers use, so editors can jump to it).
std::string FormatDiagnostic(std::string_view file, const Diagnostic& diagnostic);

// `value` with up to 15 significant digits and no trailing zeros: "4", "0.5", "1e-07".
std::string FormatNumber(double value);

// Sorts by line then column, keeping the order of errors at the same place.
void SortByPosition(std::vector<Diagnostic>* diagnostics);

}  // namespace mbstream::scene_script
