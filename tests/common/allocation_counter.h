// Counts heap allocations made through the global operator new (replaced in
// allocation_counter.cc), so a test can prove that a hot loop allocates nothing.
#pragma once

namespace mbstream::testing {

// Number of calls to any global operator new since the program started.
long AllocationCount();

}  // namespace mbstream::testing
