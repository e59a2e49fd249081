// ode::make_exact_linear: the exact steps of z' = A z + b a(t) with a(t)
// piecewise linear, against closed forms (an undamped oscillator under a
// constant and a ramp input; independent oscillators solved block by block;
// a coupled chain against the matrix exponential), its dense output, its
// event location, its quadratures (the energy accumulators' closed forms)
// against an oscillator's energy balance and Simpson's rule, and its use for
// the full-contact phase of a simulation against rk45 throughout.
#include <rocking/eigen.hpp>
#include <unsupported/Eigen/MatrixFunctions>
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>
#include "records.hpp"
import rocking.simulation;
import rocking.scene;
import rocking.records;

using namespace rocking;
using namespace rocking::ode;
using CRef = Eigen::Ref<const Eigen::VectorXd>;
using Ref = Eigen::Ref<Eigen::VectorXd>;

namespace {

constexpr double omega = 7.0;

// x'' + omega^2 x = a(t) on the block [x, v] of a 3-component state whose
// last entry is constant; a(t) = 0.5 on [0, 1], then 0.5 + 2 (t - 1).
LinearSystem oscillator() {
  LinearSystem s;
  s.size = 3;
  s.first = 0;
  s.A.resize(2, 2);
  s.A << 0, 1, -omega * omega, 0;
  s.b = Eigen::Vector2d(0, 1);
  s.forcing = [](double t) { return t <= 1 ? 0.5 : 0.5 + 2 * (t - 1); };
  return s;
}

// Closed form from x(0) = 1, v(0) = 0: for a = a0 + a' (t - t0) from (x0, v0) at t0,
//   x = a0/w^2 + a'(t - t0)/w^2 + (x0 - a0/w^2) cos w(t - t0) + (v0 - a'/w^2)/w sin w(t - t0).
Eigen::Vector2d exact(double t) {
  auto piece = [](double x0, double v0, double a0, double slope, double tau) {
    const double w2 = omega * omega, c = std::cos(omega * tau), s = std::sin(omega * tau);
    const double x = a0 / w2 + slope * tau / w2 + (x0 - a0 / w2) * c + (v0 - slope / w2) / omega * s;
    const double v = slope / w2 - (x0 - a0 / w2) * omega * s + (v0 - slope / w2) * c;
    return Eigen::Vector2d(x, v);
  };
  if (t <= 1) return piece(1, 0, 0.5, 0, t);
  const Eigen::Vector2d at1 = piece(1, 0, 0.5, 0, 1);
  return piece(at1[0], at1[1], 0.5, 2, t - 1);
}

Eigen::VectorXd start() { return Eigen::Vector3d(1, 0, 42); }

// `copies` of the oscillator laid out as a structure's modes, [x; v] (x_c and
// v_c 9 apart), copy c's omega^2 scaled by 1 + spread c, each damped by
// damping v, plus one constant component at the end.
LinearSystem oscillators(int copies, double spread, double damping) {
  const LinearSystem one = oscillator();
  LinearSystem many;
  many.size = 2 * copies + 1;
  many.first = 0;
  many.A = Eigen::MatrixXd::Zero(2 * copies, 2 * copies);
  many.b = Eigen::VectorXd::Zero(2 * copies);
  for (int c = 0; c < copies; ++c) {
    const int x = c, v = copies + c;
    many.A(x, v) = one.A(0, 1);
    many.A(v, x) = one.A(1, 0) * (1 + spread * c);
    many.A(v, v) = -damping;
    many.b[v] = one.b[1];
  }
  many.forcing = one.forcing;
  return many;
}

// The oscillator's exact integrator, with the input's kink at t = 1 as a
// breakpoint, started from start().
std::unique_ptr<Integrator> started(const Options& o) {
  auto integ = make_exact_linear(oscillator(), o);
  integ->set_breakpoints(breakpoint_list({1.0}));
  integ->reset(0, start(), {});
  return integ;
}

}  // namespace

