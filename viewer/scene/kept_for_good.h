// What the viewer keeps on purpose until the process ends: what lived on a lost X display
// (x_display.h), since freeing it would talk to a server that is not there. Marked for
// LeakSanitizer, which would otherwise report it as a leak (with everything it holds).
#pragma once

#if defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(leak_sanitizer)
#define MBSTREAM_LSAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) && !defined(MBSTREAM_LSAN)
#define MBSTREAM_LSAN 1
#endif

#ifdef MBSTREAM_LSAN
#include <sanitizer/lsan_interface.h>
#endif

namespace mbstream::viewer {

// `object` (a heap allocation, or null) is never freed; it is not a leak.
inline void KeepForGood(const void* object) {
#ifdef MBSTREAM_LSAN
  if (object) __lsan_ignore_object(object);
#else
  static_cast<void>(object);
#endif
}

}  // namespace mbstream::viewer
