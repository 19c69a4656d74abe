// What end-to-end tests check of a run's stored probe reports.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>

#include "tests/common/csv_rows.h"

namespace mbstream::testing {

// Checks the run's results: every frame from `first_seq` to `last_seq` has a probe
// report within 1e-6 m of the TCP at the same time.
inline void ExpectProbesMatchTcp(const std::filesystem::path& results, int64_t first_seq,
                                 int64_t last_seq) {
  const auto tcp = ReadCsv(results / "tcp.csv");
  const auto probes = ReadCsv(results / "probes.csv");
  ASSERT_EQ(static_cast<int64_t>(probes.size()), last_seq - first_seq + 1);
  for (size_t i = 0; i < probes.size(); ++i) {
    const auto& probe = probes[i];
    ASSERT_EQ(std::stoll(probe[0]), first_seq + static_cast<int64_t>(i));
    const auto& frame = tcp.at(std::stoul(probe[0]));
    EXPECT_EQ(probe[1], frame[0]);  // same simulated time
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(std::stod(probe[3 + j]), std::stod(frame[1 + j]), 1e-6) << "seq " << probe[0];
    }
    EXPECT_GE(std::stoll(probe[6]), 0);
  }
}

}  // namespace mbstream::testing
