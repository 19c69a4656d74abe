// A run that continues a pilot (PilotLink, beside its RunConfig: run_prefix.h): it takes the
// pilot's frames as its own and the pilot's integration over, going on at its own tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "server/sim/joint_integration.h"
#include "server/sim/run_prefix.h"
#include "server/sim/simulate.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

RunConfig At(RunConfig config, double duration, double rtol) {
  config.duration = duration;
  config.rtol = rtol;
  config.atol = rtol / 100.0;
  return config;
}

// A pilot of `scene` over [0, span] at `rtol`, kept for continuing.
std::shared_ptr<RunPrefix> Pilot(const RunConfig& scene, double span, double rtol) {
  RunResult result = SimulateTree(Irb1600(), At(scene, span, rtol), nullptr, nullptr,
                                  PilotLink{nullptr, /*keep_integration=*/true});
  EXPECT_EQ(result.stats.status, RunStatus::kFinished) << result.stats.message;
  EXPECT_NE(result.integration, nullptr);
  return MakePrefix(result, rtol, "bdf");
}

double LargestJointDistance(const RunResult& a, const RunResult& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.q.size(); ++i) d = std::max(d, std::abs(a.q[i] - b.q[i]));
  return d;
}

TEST(RunPrefixTest, ARunTakesThePilotsFramesAndGoesOnFromItsIntegration) {
  const RunConfig scene = Scene("stiff-servo");  // 2 s, frames every 0.01 s
  std::shared_ptr<RunPrefix> pilot = Pilot(scene, 0.1, 1e-9);
  ASSERT_EQ(pilot->frames(), 11u);
  const RunConfig config = At(scene, 2.0, 1e-6);
  const RunResult continued = SimulateTree(Irb1600(), config, nullptr, nullptr, {pilot});
  ASSERT_EQ(continued.stats.status, RunStatus::kFinished) << continued.stats.message;
  EXPECT_DOUBLE_EQ(continued.stats.continued_from_s, 0.1);
  EXPECT_FALSE(pilot->HasIntegration());  // taken: no other run can go on from it
  ASSERT_EQ(continued.num_frames(), 201);
  // The first 11 frames are the pilot's, bit for bit.
  for (size_t k = 0; k < 11 * 6; ++k) {
    ASSERT_EQ(continued.q[k], pilot->q[k]) << k;
    ASSERT_EQ(continued.qd[k], pilot->qd[k]) << k;
  }
  // The rest at the run's own tolerance: as close to a tight run as a run from t = 0 at that
  // tolerance is, and cheaper (no second start at order 1 with tiny steps).
  const RunResult fresh = SimulateTree(Irb1600(), At(scene, 2.0, 1e-6));
  const RunResult reference = SimulateTree(Irb1600(), At(scene, 2.0, 1e-11));
  const double fresh_error = LargestJointDistance(fresh, reference);
  EXPECT_LT(LargestJointDistance(continued, reference), 3.0 * fresh_error + 1e-12);
  EXPECT_LT(continued.stats.solver.steps, fresh.stats.solver.steps)
      << continued.stats.solver.steps << " vs " << fresh.stats.solver.steps;
  EXPECT_GT(continued.stats.solver.steps, 0);
  // The energy balance goes on across the join (E(0) is the pilot's first frame).
  EXPECT_LT(continued.stats.energy_error_max, 10.0 * fresh.stats.energy_error_max + 1e-9);

  // The integration is gone: a second run with the same prefix starts at t = 0.
  const RunResult again = SimulateTree(Irb1600(), config, nullptr, nullptr, {pilot});
  EXPECT_DOUBLE_EQ(again.stats.continued_from_s, 0.0);
  EXPECT_EQ(again.stats.solver.steps, fresh.stats.solver.steps);
}

TEST(RunPrefixTest, IntegratedWorkGoesOnAcrossTheJoin) {
  // Damping: the work of drives and damping is a quadrature of the ODE.
  Model damped = Irb1600();
  for (Body& body : damped.bodies) body.joint.damping = 5.0;
  RunConfig scene = At(Scene("seed-servo"), 4.0, 1e-8);
  RunResult pilot_result = SimulateTree(damped, At(scene, 1.0, 1e-10), nullptr, nullptr,
                                        PilotLink{nullptr, /*keep_integration=*/true});
  ASSERT_EQ(pilot_result.stats.status, RunStatus::kFinished);
  ASSERT_EQ(pilot_result.work.size(), pilot_result.t.size());
  const PilotLink pilot{MakePrefix(pilot_result, 1e-10, "bdf")};
  const RunResult continued = SimulateTree(damped, scene, nullptr, nullptr, pilot);
  const RunResult fresh = SimulateTree(damped, scene);
  ASSERT_EQ(continued.stats.status, RunStatus::kFinished);
  EXPECT_DOUBLE_EQ(continued.stats.continued_from_s, 1.0);
  EXPECT_EQ(continued.stats.energy_work, fresh.stats.energy_work);
  ASSERT_EQ(continued.work.size(), fresh.work.size());
  // The work after the join counts from t = 0, not from the join.
  const double scale = std::abs(fresh.work.back()) + 1e-300;
  EXPECT_NEAR(continued.work.back(), fresh.work.back(), 1e-5 * scale);
  EXPECT_LT(continued.stats.energy_error_max, 10.0 * fresh.stats.energy_error_max + 1e-9);
}

TEST(RunPrefixTest, APrefixThatIsNotTheRunsStartIsNotTaken) {
  const RunConfig scene = Scene("stiff-servo");
  {  // other output times: a pilot with frames every 0.005 s
    RunConfig pilot = At(scene, 0.1, 1e-9);
    pilot.output_interval = 0.005;
    RunResult result = SimulateTree(Irb1600(), pilot, nullptr, nullptr,
                                    PilotLink{nullptr, /*keep_integration=*/true});
    const RunConfig config = At(scene, 2.0, 1e-6);
    const PilotLink link{MakePrefix(result, 1e-9, "bdf")};
    EXPECT_DOUBLE_EQ(SimulateTree(Irb1600(), config, nullptr, nullptr, link).stats.continued_from_s,
                     0.0);
    EXPECT_TRUE(link.prefix->HasIntegration());
  }
  {  // another method: the integration refuses, and stays for a run it fits
    RunConfig config = At(scene, 2.0, 1e-6);
    config.method = Method::kDirk;
    const PilotLink link{Pilot(scene, 0.1, 1e-9)};
    const RunResult result = SimulateTree(Irb1600(), config, nullptr, nullptr, link);
    EXPECT_EQ(result.stats.status, RunStatus::kFinished);
    EXPECT_DOUBLE_EQ(result.stats.continued_from_s, 0.0);
    EXPECT_TRUE(link.prefix->HasIntegration());
    config.method = Method::kBdf;
    EXPECT_DOUBLE_EQ(SimulateTree(Irb1600(), config, nullptr, nullptr, link).stats.continued_from_s,
                     0.1);
  }
  {  // a pilot that was not kept has no integration
    RunResult result = SimulateTree(Irb1600(), At(scene, 0.1, 1e-9));
    EXPECT_EQ(result.integration, nullptr);
    const PilotLink link{MakePrefix(result, 1e-9, "bdf")};
    EXPECT_DOUBLE_EQ(SimulateTree(Irb1600(), At(scene, 2.0, 1e-6), nullptr, nullptr, link)
                         .stats.continued_from_s,
                     0.0);
  }
}

}  // namespace
}  // namespace mbstream
