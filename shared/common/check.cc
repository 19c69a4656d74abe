#include "shared/common/check.h"

#include <sstream>

namespace mbstream::internal {

void ThrowCheckFailure(const char* condition, const char* file, int line,
                       const std::string& detail) {
  std::ostringstream message;
  message << "internal check failed: " << condition << " at " << file << ":" << line;
  if (!detail.empty()) message << ": " << detail;
  message << " (this is a bug in mbstream; please report it with the input that caused it)";
  throw InternalError(message.str());
}

}  // namespace mbstream::internal
