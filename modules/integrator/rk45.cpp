// Dormand-Prince 5(4) with dense output, PI control, breakpoints and events.
// Coefficients and controller constants as in Hairer's DOPRI5 (see the module
// interface for the references).
module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>
module rocking.integrator;

namespace rocking::ode {

namespace {

constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
constexpr double a21 = 1.0 / 5;
constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729;
constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247, a64 = 49.0 / 176,
                 a65 = -5103.0 / 18656;
constexpr double a71 = 35.0 / 384, a73 = 500.0 / 1113, a74 = 125.0 / 192, a75 = -2187.0 / 6784,
                 a76 = 11.0 / 84;
// error estimate: 5th- minus 4th-order weights
constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920, e5 = -17253.0 / 339200,
                 e6 = 22.0 / 525, e7 = -1.0 / 40;
// dense output
constexpr double d1 = -12715105075.0 / 11282082432, d3 = 87487479700.0 / 32700410799,
                 d4 = -10690763975.0 / 1880347072, d5 = 701980252875.0 / 199316789632,
                 d6 = -1453857185.0 / 822651844, d7 = 69997945.0 / 29380423;
// PI controller (Hairer: beta = 0.04, safety 0.9, step ratio in [0.2, 10])
constexpr double beta = 0.04, expo1 = 0.2 - 0.75 * beta, safety = 0.9, fac_min = 0.2, fac_max = 10.0;

class DormandPrince final : public detail::Adaptive<DormandPrince> {
  friend class detail::Adaptive<DormandPrince>;

 public:
  DormandPrince(Eigen::Index n, Rhs rhs, Options o) : Adaptive(n, std::move(rhs), o) {
    for (auto* v : {&y_new_, &y_stage_, &k1_, &k2_, &k3_, &k4_, &k5_, &k6_, &k7_, &r1_, &r2_, &r3_, &r4_, &r5_})
      v->setZero(n);
  }

  void reset(double t, const Eigen::VectorXd& y, Guards guards) override {
    begin(t, y, std::move(guards));
    r1_ = y;
    r2_.setZero(); r3_.setZero(); r4_.setZero(); r5_.setZero();
    rhs(t_, y_, k1_);
    if (!k1_.allFinite()) throw IntegrationError(IntegrationError::Kind::non_finite_state, t_, "at the initial state");
    h_ = opt_.initial_step > 0 ? opt_.initial_step : initial_step();
    log_fac_old_ = std::log(1e-4);
  }

  void dense(double t, Eigen::Ref<Eigen::VectorXd> y) override {
    if (h_dense_ == 0) { y = r1_; return; }
    const double s = (t - t_prev_) / h_dense_, s1 = 1.0 - s;
    const double *r1 = r1_.data(), *r2 = r2_.data(), *r3 = r3_.data(), *r4 = r4_.data(), *r5 = r5_.data();
    double* out = y.data();
    for (long i = 0, n = y_.size(); i < n; ++i) out[i] = r1[i] + s * (r2[i] + s1 * (r3[i] + s * (r4[i] + s1 * r5[i])));
  }
  std::string name() const override { return "rk45"; }

 private:
  // The PI step after an accepted step: err^expo1 and the PI term
  // err^expo1 / err_old^beta from one log and one exp.
  double next_step(double h, double err) {
    const double log_err = std::log(err);
    const double pi = std::exp(expo1 * log_err - beta * log_fac_old_);
    const double fac = std::clamp(pi / safety, 1.0 / fac_max, 1.0 / fac_min);
    log_fac_old_ = std::max(log_err, std::log(1e-4));
    return h / fac;
  }
  double retry_step(double h, double err) const {
    return h / std::min(1.0 / fac_min, std::exp(expo1 * std::log(err)) / safety);
  }
  void derivative_at_state() { rhs(t_, y_, k1_); }  // FSAL: the next step's first stage

  // Hairer's starting step: h0 from |y|/|f|, refined with a second-derivative estimate.
  double initial_step() {
    const double d0 = weighted_rms(y_, y_, y_), d1 = weighted_rms(k1_, y_, y_);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    h0 = std::min(h0, opt_.max_step);
    y_stage_ = y_ + h0 * k1_;
    rhs(t_ + h0, y_stage_, k2_);
    k3_ = (k2_ - k1_) / h0;
    const double d2 = weighted_rms(k3_, y_, y_), dm = std::max(d1, d2);
    const double h1 = dm <= 1e-15 ? std::max(1e-6, h0 * 1e-3) : std::pow(0.01 / dm, 0.2);
    return std::min({100 * h0, h1, opt_.max_step});
  }

