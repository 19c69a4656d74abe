#include "server/integrate/appended_quadratures.h"

#include <algorithm>

namespace mbstream {

AppendedQuadratureOde::AppendedQuadratureOde(OdeSystem& system)
    : system_(system),
      projection_(ProjectionOf(system)),
      n_(system.size()),
      nq_(system.num_quadratures()),
      jacobian_(system.HasJacobian() ? static_cast<size_t>(n_) * n_ : 0) {}

int AppendedQuadratureOde::Rhs(double t, const double* z, double* zdot) {
  return system_.RhsAndQuadrature(t, z, zdot, zdot + n_);
}

int AppendedQuadratureOde::Project(double t, const double* z, double* correction) {
  std::fill(correction + n_, correction + n_ + nq_, 0.0);
  return projection_->Project(t, z, correction);
}

int AppendedQuadratureOde::Jacobian(double t, const double* z, const double* fz,
                                    double* jac_col_major) {
  if (const int code = system_.Jacobian(t, z, fz, jacobian_.data()); code != 0) return code;
  const int size = n_ + nq_;
  std::fill(jac_col_major, jac_col_major + static_cast<size_t>(size) * size, 0.0);
  for (int j = 0; j < n_; ++j) {
    std::copy_n(jacobian_.data() + static_cast<size_t>(j) * n_, n_,
                jac_col_major + static_cast<size_t>(j) * size);
  }
  return 0;
}

namespace {

class AppendedQuadratureIntegrator : public Integrator {
 public:
  AppendedQuadratureIntegrator(OdeSystem& system, double t0, const double* y0,
                               const IntegratorOptions& options)
      : ode_(std::make_unique<AppendedQuadratureOde>(system)),
        n_(system.size()),
        z_(static_cast<size_t>(ode_->size()), 0.0),
        z0_(z_.size(), 0.0) {
    std::copy_n(y0, n_, z_.data());
    IntegratorOptions inner = options;
    inner.error_states = n_;
    integrator_ = MakeIntegrator(*ode_, t0, z_.data(), inner);
  }

  AdvanceResult AdvanceTo(double t_out, double* y) override {
    AdvanceResult result = integrator_->AdvanceTo(t_out, z_.data());
    std::copy_n(z_.data(), n_, y);
    return result;
  }

  SolverStats stats() const override { return integrator_->stats(); }
  bool Retune(const IntegratorOptions& options) override {
    IntegratorOptions inner = options;
    inner.error_states = n_;
    return integrator_->Retune(inner);
  }
  bool Restart(double t0, const double* y0, const IntegratorOptions& options) override {
    restart_ = options;  // assigned, not made: no allocation for the table's name
    restart_.error_states = n_;
    std::copy_n(y0, n_, z0_.data());
    std::fill(z0_.begin() + n_, z0_.end(), 0.0);  // the quadratures from 0 again
    if (!integrator_->Restart(t0, z0_.data(), restart_)) return false;
    z_.swap(z0_);
    return true;
  }
  const char* name() const override { return integrator_->name(); }

  bool Quadratures(double* q) override {
    std::copy(z_.begin() + n_, z_.end(), q);
    return true;
  }

 private:
  std::unique_ptr<AppendedQuadratureOde> ode_;
  const int n_;
  std::vector<double> z_;      // [y; Q] at the last output
  std::vector<double> z0_;     // Restart's start (kept: no allocation)
  IntegratorOptions restart_;  // Restart's options for the inner integrator (likewise)
  std::unique_ptr<Integrator> integrator_;
};

}  // namespace

std::unique_ptr<Integrator> MakeAppendedQuadratureIntegrator(OdeSystem& system, double t0,
                                                             const double* y0,
                                                             const IntegratorOptions& options) {
  return std::make_unique<AppendedQuadratureIntegrator>(system, t0, y0, options);
}

}  // namespace mbstream
