#include "tests/common/allocation_counter.h"

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <new>

#include "tests/common/sanitized_build.h"

namespace {
std::atomic<long> g_allocations{0};

void Count() { g_allocations.fetch_add(1, std::memory_order_relaxed); }
}  // namespace

#ifndef MBSTREAM_SANITIZED
// glibc's own allocator entry points, which the replacements forward to (free stays glibc's:
// the memory comes from the same allocator).
extern "C" void* __libc_malloc(size_t size);
extern "C" void* __libc_calloc(size_t count, size_t size);
extern "C" void* __libc_realloc(void* pointer, size_t size);
extern "C" void* __libc_memalign(size_t alignment, size_t size);

extern "C" void* malloc(size_t size) noexcept {
  Count();
  return __libc_malloc(size);
}
extern "C" void* calloc(size_t count, size_t size) noexcept {
  Count();
  return __libc_calloc(count, size);
}
extern "C" void* realloc(void* pointer, size_t size) noexcept {
  Count();
  return __libc_realloc(pointer, size);
}
extern "C" void* memalign(size_t alignment, size_t size) noexcept {
  Count();
  return __libc_memalign(alignment, size);
}
extern "C" void* aligned_alloc(size_t alignment, size_t size) noexcept {
  Count();
  return __libc_memalign(alignment, size);
}
extern "C" int posix_memalign(void** out, size_t alignment, size_t size) noexcept {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  Count();
  void* p = __libc_memalign(alignment, size);
  if (p == nullptr) return ENOMEM;
  *out = p;
  return 0;
}

namespace mbstream::testing {
bool CountsCAllocations() { return true; }
}  // namespace mbstream::testing

#elif defined(MBSTREAM_THREAD_SANITIZED)
// ThreadSanitizer's runtime defines operator new (in a static archive that is linked whole, so
// a replacement collides with it) and owns malloc. It calls this hook after every allocation
// it makes for the program, C or C++, from any thread.
#include <sanitizer/allocator_interface.h>

extern "C" void __sanitizer_malloc_hook(const volatile void*, size_t) { Count(); }

namespace mbstream::testing {
bool CountsCAllocations() { return true; }
}  // namespace mbstream::testing

#else  // MBSTREAM_SANITIZED: count C++ allocations through a replaced operator new.

namespace {
void* CountedAllocate(std::size_t size, std::size_t alignment) {
  Count();
  if (size == 0) size = 1;
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment)
                : std::malloc(size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t size) { return CountedAllocate(size, 0); }
void* operator new[](std::size_t size) { return CountedAllocate(size, 0); }
void* operator new(std::size_t size, std::align_val_t a) {
  return CountedAllocate(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return CountedAllocate(size, static_cast<std::size_t>(a));
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them): every form of new
// and delete must come from this file, or a sanitizer sees one allocator's memory freed by
// another.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return CountedAllocate(size, 0);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return CountedAllocate(size, static_cast<std::size_t>(a));
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t& tag) noexcept {
  return operator new(size, a, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace mbstream::testing {
bool CountsCAllocations() { return false; }
}  // namespace mbstream::testing

#endif  // MBSTREAM_SANITIZED, MBSTREAM_THREAD_SANITIZED

namespace mbstream::testing {
long AllocationCount() { return g_allocations.load(std::memory_order_relaxed); }
}  // namespace mbstream::testing
