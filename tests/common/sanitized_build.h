// Whether this test binary is built with a sanitizer (scripts/test.sh's --asan and --tsan
// stages): MBSTREAM_SANITIZED for the preprocessor (code that must not be compiled there,
// such as a replaced malloc) and kSanitizedBuild for ordinary code. Such builds run the
// physics 10 to 100 times slower, so a test whose outcome depends on which of two budgets runs
// out first (steps or CPU seconds) must choose its budgets with this in mind.
#pragma once

// MBSTREAM_THREAD_SANITIZED: a ThreadSanitizer build in particular (its runtime defines every
// form of operator new itself, so tests/common/allocation_counter.cc counts through the
// sanitizers' allocation hook there instead of replacing operator new).
#if defined(__SANITIZE_THREAD__)
#define MBSTREAM_THREAD_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define MBSTREAM_THREAD_SANITIZED 1
#endif
#endif

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MBSTREAM_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || \
    __has_feature(memory_sanitizer)
#define MBSTREAM_SANITIZED 1
#endif
#endif

namespace mbstream::testing {

#ifdef MBSTREAM_SANITIZED
inline constexpr bool kSanitizedBuild = true;
#else
inline constexpr bool kSanitizedBuild = false;
#endif

}  // namespace mbstream::testing
