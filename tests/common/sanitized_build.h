// Whether this test binary is built with AddressSanitizer or ThreadSanitizer (scripts/test.sh's
// --asan and --tsan stages). Such builds run the physics 10 to 100 times slower, so a test
// whose outcome depends on which of two budgets runs out first (steps or CPU seconds) must
// choose its budgets with this in mind.
#pragma once

namespace mbstream::testing {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
inline constexpr bool kSanitizedBuild = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace mbstream::testing
