// MakeIntegrator's refusals, the table names, and the integrators' names.
#include <cstdio>
#include <string>

#include <arkode/arkode_butcher_dirk.h>
#include <arkode/arkode_butcher_erk.h>
#include <gtest/gtest.h>

#include "server/integrate/butcher_tables.h"
#include "server/integrate/integrator.h"
#include "shared/common/check.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::HarmonicOscillator;
using testing::Options;
using testing::StiffRelaxation;

// The InputError message of MakeIntegrator, or "" if it does not throw.
std::string InputErrorOf(OdeSystem& system, const IntegratorOptions& options,
                         double y0_value = 1.0) {
  const double y0[2] = {y0_value, 0.0};
  try {
    MakeIntegrator(system, 0.0, y0, options);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(OptionsTest, UnknownErkTableListsTheAcceptedNames) {
  HarmonicOscillator system(1.0);
  IntegratorOptions options = Options(Method::kErk, 1.0);
  options.erk_table = "runge";
  const std::string message = InputErrorOf(system, options);
  EXPECT_TRUE(Contains(message, "'runge'")) << message;
  for (const char* name : {"dormand-prince", "verner", "fehlberg", "bogacki-shampine",
                           "ARKODE_DORMAND_PRINCE_7_4_5"}) {
    EXPECT_TRUE(Contains(message, name)) << message;
  }
}

TEST(OptionsTest, UnknownDirkTableListsTheAcceptedNames) {
  HarmonicOscillator system(1.0);
  IntegratorOptions options = Options(Method::kDirk, 1.0);
  options.erk_table = "verner";  // an explicit table
  const std::string message = InputErrorOf(system, options);
  EXPECT_TRUE(Contains(message, "sdirk")) << message;
  EXPECT_TRUE(Contains(message, "kvaerno")) << message;
}

TEST(OptionsTest, TableNamesAreCaseInsensitive) {
  EXPECT_EQ(FindErkTable("Verner").id, ARKODE_VERNER_8_5_6);
  EXPECT_EQ(FindErkTable("arkode_fehlberg_13_7_8").id, ARKODE_FEHLBERG_13_7_8);
  EXPECT_EQ(FindErkTable("").id, ARKODE_DORMAND_PRINCE_7_4_5);
  EXPECT_EQ(FindDirkTable("").id, ARKODE_KVAERNO_5_3_4);
  EXPECT_EQ(FindDirkTable("sdirk").id, ARKODE_SDIRK_5_3_4);
  EXPECT_EQ(FindDirkTable("TRBDF2").id, ARKODE_TRBDF2_3_3_2);
}

TEST(OptionsTest, TablesMatchArkode) {
  for (const ButcherTableInfo& info : ErkTables()) {
    ARKodeButcherTable table = ARKodeButcherTable_LoadERK(static_cast<ARKODE_ERKTableID>(info.id));
    ASSERT_NE(table, nullptr) << info.arkode_name;
    EXPECT_EQ(table->q, info.order) << info.arkode_name;
    EXPECT_GT(table->p, 0) << info.arkode_name << " has no embedding";
    EXPECT_EQ(&FindErkTable(info.arkode_name), &info);
    ARKodeButcherTable_Free(table);
  }
  for (const ButcherTableInfo& info : DirkTables()) {
    ARKodeButcherTable table =
        ARKodeButcherTable_LoadDIRK(static_cast<ARKODE_DIRKTableID>(info.id));
    ASSERT_NE(table, nullptr) << info.arkode_name;
    EXPECT_EQ(table->q, info.order) << info.arkode_name;
    EXPECT_GT(table->p, 0) << info.arkode_name << " has no embedding";
    EXPECT_EQ(&FindDirkTable(info.arkode_name), &info);
    ARKodeButcherTable_Free(table);
  }
}

TEST(OptionsTest, EulerNeedsASecondOrderSystem) {
  StiffRelaxation system;
  IntegratorOptions options = Options(Method::kEuler, 1.0);
  const std::string message = InputErrorOf(system, options);
  EXPECT_TRUE(Contains(message, "second-order")) << message;
  EXPECT_TRUE(Contains(message, "rk4")) << message;
}

TEST(OptionsTest, IdaIsNotAnOdeMethod) {
  HarmonicOscillator system(1.0);
  const std::string message = InputErrorOf(system, Options(Method::kIda, 1.0));
  EXPECT_TRUE(Contains(message, "DAE")) << message;  // which formulation: ValidateRun says
  EXPECT_TRUE(Contains(message, "bdf")) << message;
}

TEST(OptionsTest, InvalidOptionsAreRefused) {
  HarmonicOscillator system(1.0);
  IntegratorOptions options = Options(Method::kBdf, 1.0);
  options.rtol = 0.0;
  EXPECT_TRUE(Contains(InputErrorOf(system, options), "rtol")) << InputErrorOf(system, options);
  options = Options(Method::kRk4, 1.0);
  options.fixed_step = -1.0;
  EXPECT_TRUE(Contains(InputErrorOf(system, options), "fixed_step"));
  options = Options(Method::kBdf, 1.0);
  options.erk_table = "verner";
  EXPECT_TRUE(Contains(InputErrorOf(system, options), "only to methods erk and dirk"));
  options = Options(Method::kBdf, 0.0);
  EXPECT_TRUE(Contains(InputErrorOf(system, options), "t_final"));
  options = Options(Method::kBdf, 1.0);
  options.max_steps = 0;
  EXPECT_TRUE(Contains(InputErrorOf(system, options), "max_steps"));
  EXPECT_TRUE(Contains(InputErrorOf(system, Options(Method::kBdf, 1.0), NAN), "not finite"));
}

TEST(OptionsTest, IntegratorsNameThemselves) {
  HarmonicOscillator system(1.0);
  const double y0[2] = {1.0, 0.0};
  const std::pair<Method, const char*> expected[] = {
      {Method::kBdf, "CVODE BDF"},
      {Method::kAdams, "CVODE Adams"},
      {Method::kErk, "ARKODE ERK (Dormand-Prince 7-4-5)"},
      {Method::kDirk, "ARKODE DIRK (Kvaerno 5-3-4)"},
      {Method::kRk4, "fixed-step RK4"},
      {Method::kEuler, "fixed-step semi-implicit Euler"},
  };
  for (const auto& [method, name] : expected) {
    EXPECT_STREQ(MakeIntegrator(system, 0.0, y0, Options(method, 1.0))->name(), name);
  }
  IntegratorOptions options = Options(Method::kErk, 1.0);
  options.erk_table = "verner";
  EXPECT_STREQ(MakeIntegrator(system, 0.0, y0, options)->name(), "ARKODE ERK (Verner 8-5-6)");
}

}  // namespace
}  // namespace mbstream
