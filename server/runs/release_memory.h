// Hands heap pages freed after a burst of allocations (a run's spool and its subscribers'
// queues, a GetResult's chunks) back to the system. glibc keeps freed memory in its arenas,
// one per thread that allocated, so without this RSS stays near its peak after a long run.
#pragma once

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace mbstream {

inline void ReleaseFreedMemory() {
#if defined(__GLIBC__) && !defined(MBSTREAM_NO_MALLOC_TRIM)  // the latter to measure without
  malloc_trim(0);
#endif
}

// Process-wide, once at start: allocations of 128 KiB and more (frame chunks, result
// messages, their gRPC buffers) get their own mappings, returned to the system when freed.
// glibc otherwise raises this threshold after the first such block is freed and serves the
// next ones from its arenas, where they fragment.
inline void UseMappingsForLargeBlocks() {
#if defined(__GLIBC__) && !defined(MBSTREAM_NO_MALLOC_TRIM)
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
}

}  // namespace mbstream
