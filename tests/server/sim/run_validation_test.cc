// ValidateRun is the one validation of a run: every combination of formulation, method and
// Butcher table that it accepts runs without an InputError (so no worker fails for a reason
// knowable up front), and each one it refuses says why.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "server/engine/engine.h"
#include "server/sim/integrator_options_from.h"
#include "server/sim/run_validation.h"
#include "shared/common/check.h"
#include "tests/server/sim/scene_fixture.h"

namespace mbstream {
namespace {

using testing::Irb1600;
using testing::Scene;

constexpr Formulation kFormulations[] = {Formulation::kAuto,       Formulation::kKinematic,
                                         Formulation::kJoint,      Formulation::kBodyIndex3,
                                         Formulation::kBodyIndex2, Formulation::kBodyBaumgarte};
constexpr Method kMethods[] = {Method::kBdf, Method::kAdams, Method::kErk,  Method::kDirk,
                               Method::kIda, Method::kRk4,   Method::kEuler};
const char* const kTables[] = {"", "nosuch", "heun-euler", "sdirk2"};

// A short free swing: something to integrate in every formulation.
RunConfig ShortSwing(Formulation formulation, Method method, const std::string& table) {
  RunConfig config = Scene("passive-swing");
  config.duration = 0.02;
  config.output_interval = 0.01;
  config.rtol = 1e-4;
  config.atol = 1e-6;
  config.fixed_step = 1e-3;
  config.formulation = formulation;
  config.method = method;
  config.erk_table = table;
  return config;
}

std::string Describe(const RunConfig& config) {
  return std::string(FormulationName(config.formulation)) + " / " + MethodName(config.method) +
         " / '" + config.erk_table + "'";
}

TEST(RunValidationTest, WhatItAcceptsRunsWithoutAnInputError) {
  int accepted = 0, refused = 0;
  for (Formulation formulation : kFormulations) {
    for (Method method : kMethods) {
      for (const char* table : kTables) {
        const RunConfig config = ShortSwing(formulation, method, table);
        try {
          ValidateRun(Irb1600(), config);
        } catch (const InputError& error) {
          ++refused;
          EXPECT_FALSE(std::string(error.what()).empty()) << Describe(config);
          continue;
        }
        ++accepted;
        try {
          Simulate(Irb1600(), config);  // a numerical failure is a status, not an exception
        } catch (const std::exception& error) {
          ADD_FAILURE() << Describe(config) << " was accepted but failed to run: " << error.what();
        }
      }
    }
  }
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
}

// The requests that failed inside a worker as "internal error:" before the validation.
TEST(RunValidationTest, RefusesWhatOnlyTheWorkerUsedToFind) {
  struct Case {
    Formulation formulation;
    Method method;
    const char* table;
    const char* says;
  };
  const Case cases[] = {
      {Formulation::kJoint, Method::kIda, "", "body-index3 or body-index2"},
      {Formulation::kAuto, Method::kIda, "", "chosen by auto"},
      {Formulation::kJoint, Method::kErk, "nosuch", "nosuch"},
      {Formulation::kJoint, Method::kDirk, "heun-euler", "heun-euler"},
      {Formulation::kJoint, Method::kBdf, "heun-euler", "applies only to methods erk and dirk"},
      {Formulation::kBodyIndex2, Method::kIda, "sdirk2", "applies only to methods erk and dirk"},
      {Formulation::kBodyBaumgarte, Method::kEuler, "", "method euler"},
  };
  for (const Case& c : cases) {
    const RunConfig config = ShortSwing(c.formulation, c.method, c.table);
    try {
      ValidateRun(Irb1600(), config);
      ADD_FAILURE() << Describe(config) << " was accepted";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(c.says), std::string::npos)
          << Describe(config) << ": " << error.what();
    }
  }
}

TEST(RunValidationTest, RefusesABodyFormulationForAMasslessLink) {
  Model model = Irb1600();
  model.bodies[2].inertia.mass = 0.0;
  const RunConfig config = ShortSwing(Formulation::kBodyBaumgarte, Method::kBdf, "");
  EXPECT_THROW(ValidateRun(model, config), InputError);
  EXPECT_NO_THROW(ValidateRun(model, ShortSwing(Formulation::kJoint, Method::kBdf, "")));
}

TEST(RunValidationTest, RefusesADriveCountThatIsNotTheModels) {
  RunConfig config = ShortSwing(Formulation::kJoint, Method::kBdf, "");
  config.drives.pop_back();
  EXPECT_THROW(ValidateRun(Irb1600(), config), InputError);
}

TEST(RunValidationTest, IntegratorOptionsFromRunConfig) {
  RunConfig config;
  config.method = Method::kErk;
  config.erk_table = "verner";
  config.rtol = 1e-7;
  config.max_steps = 42;
  const IntegratorOptions options = IntegratorOptionsFrom(config, 3.0);
  EXPECT_EQ(options.method, Method::kErk);
  EXPECT_EQ(options.erk_table, "verner");
  EXPECT_EQ(options.rtol, 1e-7);
  EXPECT_EQ(options.atol, config.atol);
  EXPECT_EQ(options.max_steps, 42);
  EXPECT_EQ(options.t_final, 3.0);
  EXPECT_STREQ(IntegratorStatusName(IntegratorStatus::kTooMuchWork), "too_much_work");
}

}  // namespace
}  // namespace mbstream
