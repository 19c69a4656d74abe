// A controlled run restarts its integrator at each control instant (a new command is a
// discontinuity) in the integrator's own memory (Integrator::Restart): after the first period
// a period allocates nothing, with every method (tests/common/allocation_counter.h; SUNDIALS'
// malloc calls too, except in sanitizer builds, where the test skips itself).
#include <gtest/gtest.h>

#include <vector>

#include "server/engine/engine.h"
#include "server/sim/run_validation.h"
#include "tests/common/allocation_counter.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;

constexpr double kPeriod = 1e-3;  // s
constexpr int kInstants = 50;

// A PD law holding every joint near 0 (gains the wrist's 0.004 kg m^2 takes at h = 1 ms:
// kd h / I = 0.25), which notes the allocation count at each instant.
class CountingLaw : public ControlLaw {
 public:
  CountingLaw() : at(kInstants + 1, -1) {}
  bool Command(const ControlState& state, double* commands, RunStats*) override {
    if (state.step >= 0 && state.step <= kInstants) {
      at[static_cast<size_t>(state.step)] = mbstream::testing::AllocationCount();
    }
    for (int i = 0; i < 6; ++i) {
      commands[i] = -20.0 * (*state.q)(i)-1.0 * (*state.qd)(i);
    }
    return true;
  }
  std::vector<long> at;  // the allocation count at each instant's command
};

RunConfig Controlled(Method method) {
  RunConfig config = testing::Scene("seed-servo");
  config.target = {};
  config.method_auto = false;
  config.duration = kInstants * kPeriod;
  config.output_interval = config.duration;  // frames at 0 and the end only
  config.method = method;
  config.fixed_step = kPeriod / 4;
  config.rtol = 1e-8;
  config.atol = 1e-10;
  for (DriveConfig& drive : config.drives) {
    drive = DriveConfig{};
    drive.kind = DriveConfig::Kind::kExternal;
    drive.command = DriveConfig::Command::kEffort;
    drive.period = kPeriod;
  }
  return config;
}

TEST(SampledNoAllocationTest, APeriodAllocatesNothingAfterTheFirst) {
  if (!mbstream::testing::CountsCAllocations()) {
    GTEST_SKIP() << "malloc is the sanitizer's: SUNDIALS' allocations not counted";
  }
  for (Method method :
       {Method::kRk4, Method::kEuler, Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk}) {
    const RunConfig config = Controlled(method);
    ValidateRun(Irb1600(), config);
    CountingLaw law;
    const RunResult result = Simulate(Irb1600(), {}, config, nullptr, nullptr, &law);
    ASSERT_EQ(result.stats.status, RunStatus::kFinished)
        << MethodName(method) << ": " << result.stats.message;
    ASSERT_GE(law.at[kInstants - 1], 0) << MethodName(method);
    // From the second instant's command to the last one's: 48 restarts and periods.
    EXPECT_EQ(law.at[kInstants - 1] - law.at[1], 0) << MethodName(method);
  }
}

}  // namespace
}  // namespace mbstream
