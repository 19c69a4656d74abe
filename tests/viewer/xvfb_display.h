// Gives rendering tests an X display: when DISPLAY is unset, starts a private Xvfb (it
// picks a free display number itself, -displayfd) for the test program and stops it at the
// end. Link this file into a test program to make it self-sufficient under ctest.
#pragma once

namespace mbstream::viewer::testing {

// True when a display is available (already set, or a private Xvfb started).
bool EnsureDisplay();

}  // namespace mbstream::viewer::testing