TEST_CASE("exact steps match the closed form of an oscillator under a constant, then a ramp, to 1e-12") {
  Options o;
  o.max_step = 0.1;
  auto integ = started(o);
  Eigen::VectorXd y(3);
  while (integ->time() < 3.0) {
    integ->step(3.0);
    const double t = integ->time();
    CHECK((integ->state().head(2) - exact(t)).norm() <= 1e-12);
    CHECK(integ->state()[2] == 42);  // outside the block: constant
    for (int k = 1; k <= 4; ++k) {   // the guard samples, cached or not
      y = integ->sample(k, 4);
      CHECK((y.head(2) - exact(integ->sample_time(k, 4))).norm() <= 1e-12);
    }
    const double mid = 0.5 * (integ->previous_time() + t);  // dense output anywhere
    integ->dense(mid, y);
    CHECK((y.head(2) - exact(mid)).norm() <= 1e-12);
  }
  CHECK(integ->stats().steps == 30);  // ten steps of 0.1 before the breakpoint, twenty after
}

TEST_CASE("with a sample spacing, exact steps span up to 16 spacings and are sampled ceil(h / spacing) times") {
  Options o;
  o.sample_spacing = 0.03;  // steps of at most 0.48
  auto integ = started(o);
  Eigen::VectorXd y(3);
  while (integ->time() < 3.0) {
    integ->step(3.0);
    const double h = integ->time() - integ->previous_time();
    CHECK(h <= 16 * 0.03 + 1e-12);
    const int count = integ->sample_count();
    CHECK(count == static_cast<int>(std::ceil(h / 0.03 - 1e-9)));
    for (int k = 1; k <= count; ++k) {
      y = integ->sample(k, count);
      CHECK((y.head(2) - exact(integ->sample_time(k, count))).norm() <= 1e-12);
    }
  }
  // [0, 1] in three steps of 1/3 (12 samples each), [1, 3] in five of 0.4 (14 each)
  CHECK(integ->stats().steps == 8);
}

TEST_CASE("9 independent oscillators laid out as a structure's modes, [x, v], are stepped block by block as exactly as one") {
  // 18 components > max_static_size, and A splits into nine 2 x 2 blocks
  // (x_c, v_c) whose components lie 9 apart: each block is solved alone.
  const int copies = 9;
  const LinearSystem many = oscillators(copies, 0, 0);
  Options o;
  o.max_step = 0.1;
  auto integ = make_exact_linear(many, o);
  integ->set_breakpoints(breakpoint_list({1.0}));
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(many.size), y(many.size);
  y0.head(copies).setOnes();
  y0[2 * copies] = 42;
  integ->reset(0, y0, {});
  while (integ->time() < 3.0) {
    integ->step(3.0);
    for (int k = 1; k <= 4; ++k) {
      y = integ->sample(k, 4);
      const Eigen::Vector2d want = exact(integ->sample_time(k, 4));
      for (int c = 0; c < copies; ++c) CHECK((Eigen::Vector2d(y[c], y[copies + c]) - want).norm() <= 1e-12);
      CHECK(y[2 * copies] == 42);
    }
    const double mid = 0.5 * (integ->previous_time() + integ->time());
    integ->dense(mid, y);
    CHECK((Eigen::Vector2d(y[0], y[copies]) - exact(mid)).norm() <= 1e-12);
  }
}

