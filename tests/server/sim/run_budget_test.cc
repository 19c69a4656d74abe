// Run budgets, input sanity warnings and the trust flag: a typo ends within its budget with a
// message that names it, every shipped scene finishes well inside its default budget with
// trust ok, and a deliberately coarse step is flagged untrusted.
#include "server/sim/run_budget.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "server/drives/drive_set.h"
#include "server/engine/engine.h"
#include "server/integrate/cpu_check_pacer.h"
#include "server/integrate/integrator.h"
#include "server/integrate/thread_cpu_clock.h"
#include "server/runs/run_budget_caps.h"
#include "server/sim/initial_state.h"
#include "server/sim/input_sanity.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/joint_space_ode.h"
#include "server/sim/run_trust.h"
#include "server/spec/run_spec_json.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/sanitized_build.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::HasSubstr;
using testing::Irb1600;
using ::testing::Not;
using testing::Scene;

RunConfig TypoSpec() {
  std::vector<std::string> joints;
  for (const Body& body : Irb1600().bodies) joints.push_back(body.joint.name);
  const std::string path = "tests/data/typo-servo.json";
  return ToRunConfig(LoadRunSpecFile(path), joints, path);
}

TEST(RunBudgetTest, DefaultsScaleWithDurationAndModelSize) {
  EXPECT_EQ(DefaultMaxSteps(0.5), 100'000);
  EXPECT_EQ(DefaultMaxSteps(20.0), 2'050'000);
  EXPECT_DOUBLE_EQ(DefaultMaxCpuSeconds(0.5, 6), 70.0);
  EXPECT_DOUBLE_EQ(DefaultMaxCpuSeconds(20.0, 6), 460.0);
  EXPECT_DOUBLE_EQ(DefaultMaxCpuSeconds(20.0, 3), 460.0);         // small models: as for 6
  EXPECT_DOUBLE_EQ(DefaultMaxCpuSeconds(20.0, 12), 60.0 + 1600);  // (12 / 6)^2 = 4

  RunConfig config = Scene("seed-servo");
  ResolveBudget(6, &config);
  EXPECT_EQ(config.max_steps, DefaultMaxSteps(20.0));
  EXPECT_DOUBLE_EQ(config.max_cpu_s, DefaultMaxCpuSeconds(20.0, 6));
  config.max_steps = 17;
  config.max_cpu_s = 2.5;
  ResolveBudget(6, &config);  // explicit values are kept
  EXPECT_EQ(config.max_steps, 17);
  EXPECT_DOUBLE_EQ(config.max_cpu_s, 2.5);
}

// The typo: kp = 123456789012345678901234567890 on joint3 and omega 0 on joint5 of
// seed-servo, 0.5 s. It used to take 4.8 million steps and 73 s of CPU and end FINISHED.
TEST(RunBudgetTest, TypoSpecEndsWithinItsBudgetNamingTheGain) {
  RunConfig config = TypoSpec();
  ASSERT_EQ(config.max_steps, 0);  // the spec asks for the default budget
  // Under a sanitizer a step of this stiff run costs about 2.5 ms of CPU, not 27 us: the
  // default CPU budget (70 s) would run out before the default 100,000 steps. There the test
  // asks for 5,000 steps, so that the step budget is still the one that runs out.
  const int steps = testing::kSanitizedBuild ? 5'000 : DefaultMaxSteps(0.5);
  if (testing::kSanitizedBuild) config.max_steps = steps;
  const RunResult result = Simulate(Irb1600(), config);
  const RunStats& s = result.stats;
  EXPECT_EQ(s.status, RunStatus::kTooMuchWork);
  EXPECT_EQ(s.max_steps, steps);
  EXPECT_EQ(s.solver.steps, steps);  // the step budget ran out, not the CPU
  EXPECT_THAT(s.message,
              HasSubstr("budget exhausted: " + std::to_string(steps) + " internal steps"));
  EXPECT_THAT(s.message, HasSubstr("steps per simulated second"));
  EXPECT_THAT(s.message, HasSubstr("likely cause: pd_servo.kp = 1.23457e+29 on joint 3 'joint3'"));
  EXPECT_THAT(s.message, HasSubstr("looks like a typo"));
  EXPECT_THAT(s.message, HasSubstr("the frames up to the stop are kept"));
  EXPECT_EQ(s.trust, Trust::kNotAssessed);
  // The frames it made are kept: at least the first.
  EXPECT_GE(result.num_frames(), 1);
  EXPECT_DOUBLE_EQ(result.t.front(), 0.0);
  // Both typos are warned about, naming field and value.
  EXPECT_THAT(s.warnings, Contains(AllOf(HasSubstr("pd_servo.kp = 1.23457e+29"),
                                         HasSubstr("closed-loop frequency"))));
  EXPECT_THAT(s.warnings,
              Contains(AllOf(HasSubstr("pd_servo.trajectory term 1 on joint 5 'joint5'"),
                             HasSubstr("omega = 0"))));
}

TEST(RunBudgetTest, WarningsComeBeforeAnyIntegration) {
  const std::vector<InputWarning> warnings = CheckInputSanity(Irb1600(), TypoSpec());
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0].message, HasSubstr("pd_servo.kp = 1.23457e+29 on joint 3 'joint3'"));
  EXPECT_GT(warnings[0].rate, 1e13);  // sqrt(1.2e29 / 12.7 kg*m^2) = 9.9e13 rad/s
  EXPECT_THAT(warnings[1].message, HasSubstr("omega = 0"));
}

