// Two doubles in one SSE2 register (a GCC and Clang vector extension; arithmetic is lane by
// lane, with a scalar operand broadcast), for the hand-vectorised vector and LU kernels: GCC
// vectorises their plain loops only behind run-time overlap checks, when at all. Each lane
// computes exactly what the scalar formula computes.
#pragma once

#include <cstring>

namespace mbstream::sundials {

using Pair = double __attribute__((vector_size(16)));

inline Pair Load(const double* p) {
  Pair v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void Store(double* p, Pair v) { std::memcpy(p, &v, sizeof v); }

}  // namespace mbstream::sundials
