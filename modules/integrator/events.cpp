// GuardScanner: the event search both built-in integrators share (see the
// module interface): guards sampled at evenly spaced points of each step, a
// wanted sign change located by Illinois (regula falsi with the stale end's
// value halved) falling back to bisection, to a bracket of a few ulps; a
// secant point that has converged onto one end closes the bracket from there.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>
module rocking.integrator;

namespace rocking::ode {

namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();

int sign(double v) { return (v > 0) - (v < 0); }

bool wanted(Direction d, int from, int to) {
  return (d != Direction::falling && from < 0 && to > 0) || (d != Direction::rising && from > 0 && to < 0);
}

}  // namespace

const Eigen::VectorXd& Integrator::sample(int k, int count) {
  if (k == count) return state();
  sample_buffer_.resize(state().size());
  dense(sample_time(k, count), sample_buffer_);
  return sample_buffer_;
}

double Integrator::sample_time(int k, int count) const {
  return sample_time(previous_time(), time(), k, count);
}

void Breakpoints::set(NextBreakpoint next) {
  next_ = std::move(next);
  asked_ = std::numeric_limits<double>::infinity();
  answer_ = -std::numeric_limits<double>::infinity();
}

double Breakpoints::after(double t) {
  // next(asked) = answer means no breakpoint in (asked, answer): for t in
  // [asked, answer) the answer stands.
  if (!(t >= asked_ && t < answer_)) {
    answer_ = next_ ? next_(t) : std::numeric_limits<double>::infinity();
    asked_ = t;
  }
  return answer_;
}

StepBound step_bound(Breakpoints& breakpoints, double t, double t_limit) {
  const double bp = breakpoints.after(t);
  return bp < t_limit ? StepBound{bp, true} : StepBound{t_limit, false};
}

void GuardScanner::reset(Guards guards, double t, Eigen::Ref<const Eigen::VectorXd> y) {
  guards_ = std::move(guards);
  restart_t_ = t;
  const auto m = static_cast<Eigen::Index>(guards_.directions.size());
  g_.setZero(m);
  g_work_.setZero(m);
  y_work_.setZero(y.size());
  ref_sign_.assign(static_cast<std::size_t>(m), 0);
  ref_time_.assign(static_cast<std::size_t>(m), t);
  ref_value_.assign(static_cast<std::size_t>(m), 0.0);
  if (m == 0) return;
  evaluate(t, y, g_);
  for (Eigen::Index i = 0; i < m; ++i) {
    ref_sign_[static_cast<std::size_t>(i)] = sign(g_[i]);
    ref_value_[static_cast<std::size_t>(i)] = g_[i];
  }
}

void GuardScanner::evaluate(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::VectorXd& g) {
  guards_.fn(t, y, g);
  ++evaluations_;
}

bool GuardScanner::scan(Integrator& stepped, int count, Crossing& found) {
  const auto m = static_cast<Eigen::Index>(guards_.directions.size());
  if (m == 0) return false;
  const double t0 = stepped.previous_time(), t1 = stepped.time();
  for (int k = 1; k <= count; ++k) {
    const double tk = Integrator::sample_time(t0, t1, k, count);
    evaluate(tk, stepped.sample(k, count), g_);
    double t_event = std::numeric_limits<double>::infinity();
    int which = -1, to_sign = 0;
    for (Eigen::Index i = 0; i < m; ++i) {
      const auto u = static_cast<std::size_t>(i);
      const int s = sign(g_[i]);
      if (s == 0) continue;  // zero: keep the last definite sign
      if (ref_sign_[u] != 0 && s != ref_sign_[u] && wanted(guards_.directions[u], ref_sign_[u], s)) {
        const double te = locate(stepped, static_cast<int>(i), ref_time_[u], ref_sign_[u], ref_value_[u], tk, g_[i]);
        // A crossing within round-off of the restart is the event that caused
        // the restart, seen again (CVODE's ttol): not reported.
        const bool at_restart = te - restart_t_ <= 100 * eps * (std::abs(restart_t_) + (t1 - t0));
        if (!at_restart && te < t_event) { t_event = te; which = static_cast<int>(i); to_sign = s; }
      }
      ref_sign_[u] = s;
      ref_time_[u] = tk;
      ref_value_[u] = g_[i];
    }
    if (which >= 0) {
      found = {t_event, which, to_sign};
      return true;
    }
  }
  return false;
}

// Bracket [a, b] of guard i, with sign sa at a and its values at both ends as
// the scan saw them; returns the end of the final bracket past the crossing.
double GuardScanner::locate(Integrator& stepped, int i, double a, int sa, double ga, double b, double gb) {
  const double t0 = stepped.previous_time();
  auto g_at = [&](double t) {
    stepped.dense(t, y_work_);
    evaluate(t, y_work_, g_work_);
    return g_work_[i];
  };
  const double tol = 8 * eps * std::max(std::abs(b), b - t0);
  int side = 0;
  for (int iter = 0; b - a > tol && iter < 200; ++iter) {
    double t = (iter % 4 == 3 || ga == gb) ? 0.5 * (a + b) : b - gb * (b - a) / (gb - ga);
    if (!(t >= a && t <= b)) t = 0.5 * (a + b);  // NaN, or outside
    // A secant point within half the tolerance of an end (it has converged
    // there, often to within an ulp of it) is moved to half the tolerance
    // inside, so that the bracket closes from that side in one evaluation
    // instead of creeping in by bisection.
    t = std::clamp(t, a + 0.5 * tol, b - 0.5 * tol);
    const double gt = g_at(t);
    if (sign(gt) == sa || gt == 0) {
      a = t; ga = gt;
      if (side == -1) gb *= 0.5;  // Illinois: halve the stale end
      side = -1;
    } else {
      b = t; gb = gt;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  return b;
}

void GuardScanner::restart_at(const Crossing& c, Eigen::Ref<const Eigen::VectorXd> y) {
  restart_t_ = c.t;
  evaluate(c.t, y, g_);
  for (std::size_t u = 0; u < ref_sign_.size(); ++u) {
    const int s = sign(g_[static_cast<Eigen::Index>(u)]);
    if (s != 0) ref_sign_[u] = s;
    ref_time_[u] = c.t;
    ref_value_[u] = g_[static_cast<Eigen::Index>(u)];
  }
  ref_sign_[static_cast<std::size_t>(c.guard)] = c.to_sign;
}

}  // namespace rocking::ode
