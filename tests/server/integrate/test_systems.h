// Small ODE systems with known behaviour for the integrator tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "server/integrate/ida_system.h"
#include "server/integrate/integrator.h"
#include "server/integrate/ode_system.h"

namespace mbstream::testing {

// x'' = -w^2 x as y = [x; v]; x(t) = x0 cos(w t) + v0 / w sin(w t).
class HarmonicOscillator : public OdeSystem {
 public:
  explicit HarmonicOscillator(double omega, bool with_jacobian = false)
      : omega_(omega), with_jacobian_(with_jacobian) {}

  int size() const override { return 2; }
  int num_positions() const override { return 1; }
  int Rhs(double t, const double* y, double* ydot) override {
    max_time_seen = std::max(max_time_seen, t);
    ydot[0] = y[1];
    ydot[1] = -omega_ * omega_ * y[0];
    return 0;
  }
  bool HasJacobian() const override { return with_jacobian_; }
  int Jacobian(double /*t*/, const double* /*y*/, const double* /*fy*/, double* jac) override {
    ++jacobian_calls;
    jac[0] = 0.0;               // d x' / d x
    jac[1] = -omega_ * omega_;  // d v' / d x
    jac[2] = 1.0;               // d x' / d v
    jac[3] = 0.0;               // d v' / d v
    return 0;
  }

  // The exact position and velocity at t for y(0) = [x0; v0].
  double Position(double t, double x0, double v0) const {
    return x0 * std::cos(omega_ * t) + v0 / omega_ * std::sin(omega_ * t);
  }
  double Velocity(double t, double x0, double v0) const {
    return -x0 * omega_ * std::sin(omega_ * t) + v0 * std::cos(omega_ * t);
  }

  double max_time_seen = -std::numeric_limits<double>::infinity();
  int jacobian_calls = 0;

 private:
  double omega_;
  bool with_jacobian_;
};

// A stiff scalar problem: y' = -lambda (y - cos t), y(0) = 1. After a fast transient the
// solution follows y ~ (lambda^2 cos t + lambda sin t) / (lambda^2 + 1).
class StiffRelaxation : public OdeSystem {
 public:
  explicit StiffRelaxation(double lambda = 1000.0) : lambda_(lambda) {}
  int size() const override { return 1; }
  int Rhs(double t, const double* y, double* ydot) override {
    ydot[0] = -lambda_ * (y[0] - std::cos(t));
    return 0;
  }
  // The exact solution for y(0) = 1.
  double Exact(double t) const {
    const double l = lambda_;
    const double denom = l * l + 1.0;
    const double steady = (l * l * std::cos(t) + l * std::sin(t)) / denom;
    const double c = 1.0 - l * l / denom;
    return steady + c * std::exp(-l * t);
  }

 private:
  double lambda_;
};

// y' = y: grows past any divergence limit.
class ExponentialGrowth : public OdeSystem {
 public:
  int size() const override { return 1; }
  int Rhs(double /*t*/, const double* y, double* ydot) override {
    ydot[0] = y[0];
    return 0;
  }
};

// A harmonic oscillator whose right-hand side returns `code` from t_fail on.
class FailingOscillator : public HarmonicOscillator {
 public:
  FailingOscillator(double t_fail, int code)
      : HarmonicOscillator(1.0), t_fail_(t_fail), code_(code) {}
  int Rhs(double t, const double* y, double* ydot) override {
    if (t >= t_fail_) return code_;
    return HarmonicOscillator::Rhs(t, y, ydot);
  }

 private:
  double t_fail_;
  int code_;
};

// A harmonic oscillator whose right-hand side turns NaN from t_fail on.
class NanOscillator : public HarmonicOscillator {
 public:
  explicit NanOscillator(double t_fail) : HarmonicOscillator(1.0), t_fail_(t_fail) {}
  int Rhs(double t, const double* y, double* ydot) override {
    HarmonicOscillator::Rhs(t, y, ydot);
    if (t >= t_fail_) ydot[1] = std::numeric_limits<double>::quiet_NaN();
    return 0;
  }

 private:
  double t_fail_;
};

// The unit harmonic oscillator as a DAE for IDA: F = [x' - v; v' + x] (y = [x; v]).
class OscillatorDae : public DaeSystem {
 public:
  int size() const override { return 2; }
  int Residual(double, const double* y, const double* yp, double* r) override {
    r[0] = yp[0] - y[1];
    r[1] = yp[1] + y[0];
    return 0;
  }
  void DifferentialIds(double* id) const override { std::fill(id, id + 2, 1.0); }
  const std::vector<int>& JacobianColumnStarts() const override { return starts_; }
  const std::vector<int>& JacobianRowIndices() const override { return rows_; }

 private:
  std::vector<int> starts_{0, 2, 4};
  std::vector<int> rows_{0, 1, 0, 1};
};

// Options for `method` over [0, t_final].
inline IntegratorOptions Options(Method method, double t_final, double rtol = 1e-6) {
  IntegratorOptions options;
  options.method = method;
  options.rtol = rtol;
  options.atol = rtol * 1e-2;
  options.t_final = t_final;
  return options;
}

}  // namespace mbstream::testing