TEST(RunBudgetTest, ShippedScenesHaveNoWarnings) {
  for (const char* name : {"seed-run", "seed-servo", "passive-swing", "stiff-servo"}) {
    EXPECT_TRUE(CheckInputSanity(Irb1600(), Scene(name)).empty()) << name;
  }
}

TEST(RunBudgetTest, AbsurdMassAndLengthAreWarned) {
  Model model = Irb1600();
  model.bodies[2].inertia.mass *= 1e9;  // t for kg, and then some
  model.bodies[3].joint.X_PJ.p *= 1e6;  // mm for m, and then some
  const std::vector<InputWarning> warnings = CheckInputSanity(model, Scene("passive-swing"));
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_THAT(warnings[0].message, AllOf(HasSubstr("link '" + model.bodies[2].name + "' has mass"),
                                         HasSubstr("orders of magnitude")));
  EXPECT_THAT(warnings[1].message,
              AllOf(HasSubstr("joint 'joint4' has its origin"), HasSubstr("orders of magnitude")));
}

// Every shipped scene finishes with trust ok, using at most a tenth of its default steps.
TEST(RunBudgetTest, ShippedScenesFinishTrustedWellInsideTheirBudget) {
  for (const char* name : {"seed-run", "seed-servo", "passive-swing", "stiff-servo"}) {
    const RunConfig config = Scene(name);
    const RunResult result = Simulate(Irb1600(), config);
    const RunStats& s = result.stats;
    ASSERT_EQ(s.status, RunStatus::kFinished) << name << ": " << s.message;
    EXPECT_EQ(s.trust, Trust::kOk) << name << ": " << s.trust_reason;
    EXPECT_TRUE(s.trust_reason.empty()) << name;
    EXPECT_LE(s.solver.steps * 10, DefaultMaxSteps(config.duration)) << name;
    EXPECT_TRUE(s.warnings.empty()) << name;
  }
}

// The seed's motion integrated (velocity sources) and the body formulations: trusted too.
TEST(RunBudgetTest, IntegratedSeedAndBodyFormulationsAreTrusted) {
  RunConfig seed = Scene("seed-run");
  seed.formulation = Formulation::kJoint;
  const RunResult joint = Simulate(Irb1600(), seed);
  ASSERT_EQ(joint.stats.status, RunStatus::kFinished) << joint.stats.message;
  EXPECT_EQ(joint.stats.trust, Trust::kOk) << joint.stats.trust_reason;

  RunConfig body = Scene("passive-swing");
  body.duration = 2.0;
  body.formulation = Formulation::kBodyBaumgarte;
  body.rtol = 1e-8;
  body.atol = 1e-10;
  const RunResult baumgarte = Simulate(Irb1600(), body);
  ASSERT_EQ(baumgarte.stats.status, RunStatus::kFinished) << baumgarte.stats.message;
  EXPECT_EQ(baumgarte.stats.trust, Trust::kOk) << baumgarte.stats.trust_reason;
}

// A scene built to fail the energy balance: passive-swing (no work done: energy must be
// conserved) with a deliberately coarse fixed step of semi-implicit Euler. It finishes, but
// untrusted.
TEST(RunBudgetTest, CoarseFixedStepFinishesWithTrustLow) {
  RunConfig config = Scene("passive-swing");
  config.method = Method::kEuler;
  config.fixed_step = 0.01;
  const RunResult result = Simulate(Irb1600(), config);
  const RunStats& s = result.stats;
  ASSERT_EQ(s.status, RunStatus::kFinished) << s.message;
  EXPECT_FALSE(s.energy_work_approximate);
  EXPECT_GT(s.energy_error_max, kTrustEnergyError);
  EXPECT_EQ(s.trust, Trust::kLow);
  EXPECT_THAT(s.trust_reason, HasSubstr("energy balance error"));
  EXPECT_THAT(s.trust_reason, HasSubstr("cannot be trusted"));
}

