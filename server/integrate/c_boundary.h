// The wall between SUNDIALS' C frames and our C++: an exception must not unwind through C
// (undefined behaviour), so every callback handed to SUNDIALS runs its body through
// AtCBoundary, which turns an exception into the error code SUNDIALS understands and lets the
// callback record what failed for the run's message.
#pragma once

#include <exception>

namespace mbstream::sundials {

// Returns body() (a SUNDIALS callback's code); if it throws, returns on_exception(what), with
// what = the exception's message. on_exception must not throw (it records the message in a
// fixed buffer and returns a negative, unrecoverable code). Costs nothing when nothing throws.
template <typename Body, typename OnException>
int AtCBoundary(Body&& body, OnException&& on_exception) noexcept {
  try {
    return body();
  } catch (const std::exception& error) {
    return on_exception(error.what());
  } catch (...) {
    return on_exception("an exception that is not a std::exception");
  }
}

}  // namespace mbstream::sundials