TEST_CASE("a coupled block beyond the unrolled sizes (a chain of 9 damped masses) follows the matrix exponential") {
  // One block of 18: the general loops. x'' = -K x - C x' + 1 a(t), K the
  // chain's tridiagonal stiffness, C = 0.02 K + 0.1 I; reference: the
  // exponential of the augmented matrix [[A, b, 0], [0, 0, 1], [0, 0, 0]]
  // acting on [z; a; a'] over each linear piece of a(t).
  const int n = 9;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    K(i, i) = i + 1 < n ? 2 * 400.0 : 400.0;
    if (i > 0) K(i, i - 1) = K(i - 1, i) = -400.0;
  }
  LinearSystem s;
  s.size = 2 * n;
  s.first = 0;
  s.A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  s.A.topRightCorner(n, n).setIdentity();
  s.A.bottomLeftCorner(n, n) = -K;
  s.A.bottomRightCorner(n, n) = -(0.02 * K + 0.1 * Eigen::MatrixXd::Identity(n, n));
  s.b = Eigen::VectorXd::Zero(2 * n);
  s.b.tail(n).setOnes();
  s.forcing = oscillator().forcing;
  Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(2 * n + 2, 2 * n + 2);
  aug.topLeftCorner(2 * n, 2 * n) = s.A;
  aug.block(0, 2 * n, 2 * n, 1) = s.b;
  aug(2 * n, 2 * n + 1) = 1;
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(2 * n);
  z0[n - 1] = 0.01;
  auto reference = [&](double t) {
    auto piece = [&](const Eigen::VectorXd& z, double a0, double slope, double tau) {
      Eigen::VectorXd x(2 * n + 2);
      x << z, a0, slope;
      return Eigen::VectorXd((aug * tau).exp() * x).head(2 * n).eval();
    };
    if (t <= 1) return piece(z0, 0.5, 0, t);
    return piece(piece(z0, 0.5, 0, 1), 0.5, 2, t - 1);
  };
  Options o;
  o.max_step = 0.05;
  auto integ = make_exact_linear(s, o);
  integ->set_breakpoints(breakpoint_list({1.0}));
  integ->reset(0, z0, {});
  Eigen::VectorXd y(2 * n);
  while (integ->time() < 2.0) {
    integ->step(2.0);
    for (int k = 1; k <= 4; ++k) {
      y = integ->sample(k, 4);
      const Eigen::VectorXd want = reference(integ->sample_time(k, 4));
      CHECK((y - want).norm() <= 1e-10 * want.norm());
    }
  }
}

TEST_CASE("an event is located to round-off on the exact solution") {
  // Free oscillation (a = 0) from x = 1: x falls through 0 at t = pi / (2 omega).
  LinearSystem s = oscillator();
  s.forcing = [](double) { return 0.0; };
  Options o;
  o.max_step = 0.05;
  auto integ = make_exact_linear(s, o);
  integ->reset(0, start(), {[](double, CRef y, Ref g) { g[0] = y[0]; }, {Direction::falling}});
  const StepReport r = advance(*integ, 1.0);
  REQUIRE(r.reason == Stop::event);
  CHECK(r.t == close_to(std::numbers::pi / (2 * omega), 1e-13));
  CHECK(std::abs(integ->state()[0]) <= 1e-13);
}