// The CPU budget, read from the run thread's clock between chunks of steps: every kind of
// integrator (CVODE/ARKODE, fixed step, IDA) stops at it, keeping its frames.
TEST(RunBudgetTest, CpuBudgetStopsEveryKindOfIntegrator) {
  struct Case {
    const char* scene;
    Formulation formulation;
    Method method;
    double fixed_step;
  };
  for (const Case& c : {Case{"stiff-servo", Formulation::kJoint, Method::kErk, 0.0},
                        Case{"passive-swing", Formulation::kJoint, Method::kRk4, 1e-7},
                        Case{"passive-swing", Formulation::kBodyIndex2, Method::kIda, 0.0}}) {
    RunConfig config = Scene(c.scene);
    config.formulation = c.formulation;
    config.method = c.method;
    if (c.fixed_step > 0.0) config.fixed_step = c.fixed_step;
    config.max_steps = 1'000'000'000;  // only the CPU budget can stop it
    config.max_cpu_s = 1e-3;
    const RunResult result = Simulate(Irb1600(), config);
    const RunStats& s = result.stats;
    EXPECT_EQ(s.status, RunStatus::kTooMuchWork) << MethodName(c.method) << ": " << s.message;
    EXPECT_THAT(s.message, HasSubstr("budget exhausted: "));
    EXPECT_THAT(s.message, HasSubstr("s of CPU (max_cpu_s = 0.001 s) used"));
    EXPECT_GE(result.num_frames(), 1) << MethodName(c.method);
    EXPECT_LT(s.t_reached, config.duration) << MethodName(c.method);
  }
}

// With a CPU deadline the SUNDIALS solvers are called in chunks of steps (CpuCheckPacer) and
// the fixed-step loop reads the clock: the solution and the step count are the same bit for
// bit as without, and advancing still allocates nothing.
TEST(RunBudgetTest, CpuChecksLeaveTheSolutionBitForBitAndAllocateNothing) {
  const Model& model = Irb1600();
  const RunConfig scene = Scene("passive-swing");
  const DriveSet drives(model, scene.drives);
  for (Method method : {Method::kBdf, Method::kErk, Method::kRk4}) {
    RunConfig config = scene;
    config.method = method;
    config.rtol = 1e-10;
    config.atol = 1e-12;
    config.fixed_step = 1e-4;
    std::vector<double> states[2];
    long steps[2] = {0, 0};
    for (int budgeted = 0; budgeted < 2; ++budgeted) {
      JointSpaceOde ode(model, drives);
      Eigen::VectorXd y = InitialJointState(config, drives, model.num_dofs());
      const double deadline =
          budgeted ? ThreadCpuSeconds() + 3600.0 : std::numeric_limits<double>::infinity();
      std::unique_ptr<Integrator> integrator =
          MakeIntegrator(ode, 0.0, y.data(), IntegratorOptionsFrom(config, 2.0, deadline));
      ASSERT_EQ(integrator->AdvanceTo(0.5, y.data()).status, IntegratorStatus::kOk);
      const long steps_before = integrator->stats().steps;
      const long allocations = testing::AllocationCount();
      ASSERT_EQ(integrator->AdvanceTo(2.0, y.data()).status, IntegratorStatus::kOk);
      EXPECT_EQ(testing::AllocationCount() - allocations, 0) << MethodName(method);
      steps[budgeted] = integrator->stats().steps;
      EXPECT_GT(steps[budgeted] - steps_before, 2 * CpuCheckPacer::kMaxSteps) << MethodName(method);
      states[budgeted].assign(y.data(), y.data() + y.size());
    }
    EXPECT_EQ(steps[0], steps[1]) << MethodName(method);
    EXPECT_EQ(states[0], states[1]) << MethodName(method);
  }
}

// An explicit method on a stiff scene: the message gives the eigenvalue estimate.
TEST(RunBudgetTest, StiffSceneMessageGivesTheLargestEigenvalue) {
  RunConfig config = Scene("stiff-servo");
  config.method = Method::kErk;
  config.max_steps = 20'000;
  const RunResult result = Simulate(Irb1600(), config);
  const RunStats& s = result.stats;
  ASSERT_EQ(s.status, RunStatus::kTooMuchWork) << s.message;
  EXPECT_THAT(s.message, HasSubstr("budget exhausted: 20000 internal steps"));
  EXPECT_THAT(s.message, HasSubstr("likely cause: the scene is stiff there: the largest "
                                   "eigenvalue of the ODE's Jacobian"));
  EXPECT_THAT(s.message, HasSubstr("use method bdf or dirk"));
}

