// ROS34PW2, the 4-stage Rosenbrock-W method of Rang & Angermann (BIT 45,
// 2005): order 3 for ANY matrix T standing in for the Jacobian (a W-method),
// L-stable, stiffly accurate, with an embedded order-2 solution. Each stage
// solves (I - gamma h T) x = b through the caller's LinearSolve, so a caller
// that knows the stiff linear part of its system (T) and can solve with it
// cheaply at any h gets steps bound by accuracy, not by stability. The
// non-autonomous term gamma_i h^2 df/dt of a Rosenbrock method is left out:
// for the autonomised system (t' = 1) that is a T without the column of t,
// which a W-method allows.
// In the transformed variables of Hairer & Wanner, Solving ODEs II (2nd ed.),
// IV.7 (7.25) (u_i = sum_j gamma_ij k_j), with Gamma = (gamma_ij) and
// alpha = (alpha_ij) the method's tables:
//   (I - gamma h T) u_i = gamma h (f(t + alpha_i h, y + sum_j a_ij u_j) + sum_j c_ij u_j / h),
//   y1 = y + sum m_i u_i,  a = alpha Gamma^-1,  c = -Gamma^-1 (off the diagonal),  m = b' Gamma^-1.
// Dense output: y(t + s h) = y + s D1 + s^2 D2 + s^3 D3. With a stiff part,
// the quadratic (D3 = 0) y + sum_j b_j(s) k_j whose weights
// b_j(s) = s v_j + s^2 (b_j - v_j) meet the W-method's conditions of order 2
// at every s (sum v = 1, sum v alpha_j = 0, sum v gamma_j = 0 with
// gamma_j = sum_k gamma_jk; v the least-norm solution): built from the
// stages, it stays bounded on stiff components, where a Hermite interpolant
// through h f(y1) would not. Without one (T = 0, an explicit method of
// order 3) the step's cubic Hermite interpolant through y, y1 and h f(t, y),
// h f(t + h, y1) (the next step's first stage, computed anyway), of order 3:
// exact on a cubic, as a rocking angle is just after an uplift from rest
// (theta ~ t^3 while its acceleration grows from 0 with the ground's). The
// quadratic is not: on theta = t^3 / 6 it dips through 0 inside every step
// longer than about twice the time since the uplift (as the steps are when
// they grow from a small first one by the controller's factor 5), which the
// guards took for an impact.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
module rocking.integrator;

namespace rocking::ode {

namespace {

constexpr int stages = 4;

// The method's tables and what the transformed form and the dense output need.
struct Tableau {
  std::array<std::array<double, stages>, stages> a{}, c{};
  std::array<double, stages> alpha{}, m{}, error{}, dense1{};

  Tableau() {
    const double g = 4.3586652150845900e-01;
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero(), G = Eigen::Matrix4d::Zero();
    A(1, 0) = 8.7173304301691801e-01;
    A(2, 0) = 8.4457060015369423e-01;
    A(2, 1) = -1.1299064236484185e-01;
    A(3, 2) = 1.0;
    G.diagonal().setConstant(g);
    G(1, 0) = -8.7173304301691801e-01;
    G(2, 0) = -9.0338057013044082e-01;
    G(2, 1) = 5.4180672388095326e-02;
    G(3, 0) = 2.4212380706095346e-01;
    G(3, 1) = -1.2232505839045147e+00;
    G(3, 2) = 5.4526025533510214e-01;
    const Eigen::RowVector4d b(2.4212380706095346e-01, -1.2232505839045147e+00, 1.5452602553351020e+00,
                               4.3586652150845900e-01);
    const Eigen::RowVector4d b_hat(3.7810903145819369e-01, -9.6042292212423178e-02, 5.0000000000000000e-01,
                                   2.1793326075422950e-01);
    const Eigen::Matrix4d Gi = G.inverse();
    const Eigen::Matrix4d At = A * Gi;
    const Eigen::RowVector4d mt = b * Gi, et = (b - b_hat) * Gi;
    // Order-2 dense weights: least-norm v with [1; alpha; gamma sums]' v = (1, 0, 0).
    Eigen::Matrix<double, 3, 4> conditions;
    conditions.row(0).setOnes();
    conditions.row(1) = A.rowwise().sum().transpose();
    conditions.row(2) = G.rowwise().sum().transpose();
    const Eigen::Vector4d v = conditions.transpose() *
                              (conditions * conditions.transpose()).ldlt().solve(Eigen::Vector3d(1, 0, 0));
    const Eigen::RowVector4d d1 = v.transpose() * Gi;
    for (int i = 0; i < stages; ++i) {
      alpha[i] = A.row(i).sum();
      m[i] = mt[i];
      error[i] = et[i];
      dense1[i] = d1[i];
      for (int j = 0; j < i; ++j) {
        a[i][j] = At(i, j);
        c[i][j] = -Gi(i, j);
      }
    }
  }
  static constexpr double gamma = 4.3586652150845900e-01;
};

const Tableau& tableau() {
  static const Tableau t;
  return t;
}

// Step-size control for an error estimate of order 2 (local error h^3).
constexpr double safety = 0.9, fac_min = 0.2, fac_max = 5.0, exponent = 1.0 / 3.0;

class RosenbrockW final : public detail::Adaptive<RosenbrockW> {
  friend class detail::Adaptive<RosenbrockW>;