namespace {

// int_t0^t1 f by composite Simpson's rule on 400 panels.
template <class F>
double simpson(F f, double t0, double t1) {
  const int panels = 400;
  const double h = (t1 - t0) / panels;
  double sum = f(t0) + f(t1);
  for (int i = 1; i < panels; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * f(t0 + i * h);
  return sum * h / 3.0;
}

}  // namespace

TEST_CASE("quadratures: a damped oscillator's energy balance closes to round-off over usual, odd and event-cut steps") {
  // x'' + 2 zeta omega x' + omega^2 x = a(t) (unit mass); y = [x, v, W_in, W_visc]
  // with W_in' = a v and W_visc' = 2 zeta omega v^2, so that
  //   v^2 / 2 + omega^2 x^2 / 2 - E(0) = W_in - W_visc
  // holds exactly; and each step's increments equal Simpson's rule on the
  // dense output (an independent quadrature of the same integrands).
  const double zeta = 0.05;
  LinearSystem s = oscillator();
  s.size = 4;
  s.A(1, 1) = -2 * zeta * omega;
  s.quadratures.push_back({2, Eigen::MatrixXd(), Eigen::Vector2d(0, 1)});
  Eigen::Matrix2d Q = Eigen::Matrix2d::Zero();
  Q(1, 1) = 2 * zeta * omega;
  s.quadratures.push_back({3, Q, Eigen::VectorXd()});
  Options o;
  o.max_step = 0.1;
  auto integ = make_exact_linear(s, o);
  integ->set_breakpoints(breakpoint_list({1.0, 1.37}));  // 1.37: a step of odd length
  Eigen::VectorXd y0(4);
  y0 << 1, 0, 0, 0;
  // x rising through 0.2 is an event: steps are cut there
  integ->reset(0, y0, {[](double, CRef y, Ref g) { g[0] = y[0] - 0.2; }, {Direction::rising}});
  auto energy = [](const Eigen::VectorXd& y) { return 0.5 * y[1] * y[1] + 0.5 * omega * omega * y[0] * y[0]; };
  const double e0 = energy(y0);
  Eigen::VectorXd y(4), previous = y0;
  int events = 0;
  while (integ->time() < 3.0) {
    const StepReport r = integ->step(3.0);
    events += r.reason == Stop::event;
    const Eigen::VectorXd& now = integ->state();
    CHECK(std::abs(energy(now) - e0 - (now[2] - now[3])) <= 1e-13 * std::max(e0, now[2]));
    const double t0 = integ->previous_time(), t1 = integ->time();
    auto at = [&](double t) {
      integ->dense(t, y);
      return y;
    };
    const double in = simpson([&](double t) { return s.forcing(t) * at(t)[1]; }, t0, t1);
    const double visc = simpson([&](double t) { return 2 * zeta * omega * std::pow(at(t)[1], 2); }, t0, t1);
    CHECK(now[2] - previous[2] == close_to(in, 1e-9, 1e-21));
    CHECK(now[3] - previous[3] == close_to(visc, 1e-9, 1e-21));
    integ->dense(0.5 * (t0 + t1), y);  // dense output holds them at the step's start
    CHECK(y[2] == previous[2]);
    if (r.reason == Stop::event) integ->reset(t1, now, {});
    previous = now;
  }
  CHECK(events >= 1);
}

TEST_CASE("quadratures on 9 oscillators stepped block by block: a Q that couples two blocks joins them") {
  // W' = v_0 v_5 + a(t) (v_0 + v_8): Q couples copies 0 and 5 (they are then
  // solved as one block); against Simpson's rule on the dense output.
  const int copies = 9;
  LinearSystem many = oscillators(copies, 0.1, 0.3);  // distinct frequencies, damped
  Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(2 * copies, 2 * copies);
  Q(copies, copies + 5) = Q(copies + 5, copies) = 0.5;
  Eigen::VectorXd c = Eigen::VectorXd::Zero(2 * copies);
  c[copies] = c[2 * copies - 1] = 1;
  many.quadratures.push_back({2 * copies, Q, c});
  Options o;
  o.max_step = 0.1;
  auto integ = make_exact_linear(many, o);
  integ->set_breakpoints(breakpoint_list({1.0}));
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(many.size), y(many.size);
  for (int k = 0; k < copies; ++k) y0[k] = 0.1 * (k + 1);
  integ->reset(0, y0, {});
  double previous = 0;
  while (integ->time() < 2.0) {
    integ->step(2.0);
    const double t0 = integ->previous_time(), t1 = integ->time();
    const double want = simpson(
        [&](double t) {
          integ->dense(t, y);
          return y[copies] * y[copies + 5] + many.forcing(t) * (y[copies] + y[2 * copies - 1]);
        },
        t0, t1);
    const double now = integ->state()[2 * copies];
    CHECK(now - previous == close_to(want, 1e-9, 1e-21));
    previous = now;
  }
}

TEST_CASE("a singular linear system is refused with a typed error") {
  LinearSystem s = oscillator();
  s.A.setZero();
  CHECK_THROWS_AS(make_exact_linear(s, Options{}), IntegrationError);
}

namespace {

// The chimney under g at rtol 1e-10: with exact full contact, and with rk45 in every phase.
std::pair<RunResult, RunResult> exact_and_integrated(const ContactModel& m, const GroundMotion& g) {
  RunOptions tight;
  tight.tolerances = {.rtol = 1e-10, .atol = 1e-13};
  RunOptions rk45_only = tight;
  rk45_only.exact_full_contact = false;
  return {simulate(m, g, tight), simulate(m, g, rk45_only)};
}

}  // namespace

TEST_CASE("El Centro: exact full contact agrees with rk45 throughout, and is as accurate at the default tolerance") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  const ContactModel m = make_contact_model(load_default_scene(), false);
  const auto [a, b] = exact_and_integrated(m, g);
  REQUIRE(a.outcome == Outcome::completed);
  CHECK(a.exact_full_contact);
  CHECK_FALSE(b.exact_full_contact);
  CHECK(a.counts.uplifts == b.counts.uplifts);
  CHECK(a.counts.impacts == b.counts.impacts);
  CHECK(a.first_uplift == close_to(b.first_uplift, 1e-9));
  for (std::size_t k = 0; k < quantity_count; ++k)  // peaks: both sample densely; parabolas refine
    CHECK(a.peaks[k] == close_to(b.peaks[k], 1e-6));
  // At the default tolerance the combination keeps peak delta_t within 1e-4 of the reference.
  const RunResult d = simulate(m, g, RunOptions{});
  CHECK(d.peak(Quantity::delta_t) == close_to(b.peak(Quantity::delta_t), 1e-4));
}