TEST(RunBudgetTest, TrustFollowsEachIndicator) {
  RunStats s;
  s.solver.steps = 100;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kOk);
  s.drift_position_max = 2e-3;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kLow);
  EXPECT_THAT(s.trust_reason, HasSubstr("constraint drift (m) 0.002 exceeds 0.001"));
  s.drift_position_max = -1.0;
  s.energy_error_max = 0.05;
  s.energy_work_approximate = true;  // looser: the work is a quadrature of the frames
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kOk);
  s.energy_work_approximate = false;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kLow);
  s.energy_error_max = 0.0;
  s.solver.error_test_failures = 150;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kLow);
  EXPECT_THAT(s.trust_reason, HasSubstr("rejected steps per accepted step 1.5"));
  s.status = RunStatus::kDiverged;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kNotAssessed);
  EXPECT_TRUE(s.trust_reason.empty());
}

// Each failed indicator names its own remedy: an energy balance whose work is the trapezoid
// rule over the output frames asks for a smaller output interval, never for tolerances;
// an integrated balance, the TCP error, drift and rejections ask for tolerances or a step.
TEST(RunBudgetTest, TrustNamesTheRemedyOfTheIndicatorThatFailed) {
  RunStats s;
  s.formulation = "body-index2";
  s.solver.steps = 100;
  s.energy_error_max = 0.131;
  s.energy_work_approximate = true;
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kLow);
  EXPECT_THAT(s.trust_reason, HasSubstr("energy balance error 0.131 exceeds 0.1"));
  EXPECT_THAT(s.trust_reason, HasSubstr("use a smaller output_interval_s"));
  EXPECT_THAT(s.trust_reason, HasSubstr("formulation body-index2"));
  EXPECT_THAT(s.trust_reason, Not(HasSubstr("rtol")));
  EXPECT_THAT(s.trust_reason, HasSubstr("or the joint formulation"));
  s.loops.cut_joints = {"j (revolute)"};  // closed loops: no joint formulation to switch to
  AssessTrust(&s);
  EXPECT_THAT(s.trust_reason, HasSubstr("use a smaller output_interval_s"));
  EXPECT_THAT(s.trust_reason, Not(HasSubstr("joint formulation")));
  s.loops.cut_joints.clear();
  s.drift_position_max = 2e-3;  // and an indicator of the integration: both remedies
  AssessTrust(&s);
  EXPECT_THAT(s.trust_reason, HasSubstr("use a smaller output_interval_s"));
  // body-index2's drift grows with time whatever the tolerance (its limit shrinks with the
  // tolerance too, run_trust.h): the remedy is the formulation (issue 42, item 4).
  EXPECT_THAT(s.trust_reason, HasSubstr("use the body-index3 formulation"));
  s.formulation = "joint";  // a drift the tolerance controls: tighten it
  AssessTrust(&s);
  EXPECT_THAT(s.trust_reason, HasSubstr("tighten rtol/atol"));
  s.formulation = "body-index2";
  s.drift_position_max = -1.0;
  s.energy_work_approximate = false;  // the work integrated with the motion
  AssessTrust(&s);
  EXPECT_EQ(s.trust, Trust::kLow);
  EXPECT_THAT(s.trust_reason, HasSubstr("tighten rtol/atol"));
  EXPECT_THAT(s.trust_reason, Not(HasSubstr("output_interval_s")));
}

TEST(RunBudgetTest, ServerCapsClampTheBudgetAndSayWhenTheSpecAskedForMore) {
  ServerLimits limits;
  limits.max_internal_steps = 1000;
  limits.max_run_cpu_s = 5.0;
  RunConfig config = Scene("seed-servo");  // default budget: above both caps, silently capped
  EXPECT_TRUE(PrepareRunBudget(Irb1600(), limits, &config).empty());
  EXPECT_EQ(config.max_steps, 1000);
  EXPECT_DOUBLE_EQ(config.max_cpu_s, 5.0);

  config = Scene("seed-servo");
  config.max_steps = 5000;
  config.max_cpu_s = 100.0;
  const std::vector<std::string> warnings = PrepareRunBudget(Irb1600(), limits, &config);
  EXPECT_EQ(config.max_steps, 1000);
  EXPECT_DOUBLE_EQ(config.max_cpu_s, 5.0);
  EXPECT_THAT(warnings, Contains(HasSubstr("max_internal_steps = 5000 exceeds this server's cap "
                                           "of 1000 steps (mbstream-server --max-run-steps)")));
  EXPECT_THAT(warnings, Contains(HasSubstr("max_cpu_s = 100 s exceeds this server's cap of 5 s "
                                           "(mbstream-server --max-run-cpu-s)")));

  config = TypoSpec();  // the inputs' warnings come with them
  EXPECT_THAT(PrepareRunBudget(Irb1600(), ServerLimits(), &config),
              Contains(HasSubstr("looks like a typo")));
}

}  // namespace
}  // namespace mbstream
