// sin and cos of one angle together, without branches on the quadrant: the joint angle's
// (cos, sin) of the dynamics kernels (server/dynamics), where glibc's sincos was a quarter of
// the inverse dynamics' instructions (about 180 per call).
//
// The algorithm is fdlibm's (as in musl: __rem_pio2's medium case, __sin, __cos): reduce x
// by the nearest multiple n of pi/2 with pi/2 split in three parts (the reduced argument is
// exact to about 2^-100 |n|), evaluate the minimax polynomials on [-pi/4, pi/4] with the
// reduction's tail y, and pick the quadrant by n mod 4 with table look-ups instead of
// branches (the angles of a simulation come in random order). About 100 instructions. The
// values are within one ulp of glibc's (tests/server/sin_cos_test.cc: a million random
// angles up to 8e5 rad and the neighbours of multiples of pi/2), equal on most arguments.
// |x| >= 2^19 pi/2 (or not finite) goes to the C library. Allocates nothing.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace mbstream {

namespace internal {

// fdlibm's minimax polynomial for sin(x + y), |x| <= pi/4, y the tail of x (|y| < ulp(x)/2).
[[gnu::always_inline]] inline double KernelSin(double x, double y) {
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                   S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                   S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  const double z = x * x;
  const double w = z * z;
  const double r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
  const double v = z * x;
  return x - ((z * (0.5 * y - v * r) - y) - v * S1);
}

// fdlibm's minimax polynomial for cos(x + y), |x| <= pi/4.
[[gnu::always_inline]] inline double KernelCos(double x, double y) {
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                   C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                   C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  const double z = x * x;
  const double w = z * z;
  const double r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
  const double hz = 0.5 * z;
  const double one_minus_hz = 1.0 - hz;
  return one_minus_hz + (((1.0 - one_minus_hz) - hz) + (z * r - x * y));
}

inline int BiasedExponent(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return static_cast<int>((bits >> 52) & 0x7ff);
}

}  // namespace internal

// *s = sin(x), *c = cos(x), x in rad.
inline void SinCos(double x, double* s, double* c) {
  constexpr double kMaxReduced = 823549.6585318446;  // 2^19 pi/2: n fits the 33-bit split
  if (!(std::fabs(x) < kMaxReduced)) {
    ::sincos(x, s, c);
    return;
  }
  constexpr double kToInt = 6755399441055744.0;  // 1.5 * 2^52: adding it rounds to an integer
  constexpr double kInvPio2 = 6.36619772367581382433e-01;
  constexpr double kPio2_1 = 1.57079632673412561417e+00;   // first 33 bits of pi/2
  constexpr double kPio2_1t = 6.07710050650619224932e-11;  // pi/2 - kPio2_1
  constexpr double kPio2_2 = 6.07710050630396597660e-11;   // second 33 bits
  constexpr double kPio2_2t = 2.02226624879595063154e-21;  // pi/2 - (kPio2_1 + kPio2_2)
  constexpr double kPio2_3 = 2.02226624871116645580e-21;   // third 33 bits
  constexpr double kPio2_3t = 8.47842766036889956997e-32;  // pi/2 - (the three parts)
  // n = round(x * 2/pi): adding and subtracting 1.5 * 2^52 rounds to an integer (IEEE doubles,
  // no -ffast-math).
  const double fn = (x * kInvPio2 + kToInt) - kToInt;
  const int n = static_cast<int>(fn);
  double r = x - fn * kPio2_1;
  double w = fn * kPio2_1t;
  double y0 = r - w;
  const int ex = internal::BiasedExponent(x);
  if (ex - internal::BiasedExponent(y0) > 16) {
    // x is close to a multiple of pi/2: the first part cancelled, take the second.
    double t = r;
    w = fn * kPio2_2;
    r = t - w;
    w = fn * kPio2_2t - ((t - r) - w);
    y0 = r - w;
    if (ex - internal::BiasedExponent(y0) > 49) {
      t = r;
      w = fn * kPio2_3;
      r = t - w;
      w = fn * kPio2_3t - ((t - r) - w);
      y0 = r - w;
    }
  }
  const double y1 = (r - y0) - w;
  // sin(x) and cos(x) from sin and cos of the reduced argument, by n mod 4:
  // 0: (S, C), 1: (C, -S), 2: (-S, -C), 3: (-C, S).
  const double kernel[2] = {internal::KernelSin(y0, y1), internal::KernelCos(y0, y1)};
  static constexpr double kSinSign[4] = {1.0, 1.0, -1.0, -1.0};
  static constexpr double kCosSign[4] = {1.0, -1.0, -1.0, 1.0};
  const int quadrant = n & 3;
  *s = kSinSign[quadrant] * kernel[quadrant & 1];
  *c = kCosSign[quadrant] * kernel[(quadrant & 1) ^ 1];
}

}  // namespace mbstream
