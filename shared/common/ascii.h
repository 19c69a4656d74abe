// ASCII text helpers shared by the URDF reader and the scene script language (whose keywords
// and frame names are case-insensitive).
#pragma once

#include <cctype>
#include <string_view>

namespace mbstream {

// ASCII case-insensitive equality ("World" == "WORLD"); bytes above 0x7F compare exactly.
inline bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i]))) {
      return false;
    }
  }
  return true;
}

}  // namespace mbstream
