// The body-coordinate formulations with closed loops (server/body/body_cuts.h): the cut
// joint is one more joint between two bodies, its dependent rows dropped. Each formulation
// against the joint-space run of the same linkage (every joint of the file, the cut joints'
// coordinates included), energy conservation and the constraint residual; body-index3
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "server/parse/sdf_import.h"
#include "server/sim/loop_run.h"
#include "shared/common/check.h"

namespace mbstream {
namespace {

const std::string kLinkages = std::string(MBSTREAM_SOURCE_DIR) + "/models/linkages/";

RunConfig Passive(int n, double duration) {
  RunConfig config;
  config.duration = duration;
  config.output_interval = 0.01;
  config.drives.assign(n, DriveConfig{});
  config.rtol = 1e-10;
  config.atol = 1e-12;
  return config;
}

RunConfig Body(RunConfig config, Formulation formulation, double rtol) {
  config.formulation = formulation;
  config.method = formulation == Formulation::kBodyBaumgarte ? Method::kBdf : Method::kIda;
  config.rtol = rtol;
  config.atol = 1e-2 * rtol;
  return config;
}

// Largest difference of the joint coordinates (angles modulo 2 pi) over every frame.
double LargestDifference(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.q.size(), b.q.size());
  double worst = 0.0;
  for (size_t i = 0; i < std::min(a.q.size(), b.q.size()); ++i) {
    worst = std::max(worst, std::abs(std::remainder(a.q[i] - b.q[i], 2.0 * M_PI)));
  }
  return worst;
}

struct Case {
  const char* file;
  double qd0_crank;  // rad/s (the rest follows from the loop)
};

// Released at rest (four-bar) or spun (slider-crank) for 2 s. The reference is the joint-space
// run at rtol 1e-10. The body runs' global error follows their rtol (measured, docs/accuracy.md
// "Closed loops": 4e-3 rad at rtol 1e-6, 1e-4 at 1e-8, 1e-6 at 1e-10, about 2e3 to 2e4 times
// rtol over the 2 s): at rtol 1e-9 they agree to 5e-5 rad or m (measured up to 2e-5), and
// the error falls by more than 30 from rtol 1e-7 to 1e-10, so it is the integration's, not a
// different mechanism's. Energy error (J) within 1e3 rtol (measured up to 3e-7) and the
// loops' residual within the tolerance's promise (10 rtol m: measured 4e-9 m).
TEST(BodyLoopTest, BodyIndex2AndBaumgarteAgreeWithTheJointSpaceRun) {
  for (const Case c : {Case{"four_bar.sdf", 0.0}, Case{"slider_crank.sdf", 6.0}}) {
    const SdfImport sdf = ImportSdfFile(kLinkages + c.file);
    RunConfig joint = Passive(3, 2.0);
    joint.qd0 = Eigen::Vector3d(c.qd0_crank, 0.0, 0.0);
    const RunResult reference = SimulateLoops(sdf.model, sdf.loops, joint);
    ASSERT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
    for (Formulation f : {Formulation::kBodyIndex2, Formulation::kBodyBaumgarte}) {
      SCOPED_TRACE(std::string(c.file) + " " + FormulationName(f));
      const RunResult body = SimulateLoops(sdf.model, sdf.loops, Body(joint, f, 1e-9));
      ASSERT_EQ(body.stats.status, RunStatus::kFinished) << body.stats.message;
      EXPECT_EQ(body.stats.formulation, FormulationName(f));
      EXPECT_NE(body.stats.formulation_reason.find("5 loop equation(s), 2 independent"),
                std::string::npos)
          << body.stats.formulation_reason;
      EXPECT_EQ(body.stats.trust, Trust::kOk) << body.stats.trust_reason;
      EXPECT_EQ(body.joint_names, reference.joint_names);  // the cut joint's column too
      EXPECT_EQ(body.num_dofs, 4);
      const double difference = LargestDifference(body, reference);
      EXPECT_LT(difference, 5e-5);
      EXPECT_LT(body.stats.energy_error_max, 1e-6);
      EXPECT_LT(body.stats.drift_position_max, 1e-8);
      EXPECT_LT(body.stats.drift_velocity_max, 1e-6);

      const RunResult loose = SimulateLoops(sdf.model, sdf.loops, Body(joint, f, 1e-7));
      const RunResult tight = SimulateLoops(sdf.model, sdf.loops, Body(joint, f, 1e-10));
      ASSERT_EQ(loose.stats.status, RunStatus::kFinished) << loose.stats.message;
      ASSERT_EQ(tight.stats.status, RunStatus::kFinished) << tight.stats.message;
      EXPECT_GT(LargestDifference(loose, reference), 30.0 * LargestDifference(tight, reference));
    }
  }
}

// The Delta: five ball joints closing three chains (15 rows, all independent), released
// under gravity for 0.1 s, body-index2 against the joint-space run.
TEST(BodyLoopTest, TheDeltasBallJointsCloseInBodyCoordinates) {
  const SdfImport sdf = ImportSdfFile(kLinkages + "delta.sdf");
  const int n = sdf.model.num_dofs();
  const RunConfig joint = Passive(n, 0.1);
  const RunResult reference = SimulateLoops(sdf.model, sdf.loops, joint);
  ASSERT_EQ(reference.stats.status, RunStatus::kFinished) << reference.stats.message;
  const RunResult body =
      SimulateLoops(sdf.model, sdf.loops, Body(joint, Formulation::kBodyIndex2, 1e-9));
  ASSERT_EQ(body.stats.status, RunStatus::kFinished) << body.stats.message;
  EXPECT_LT(LargestDifference(body, reference), 1e-7);  // measured 1e-9
  EXPECT_LT(body.stats.drift_position_max, 1e-8);
}

TEST(BodyLoopTest, BodyIndex3IsRefusedSayingWhatToUse) {
  const SdfImport sdf = ImportSdfFile(kLinkages + "four_bar.sdf");
  try {
    ValidateLoopRun(sdf.model, sdf.loops, Body(Passive(3, 1.0), Formulation::kBodyIndex3, 1e-8));
    ADD_FAILURE() << "body-index3 accepted";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("formulation body-index3 does not close kinematic loops"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("body-index2 (method ida) or body-baumgarte (method bdf)"),
              std::string::npos)
        << message;
  }
}

TEST(BodyLoopTest, AFixedCutJointIsRefusedNamingItsLine) {
  SdfImport sdf = ImportSdfFile(kLinkages + "four_bar.sdf");
  sdf.loops[0].type = LoopJointType::kFixed;
  try {
    ValidateLoopRun(sdf.model, sdf.loops, Body(Passive(3, 1.0), Formulation::kBodyIndex2, 1e-8));
    ADD_FAILURE() << "a fixed cut joint accepted";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(sdf.loops[0].where + ": joint 'loop_joint' (fixed)"), std::string::npos)
        << message;
    EXPECT_NE(message.find("use formulation joint"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace mbstream