  // One trial step of size h from (t_, y_) with k1_ = f(t_, y_); returns the
  // error norm (NaN when the step produced a non-finite value).
  double attempt(double h) {
    double err = 0;
    with_static_size(y_.size(), [&](auto size) { err = attempt_n<decltype(size)::value>(h); });
    return err;
  }

  // The stages and the error estimate in plain loops, unrolled for the state
  // size (static_size.hpp): a state has a dozen components, where general
  // vector expressions cost more in control than in arithmetic.
  template <int S>
  double attempt_n(double h) {
    const long n = static_or<S>(y_.size());
    const double *y = y_.data(), *k1 = k1_.data(), *k2 = k2_.data(), *k3 = k3_.data(), *k4 = k4_.data(),
                 *k5 = k5_.data(), *k6 = k6_.data(), *k7 = k7_.data();
    double *ys = y_stage_.data(), *yn = y_new_.data();
    for (long i = 0; i < n; ++i) ys[i] = y[i] + h * a21 * k1[i];
    rhs(t_ + c2 * h, y_stage_, k2_);
    for (long i = 0; i < n; ++i) ys[i] = y[i] + h * (a31 * k1[i] + a32 * k2[i]);
    rhs(t_ + c3 * h, y_stage_, k3_);
    for (long i = 0; i < n; ++i) ys[i] = y[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
    rhs(t_ + c4 * h, y_stage_, k4_);
    for (long i = 0; i < n; ++i) ys[i] = y[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
    rhs(t_ + c5 * h, y_stage_, k5_);
    for (long i = 0; i < n; ++i)
      ys[i] = y[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
    rhs(t_ + h, y_stage_, k6_);
    for (long i = 0; i < n; ++i)
      yn[i] = y[i] + h * (a71 * k1[i] + a73 * k3[i] + a74 * k4[i] + a75 * k5[i] + a76 * k6[i]);
    rhs(t_ + h, y_new_, k7_);
    // The error over the weighed components (the static size itself unless
    // some trailing components are left out), and in the same pass whether
    // the new state and derivative are finite: x - x is 0 for a finite x and
    // NaN otherwise, so a sum of such differences is 0 exactly when all are
    // finite (NaN != 0).
    const auto error_sum = [&](long count, double& nonfinite) {
      double sum = 0, bad = 0;
      for (long i = 0; i < count; ++i) {
        const double e = h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
        const double r = scaled(e, y[i], yn[i]);
        sum += r * r;
        bad += (yn[i] - yn[i]) + (k7[i] - k7[i]);
      }
      nonfinite = bad;
      return sum;
    };
    const long nc = controlled();
    double bad = 0;
    const double sum = nc == n ? error_sum(n, bad) : error_sum(nc, bad);
    for (long i = nc; i < n; ++i) bad += (yn[i] - yn[i]) + (k7[i] - k7[i]);
    if (bad != 0.0) return std::numeric_limits<double>::quiet_NaN();
    return std::sqrt(sum / static_cast<double>(nc));
  }

  void accept(double h, double t_new) {
    const long n = y_.size();
    const double *y = y_.data(), *yn = y_new_.data(), *k1 = k1_.data(), *k3 = k3_.data(), *k4 = k4_.data(),
                 *k5 = k5_.data(), *k6 = k6_.data(), *k7 = k7_.data();
    double *r1 = r1_.data(), *r2 = r2_.data(), *r3 = r3_.data(), *r4 = r4_.data(), *r5 = r5_.data();
    for (long i = 0; i < n; ++i) {
      r1[i] = y[i];
      r2[i] = yn[i] - y[i];
      r3[i] = h * k1[i] - r2[i];
      r4[i] = r2[i] - h * k7[i] - r3[i];
      r5[i] = h * (d1 * k1[i] + d3 * k3[i] + d4 * k4[i] + d5 * k5[i] + d6 * k6[i] + d7 * k7[i]);
    }
    t_prev_ = t_;
    h_dense_ = h;
    t_ = t_new;
    y_.swap(y_new_);
    k1_.swap(k7_);  // FSAL
    ++stats_.steps;
  }

  double log_fac_old_ = 0;  // log of Hairer's facold
  Eigen::VectorXd y_new_, y_stage_, k1_, k2_, k3_, k4_, k5_, k6_, k7_;
  Eigen::VectorXd r1_, r2_, r3_, r4_, r5_;
};

}  // namespace

std::unique_ptr<Integrator> make_rk45(Eigen::Index n, Rhs rhs, Options options) {
  return std::make_unique<DormandPrince>(n, std::move(rhs), options);
}

}  // namespace rocking::ode