TEST_CASE("El Centro with the energy balance: full contact is stepped exactly, and the work terms agree with rk45's") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  const ContactModel m = make_contact_model(load_default_scene(), true);
  const auto [a, b] = exact_and_integrated(m, g);
  REQUIRE(a.outcome == Outcome::completed);
  REQUIRE(a.energy_tracked);
  CHECK(a.exact_full_contact);
  CHECK(a.counts.impacts == b.counts.impacts);
  const EnergyBalance &x = a.energy, &z = b.energy;
  // each term to 1e-7 of the input; the balance closes as tightly as rk45's
  for (const auto& [mine, theirs] : {std::pair{x.ground, z.ground}, {x.viscous, z.viscous}, {x.damper, z.damper},
                                     {x.impacts, z.impacts}, {x.final, z.final}})
    CHECK(std::abs(mine - theirs) <= 1e-7 * z.ground);
  CHECK(std::abs(x.residual()) <= 1e-8 * x.ground);
  CHECK(std::abs(z.residual()) <= 1e-8 * z.ground);
  // At the default tolerance it closes as it did with rk45 through full contact.
  RunOptions rk45_default;
  rk45_default.exact_full_contact = false;
  const RunResult d = simulate(m, g, RunOptions{}), e = simulate(m, g, rk45_default);
  CHECK(d.exact_full_contact);
  CHECK(std::abs(d.energy.residual()) <= std::max(2 * std::abs(e.energy.residual()), 1e-6 * e.energy.ground));
}

TEST_CASE("a fixed-base chimney under El Centro, all exact steps: its energy balance closes to round-off") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  Scene scene = load_default_scene();
  scene.contact.rocking = false;
  const RunResult r = simulate(make_contact_model(scene, true), g, RunOptions{});
  REQUIRE(r.outcome == Outcome::completed);
  CHECK(r.exact_full_contact);
  CHECK(r.energy.ground > 0);
  CHECK(r.energy.viscous > 0);
  CHECK(std::abs(r.energy.residual()) <= 1e-10 * r.energy.ground);
}
