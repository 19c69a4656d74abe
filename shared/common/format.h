// printf-style formatting into a std::string, for messages built on error paths.
#pragma once

#include <string>

namespace mbstream {

std::string FormatString(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace mbstream
