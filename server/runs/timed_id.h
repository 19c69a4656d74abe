// Ids that say when they were made: PREFIX + UTC "YYYYMMDD-HHMMSS" + "-" + 32 random bits in
// hex, e.g. "r-20261127-031500-3fa2c1d0" (runs) or "s-..." (sweeps).
#pragma once

#include <string>
#include <string_view>

namespace mbstream {

// At thousands of ids a second, ids of one second collide about once in a million seconds:
// a caller that must not collide checks (the store refuses a taken run id).
std::string NewTimedId(std::string_view prefix);

}  // namespace mbstream
