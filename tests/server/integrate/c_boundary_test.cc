// No exception crosses SUNDIALS' C frames: a model that throws inside a right-hand side,
// Jacobian or residual callback ends the run with a failure status whose message keeps the
// exception's, for every method.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "server/integrate/ida_integrator.h"
#include "server/integrate/integrator.h"
#include "shared/common/check.h"
#include "tests/server/integrate/test_systems.h"

namespace mbstream {
namespace {

using testing::HarmonicOscillator;
using testing::Options;

constexpr char kWhat[] = "a check inside the model failed: mass matrix not positive definite";

// A harmonic oscillator whose right-hand side (or, with `in_jacobian`, its own Jacobian)
// throws from t_fail on, as a check inside ABA would.
class ThrowingOscillator : public HarmonicOscillator {
 public:
  ThrowingOscillator(double t_fail, bool in_jacobian)
      : HarmonicOscillator(1.0, /*with_jacobian=*/in_jacobian),
        t_fail_(t_fail),
        in_jacobian_(in_jacobian) {}
  int Rhs(double t, const double* y, double* ydot) override {
    if (!in_jacobian_ && t >= t_fail_) throw InternalError(kWhat);
    return HarmonicOscillator::Rhs(t, y, ydot);
  }
  int Jacobian(double t, const double* y, const double* fy, double* jac) override {
    if (in_jacobian_ && t >= t_fail_) throw std::runtime_error(kWhat);
    return HarmonicOscillator::Jacobian(t, y, fy, jac);
  }

 private:
  double t_fail_;
  bool in_jacobian_;
};

// The oscillator as a DAE for IDA: F = [x' - v; v' + x], whose residual throws from t_fail.
class ThrowingOscillatorDae : public testing::OscillatorDae {
 public:
  explicit ThrowingOscillatorDae(double t_fail) : t_fail_(t_fail) {}
  int Residual(double t, const double* y, const double* yp, double* r) override {
    if (t >= t_fail_) throw InternalError(kWhat);
    return OscillatorDae::Residual(t, y, yp, r);
  }

 private:
  double t_fail_;
};

// Advances in outputs of 0.1 s up to 2 s until a failure; returns it.
AdvanceResult RunUntilFailure(Integrator& integrator, double* y) {
  AdvanceResult result;
  for (int k = 1; k <= 20; ++k) {
    result = integrator.AdvanceTo(0.1 * k, y);
    if (result.status != IntegratorStatus::kOk) break;
  }
  return result;
}

TEST(CBoundaryTest, ARightHandSideThatThrowsFailsEveryMethodWithItsMessage) {
  for (Method method :
       {Method::kBdf, Method::kAdams, Method::kErk, Method::kDirk, Method::kRk4, Method::kEuler}) {
    ThrowingOscillator system(/*t_fail=*/0.5, /*in_jacobian=*/false);
    const double y0[2] = {1.0, 0.0};
    IntegratorOptions options = Options(method, 2.0);
    options.fixed_step = 0.01;
    auto integrator = MakeIntegrator(system, 0.0, y0, options);
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, y);
    EXPECT_EQ(result.status, IntegratorStatus::kRhsFailure) << integrator->name();
    EXPECT_NE(result.message.find(kWhat), std::string::npos) << result.message;
    EXPECT_LE(result.t, 0.5) << integrator->name();
    // Later calls report the same failure.
    EXPECT_EQ(integrator->AdvanceTo(2.0, y).status, IntegratorStatus::kRhsFailure);
  }
}

TEST(CBoundaryTest, AJacobianThatThrowsFailsWithItsMessage) {
  for (Method method : {Method::kBdf, Method::kDirk}) {
    // The Jacobian is evaluated seldom: from the first evaluation on.
    ThrowingOscillator system(/*t_fail=*/0.0, /*in_jacobian=*/true);
    const double y0[2] = {1.0, 0.0};
    auto integrator = MakeIntegrator(system, 0.0, y0, Options(method, 2.0));
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, y);
    EXPECT_EQ(result.status, IntegratorStatus::kRhsFailure) << integrator->name();
    EXPECT_NE(result.message.find(kWhat), std::string::npos) << result.message;
  }
}

TEST(CBoundaryTest, AResidualThatThrowsFailsIdaWithItsMessage) {
  for (const auto solver : {IdaOptions::LinearSolver::kKlu, IdaOptions::LinearSolver::kDense}) {
    ThrowingOscillatorDae system(/*t_fail=*/0.5);
    const double y0[2] = {1.0, 0.0}, yp0[2] = {0.0, -1.0};
    IdaOptions options;
    options.base = Options(Method::kIda, 2.0);
    options.linear_solver = solver;
    auto integrator = MakeIdaIntegrator(system, 0.0, y0, yp0, options);
    double y[2];
    const AdvanceResult result = RunUntilFailure(*integrator, y);
    EXPECT_NE(result.status, IntegratorStatus::kOk);
    EXPECT_NE(result.message.find(kWhat), std::string::npos) << result.message;
    EXPECT_LE(result.t, 0.5);
  }
}

}  // namespace
}  // namespace mbstream
