// MultiplierTolerances: the run's atol for the differential unknowns, and for the
// multipliers a floor relative to their largest initial magnitude (ida_system.h).
#include <gtest/gtest.h>

#include <vector>

#include "server/integrate/ida_system.h"

namespace mbstream {
namespace {

TEST(MultiplierTolerancesTest, TheMultipliersGetAFloorFromTheirLargestStartingValue) {
  // Two differential unknowns, then three multipliers, the largest |-250| N.
  const std::vector<double> y0 = {0.3, -7.0, 12.0, -250.0, 0.0};
  std::vector<double> atols(y0.size());
  MultiplierTolerances(5, 2, 1e-11, y0.data(), atols.data());
  EXPECT_EQ(atols[0], 1e-11);
  EXPECT_EQ(atols[1], 1e-11);  // |y0| of a differential unknown does not count
  for (int i = 2; i < 5; ++i) EXPECT_DOUBLE_EQ(atols[i], kMultiplierNoiseFloor * 250.0);
}

TEST(MultiplierTolerancesTest, SmallMultipliersAreScaledFromOneAndALooserAtolWins) {
  const std::vector<double> y0 = {1.0, 0.07, -0.002};
  std::vector<double> atols(y0.size());
  MultiplierTolerances(3, 1, 1e-10, y0.data(), atols.data());
  EXPECT_EQ(atols[0], 1e-10);
  EXPECT_EQ(atols[1], kMultiplierNoiseFloor);
  EXPECT_EQ(atols[2], kMultiplierNoiseFloor);
  MultiplierTolerances(3, 1, 1e-3, y0.data(), atols.data());  // the run's atol is looser
  for (double atol : atols) EXPECT_EQ(atol, 1e-3);
}

}  // namespace
}  // namespace mbstream
