// The one allocation counter of the test suite: counts heap allocations so that a test can
// prove a hot loop allocates nothing. Link mbstream_allocation_counter into the test program.
//
// In an ordinary build the C allocator's entry points (malloc, calloc, realloc,
// aligned_alloc, posix_memalign, memalign) are interposed for the whole program, so C++'s
// operator new (which calls malloc) and C libraries such as SUNDIALS are both seen. In a
// sanitizer build (tests/common/sanitized_build.h) malloc belongs to the sanitizer and cannot
// be replaced: there the global operator new is replaced instead and C allocations are not
// counted (CountsCAllocations() is false; a test that needs them skips itself). ThreadSanitizer
// defines operator new itself: there the sanitizers' allocation hook counts every allocation.
#pragma once

namespace mbstream::testing {

// Number of heap allocations (from any thread) since the program started.
long AllocationCount();

// Whether AllocationCount() includes allocations made by C code through malloc & co.
bool CountsCAllocations();

}  // namespace mbstream::testing