 public:
  RosenbrockW(Eigen::Index n, Rhs rhs, LinearSolve solve, Options o)
      : Adaptive(n, std::move(rhs), o), solve_(std::move(solve)) {
    for (auto* v : {&y_prev_, &y_new_, &y_stage_, &f_, &f_stage_, &r_, &err_, &d1_, &d2_, &d3_}) v->setZero(n);
    for (auto& u : u_) u.setZero(n);
  }

  void reset(double t, const Eigen::VectorXd& y, Guards guards) override {
    begin(t, y, std::move(guards));
    y_prev_ = y;
    d1_.setZero();
    d2_.setZero();
    d3_.setZero();
    h_dense_ = 0;
    rhs(t_, y_, f_);
    if (!f_.allFinite()) throw IntegrationError(IntegrationError::Kind::non_finite_state, t_, "at the initial state");
    h_ = opt_.initial_step > 0 ? opt_.initial_step : initial_step();
  }

  void dense(double t, Eigen::Ref<Eigen::VectorXd> y) override {
    if (h_dense_ == 0) { y = y_prev_; return; }
    const double s = (t - t_prev_) / h_dense_;
    if (solve_) y = y_prev_ + s * (d1_ + s * d2_);
    else y = y_prev_ + s * (d1_ + s * (d2_ + s * d3_));
  }
  std::string name() const override { return "rosw"; }

 private:
  double next_step(double h, double err) const {
    return h * (err == 0 ? fac_max : std::clamp(safety * std::pow(err, -exponent), fac_min, fac_max));
  }
  double retry_step(double h, double err) const {
    return h * std::clamp(safety * std::pow(err, -exponent), fac_min, 1.0);
  }
  void derivative_at_state() { rhs(t_, y_, f_); }  // the next step's first stage

  // x = (I - g T)^-1 b; T = 0 without a LinearSolve.
  void solve(double g, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    if (solve_) solve_(g, b, x);
    else x = b;
  }

  // A first step from |y| / |f| (the controller corrects it within a few steps).
  double initial_step() {
    const double d0 = weighted_rms(y_, y_, y_), d1 = weighted_rms(f_, y_, y_);
    const double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    return std::min(h0, opt_.max_step);
  }

  // One trial step of size h from (t_, y_) with f_ = f(t_, y_); returns the
  // error norm (NaN when a stage produced a non-finite value).
  double attempt(double h) {
    const Tableau& tb = tableau();
    const double g = Tableau::gamma * h;
    for (int i = 0; i < stages; ++i) {
      if (i == 0) {
        r_ = g * f_;
      } else {
        y_stage_ = y_;
        for (int j = 0; j < i; ++j) y_stage_ += tb.a[i][j] * u_[j];
        rhs(t_ + tb.alpha[i] * h, y_stage_, f_stage_);
        r_ = g * f_stage_;
        for (int j = 0; j < i; ++j) r_ += (g * tb.c[i][j] / h) * u_[j];
      }
      solve(g, r_, u_[i]);
    }
    y_new_ = y_;
    err_.setZero();
    for (int j = 0; j < stages; ++j) {
      y_new_ += tb.m[j] * u_[j];
      err_ += tb.error[j] * u_[j];
    }
    if (!y_new_.allFinite() || !err_.allFinite()) return std::numeric_limits<double>::quiet_NaN();
    // weighted_rms as one vectorised expression
    const long nc = controlled();
    const auto scale = opt_.atol + opt_.rtol * y_.head(nc).cwiseAbs().cwiseMax(y_new_.head(nc).cwiseAbs()).array();
    return std::sqrt((err_.head(nc).array() / scale).square().sum() / static_cast<double>(nc));
  }

  void accept(double h, double t_new) {
    if (solve_) {
      const Tableau& tb = tableau();
      d1_.setZero();
      for (int j = 0; j < stages; ++j) d1_ += tb.dense1[j] * u_[j];
      d2_ = y_new_ - y_ - d1_;
    } else {
      d1_ = h * f_;  // h f(t, y), before f_ moves on to the step's end
    }
    y_prev_.swap(y_);
    y_.swap(y_new_);
    t_prev_ = t_;
    h_dense_ = h;
    t_ = t_new;
    ++stats_.steps;
    rhs(t_, y_, f_);  // the next step's first stage
    if (!solve_) {  // the cubic Hermite interpolant: D2 = 3 dy - 2 h f0 - h f1, D3 = h f0 + h f1 - 2 dy
      d3_ = h * f_;   // h f1 for now
      d2_ = 3 * (y_ - y_prev_) - 2 * d1_ - d3_;
      d3_ += d1_ - 2 * (y_ - y_prev_);
    }
  }

  LinearSolve solve_;
  std::array<Eigen::VectorXd, stages> u_;
  Eigen::VectorXd y_prev_, y_new_, y_stage_, f_, f_stage_, r_, err_, d1_, d2_, d3_;
};

}  // namespace

std::unique_ptr<Integrator> make_rosenbrock_w(Eigen::Index n, Rhs rhs, LinearSolve solve, Options options) {
  return std::make_unique<RosenbrockW>(n, std::move(rhs), std::move(solve), options);
}

}  // namespace rocking::ode
