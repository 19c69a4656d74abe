// Always-on invariant checks and the exception type for bad input from outside.
//
// Three levels, as in Drake: assert() for debug-only checks of cheap local facts,
// MBSTREAM_CHECK for internal invariants that stay on in release builds (a failure is a
// bug in mbstream), and InputError for input from outside (files, requests, specs), whose
// message says what is wrong, where, and what to do.
#pragma once

#include <stdexcept>
#include <string>

namespace mbstream {

// Thrown for invalid input from outside: a file, a request, a spec. The message names the
// place (file, line, element, field) and says what to do.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Thrown for input from outside that is well formed but larger than a limit the caller set
// (links of a model, frames of a run): the service answers RESOURCE_EXHAUSTED, the CLI
// exits 2 as for any InputError. The message names the limit and the flag that raises it.
class LimitError : public InputError {
 public:
  using InputError::InputError;
};

// Thrown when an internal invariant fails: a bug in mbstream, not a user error.
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

namespace internal {
[[noreturn]] void ThrowCheckFailure(const char* condition, const char* file, int line,
                                    const std::string& detail);
}  // namespace internal

}  // namespace mbstream

// Checks an internal invariant in every build type; throws InternalError when it fails.
#define MBSTREAM_CHECK(condition)                                                  \
  do {                                                                             \
    if (!(condition)) [[unlikely]]                                                 \
      ::mbstream::internal::ThrowCheckFailure(#condition, __FILE__, __LINE__, ""); \
  } while (0)

// Like MBSTREAM_CHECK, with a message explaining the invariant.
#define MBSTREAM_CHECK_MSG(condition, message)                                            \
  do {                                                                                    \
    if (!(condition)) [[unlikely]]                                                        \
      ::mbstream::internal::ThrowCheckFailure(#condition, __FILE__, __LINE__, (message)); \
  } while (0)
