// rocking.hysteresis: damper kinematics, the Bouc-Wen law (closed form under
// monotonic loading, bounded and dissipative under cycles) and the thickness rule.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <numbers>
import rocking.hysteresis;
import rocking.integrator;

using namespace rocking;

namespace {
Damper chimney_damper() {
  Damper d;
  d.stiffness = 1.0e7;
  d.post_yield_ratio = 0.06;
  d.theta_y = 2.8e-3;
  return d;
}
constexpr double B = 3.3;
}  // namespace

TEST_CASE("the chimney damper yields at d_y = 4B sin(theta_y/2) = 18.48 mm (MODEL.md 5)") {
  CHECK(yield_displacement(chimney_damper(), B) == close_to(4 * B * std::sin(2.8e-3 / 2), 1e-14));
  CHECK(yield_displacement(chimney_damper(), B) == close_to(18.48e-3, 2.8e-4));  // MODEL.md's 4 digits: +-0.005 mm
}

TEST_CASE("thickness x tau: stiffness x tau^3, yield force x tau^2, yield displacement x 1/tau") {
  const Damper base = chimney_damper();
  for (double tau : {0.5, 1.5, 2.0, 3.0}) {
    Damper thick = base;
    thick.thickness = tau;
    const double k = plate_stiffness(thick);
    CHECK(k == close_to(base.stiffness * tau * tau * tau, 1e-14));
    const double dy = yield_displacement(thick, B), dy0 = yield_displacement(base, B);
    CHECK(dy == close_to(dy0 / tau, 1e-12));
    CHECK(k * dy == close_to(base.stiffness * dy0 * tau * tau, 1e-12));
  }
}

TEST_CASE("a plate thin enough never to yield keeps a finite yield elongation beyond every chord") {
  Damper thin = chimney_damper();
  thin.thickness = 1e-3;
  const double dy = yield_displacement(thin, B);
  CHECK(std::isfinite(dy));
  CHECK(dy > 4 * B);  // no chord of the base reaches it
  CHECK(dy == close_to(yield_displacement(chimney_damper(), B) * 1e3, 1e-12));
  CHECK(plate_stiffness(thin) == close_to(1e7 * 1e-9, 1e-12));
}

TEST_CASE("rotational stiffness of the damper about a pivot is k (2B)^2, eps k (2B)^2 after yield") {
  const Damper d = chimney_damper();
  CHECK(pre_yield_rotational_stiffness(d, B) == close_to(1e7 * 6.6 * 6.6, 1e-12));
  CHECK(post_yield_rotational_stiffness(d, B) == close_to(0.06 * 1e7 * 6.6 * 6.6, 1e-12));
}

TEST_CASE("Bouc-Wen under monotonic loading follows z = 1 - exp(-d / d_y) (alpha = 1, beta = 0, n = 1)") {
  // d_y dz/dd = 1 - z for dd > 0 and 0 <= z: integrate along d with unit rate v = 1.
  const Damper d = chimney_damper();
  const double dy = yield_displacement(d, B);
  auto rk = rocking::ode::make_rk45(1, [&](double, auto y, auto f) { f[0] = bouc_wen_rate(d, dy, 1.0, y[0]); },
                                    {.rtol = 1e-12, .atol = 1e-14});
  rk->reset(0.0, Eigen::VectorXd::Zero(1), {});
  rocking::ode::advance(*rk, 3 * dy);
  CHECK(rk->state()[0] == close_to(1.0 - std::exp(-3.0), 1e-9));
}

TEST_CASE("cyclic loading: z stays within [-1, 1] and every loop dissipates energy") {
  // d(t) = A sin(t) with A = 5 d_y; state (z, dissipated work of the hysteretic force).
  Damper d = chimney_damper();
  const double dy = yield_displacement(d, B), A = 5 * dy;
  for (double beta : {0.0, 0.5}) {
    d.alpha = 1.0 - beta;
    d.beta = beta;
    double worst = 0;
    auto rk = rocking::ode::make_rk45(2, [&](double t, auto y, auto f) {
      const double v = A * std::cos(t);
      f[0] = bouc_wen_rate(d, dy, v, y[0]);
      f[1] = damper_force(d, dy, A * std::sin(t), y[0]) * v;  // work done on the damper
    }, {.rtol = 1e-10, .atol = 1e-12});
    rk->reset(0.0, Eigen::VectorXd::Zero(2), {});
    double work_after_first = 0;
    for (int cycle = 1; cycle <= 3; ++cycle) {
      while (rk->time() < 2 * std::numbers::pi * cycle) {
        rk->step(2 * std::numbers::pi * cycle);
        worst = std::max(worst, std::abs(rk->state()[0]));
      }
      if (cycle == 1) work_after_first = rk->state()[1];
    }
    CAPTURE(beta);
    CHECK(worst <= 1.0 + 1e-9);
    // Steady loops: the same positive work per cycle (the elastic part cancels).
    const double per_cycle = (rk->state()[1] - work_after_first) / 2.0;
    CHECK(per_cycle > 0);
    // bounded by the rigid-plastic loop 4 (1 - eps) k d_y A
    CHECK(per_cycle < 4 * (1 - d.post_yield_ratio) * d.stiffness * dy * A);
  }
}

TEST_CASE("damper kinematics: chord of the lifted edge and its rate") {
  CHECK(damper_elongation(B, -0.1) == close_to(4 * B * std::sin(0.05), 1e-12));
  // v = d(d)/dt for theta > 0 about the right pivot (s = +1)
  const double th = 0.05, thd = 0.3, h = 1e-6;
  const double numeric = (damper_elongation(B, th + h * thd) - damper_elongation(B, th - h * thd)) / (2 * h);
  CHECK(damper_rate(B, th, thd, Pivot::right) == close_to(numeric, 1e-8));
  CHECK(damper_rate(B, -th, -thd, Pivot::left) == close_to(numeric, 1e-8));
}
