// A constant table of (enum value, name) pairs: the name of a value and the value of a name.
#pragma once

#include <array>
#include <string>
#include <utility>

namespace mbstream {

template <typename Enum, size_t N>
using NameTable = std::array<std::pair<Enum, const char*>, N>;

// The name of `value`, "unknown" when the table has none.
template <typename Enum, size_t N>
const char* NameOf(const NameTable<Enum, N>& table, Enum value) {
  for (const auto& [e, name] : table) {
    if (e == value) return name;
  }
  return "unknown";
}

// Sets *value to the value called `name`; returns false when there is none.
template <typename Enum, size_t N>
bool ParseName(const NameTable<Enum, N>& table, const std::string& name, Enum* value) {
  for (const auto& [e, n] : table) {
    if (name == n) {
      *value = e;
      return true;
    }
  }
  return false;
}

}  // namespace mbstream
