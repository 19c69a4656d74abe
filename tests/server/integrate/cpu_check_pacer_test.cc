// CpuCheckPacer (cpu_check_pacer.h) spaces the checks of a run's CPU budget by time, not by
// a fixed step count: with slow steps an integrator stops near its budget, not 256 steps
// past it. Every bound below holds however loaded the machine is: a slower machine only
// makes each step cost more monotonic time, which shortens the chunks.
#include "server/integrate/cpu_check_pacer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "server/integrate/integrator.h"
#include "server/integrate/thread_cpu_clock.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

// Busy until the calling thread's CPU clock has advanced by `seconds`.
void BurnCpu(double seconds) {
  const double until = ThreadCpuSeconds() + seconds;
  volatile double sink = 0.0;
  while (ThreadCpuSeconds() < until) {
    for (int k = 0; k < 100; ++k) sink = sink + std::sqrt(static_cast<double>(k));
  }
}

TEST(CpuCheckPacerTest, StartsWithOneStepAndGrowsToTheMaximumForFastSteps) {
  CpuCheckPacer pacer;
  EXPECT_EQ(pacer.Chunk(1000), 1);
  pacer.Start();
  pacer.Finish(1'000'000'000);  // a billion steps in no time at all
  EXPECT_EQ(pacer.Chunk(1000), CpuCheckPacer::kMaxSteps);
  EXPECT_EQ(pacer.Chunk(7), 7) << "never more than the step budget left";
  EXPECT_EQ(pacer.Chunk(0), 1) << "at least one step";
}

TEST(CpuCheckPacerTest, ChecksAfterEveryStepWhenAStepTakesLongerThanTheInterval) {
  CpuCheckPacer pacer;
  pacer.Start();
  pacer.Finish(1'000'000'000);
  pacer.Start();
  BurnCpu(2 * CpuCheckPacer::kInterval_s);  // one step of 20 ms
  pacer.Finish(1);
  EXPECT_EQ(pacer.Chunk(1000), 1);
}

TEST(CpuCheckPacerTest, ZeroStepsLeaveTheChunkAsItWas) {
  CpuCheckPacer pacer;
  pacer.Start();
  pacer.Finish(1'000'000'000);
  pacer.Start();
  BurnCpu(2 * CpuCheckPacer::kInterval_s);
  pacer.Finish(0);
  EXPECT_EQ(pacer.Chunk(1000), CpuCheckPacer::kMaxSteps);
}

// An oscillator whose right-hand side costs 1 ms of CPU per call.
class SlowOscillator : public testing::HarmonicOscillator {
 public:
  SlowOscillator() : HarmonicOscillator(2.0) {}
  int Rhs(double t, const double* y, double* ydot) override {
    BurnCpu(1e-3);
    return HarmonicOscillator::Rhs(t, y, ydot);
  }
};

// A budget of 50 ms with steps of at least 1 ms each: every method stops with kTooMuchWork
// long before the 256 steps a fixed check interval took (the pacer's chunks are at most
// 10 steps here, so at most 50 + 10 steps run).
TEST(CpuCheckPacerTest, SlowStepsStopNearTheCpuBudget) {
  for (Method method : {Method::kBdf, Method::kErk, Method::kRk4}) {
    SlowOscillator ode;
    double y[2] = {1.0, 0.0};
    IntegratorOptions options;
    options.method = method;
    options.rtol = 1e-10;
    options.atol = 1e-12;
    options.fixed_step = 1e-3;
    options.cpu_deadline_s = ThreadCpuSeconds() + 0.05;
    std::unique_ptr<Integrator> integrator = MakeIntegrator(ode, 0.0, y, options);
    const AdvanceResult result = integrator->AdvanceTo(1000.0, y);
    EXPECT_EQ(result.status, IntegratorStatus::kTooMuchWork) << MethodName(method);
    EXPECT_LT(integrator->stats().steps, 100) << MethodName(method);
    EXPECT_GT(integrator->stats().steps, 0) << MethodName(method);
  }
}

}  // namespace
}  // namespace mbstream
