// SinCos (server/math/sin_cos.h) against the C library's sincos: within one unit in the last
// place everywhere, exact at the special values, the C library's beyond its reduction range.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>

#include "server/math/sin_cos.h"

namespace mbstream {
namespace {

// Distance in units in the last place between two finite doubles.
std::int64_t Ulps(double a, double b) {
  std::int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof ia);
  std::memcpy(&ib, &b, sizeof ib);
  if (ia < 0) ia = std::numeric_limits<std::int64_t>::min() - ia;
  if (ib < 0) ib = std::numeric_limits<std::int64_t>::min() - ib;
  return ia > ib ? ia - ib : ib - ia;
}

// The larger of the two functions' ulp distances from the C library's at x.
std::int64_t UlpsFromLibm(double x) {
  double s, c, s_ref, c_ref;
  SinCos(x, &s, &c);
  ::sincos(x, &s_ref, &c_ref);
  return std::max(Ulps(s, s_ref), Ulps(c, c_ref));
}

TEST(SinCosTest, WithinOneUlpOfTheCLibraryOnRandomAngles) {
  std::mt19937_64 rng(7);
  for (double range : {1.0, 4.0, 100.0, 1e5, 8e5}) {
    std::uniform_real_distribution<double> dist(-range, range);
    for (int k = 0; k < 200000; ++k) {
      const double x = dist(rng);
      ASSERT_LE(UlpsFromLibm(x), 1) << "x = " << x;
    }
  }
}

TEST(SinCosTest, WithinOneUlpNearMultiplesOfHalfPi) {
  // Where the reduction cancels: the second and third parts of pi/2 are needed.
  for (int k = -20000; k <= 20000; ++k) {
    const double x = k * (M_PI / 2);
    for (double y : {x, std::nextafter(x, 1e300), std::nextafter(x, -1e300)}) {
      ASSERT_LE(UlpsFromLibm(y), 1) << "x = " << y;
    }
  }
}

TEST(SinCosTest, SpecialValuesMatchTheLibrary) {
  double s, c;
  SinCos(0.0, &s, &c);
  EXPECT_EQ(s, 0.0);
  EXPECT_FALSE(std::signbit(s));
  EXPECT_EQ(c, 1.0);
  SinCos(-0.0, &s, &c);
  EXPECT_TRUE(std::signbit(s));
  SinCos(1e-300, &s, &c);
  EXPECT_EQ(s, 1e-300);
  EXPECT_EQ(c, 1.0);
  SinCos(1e10, &s, &c);  // beyond the reduction's range: the C library's values
  double s_ref, c_ref;
  ::sincos(1e10, &s_ref, &c_ref);
  EXPECT_EQ(s, s_ref);
  EXPECT_EQ(c, c_ref);
  SinCos(std::numeric_limits<double>::quiet_NaN(), &s, &c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
  SinCos(std::numeric_limits<double>::infinity(), &s, &c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

}  // namespace
}  // namespace mbstream
