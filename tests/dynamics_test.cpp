// rocking.dynamics: the equations conserve energy where physics says they must,
// which decides the gravity sign of Eq. 4 (MODEL.md 9.2), and the full-contact
// equations vibrate at the fixed-base frequencies.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <algorithm>
#include <cmath>
#include <numbers>
import rocking.dynamics;
import rocking.scene;
import rocking.integrator;
#include "spread_nodes.hpp"

using namespace rocking;
using CRef = Eigen::Ref<const Eigen::VectorXd>;
using Ref = Eigen::Ref<Eigen::VectorXd>;

namespace {

// The chimney with no viscous damping (free, conservative).
RockingBody undamped_chimney() {
  Structure s = load_default_scene({"structure.damping_ratio=0.0"}).structure;
  return make_body(s);
}

// The chimney's mass and stiffness spread over 20 nodes: more than the sizes
// the kernels are unrolled for (static_size.hpp), so the general loops run.
RockingBody undamped_tower_of_20() {
  Structure s = load_default_scene({"structure.damping_ratio=0.0"}).structure;
  spread_over_nodes(s, 20);
  return make_body(s);
}

// Largest relative energy change over one free rocking phase about the right
// pivot, from theta0 = alpha_cg / 2 at rest until the impact (theta = 0).
// paper_sign = true uses the gravity sign printed in the paper's Eq. 4.
double energy_drift_over_one_phase(bool paper_sign, double* phase_duration,
                                   const RockingBody& body = undamped_chimney()) {
  const Eigen::Index n = body.structure.heights.size();
  auto rhs = [&](double, CRef y, Ref f) {
    const Coordinates q{y.head(n), y.segment(n, n), y[2 * n], y[2 * n + 1]};
    f[2 * n] = y[2 * n + 1];
    double th_ddot = rocking_acceleration(body, Pivot::right, 0.0, 0.0, q, f.head(2 * n));  // u', u''
    Eigen::Ref<Eigen::VectorXd> u_ddot = f.segment(n, n);
    if (paper_sign) {
      // rhs_u loses 2 M1 g sin(th); propagate through the closed-form solve
      const auto& st = body.structure;
      const Eigen::ArrayXd w = st.half_width - y.head(n).array();
      const double Dm = st.base_mass * st.half_width * st.half_width + (st.masses.array() * w.square()).sum();
      const double extra = -2.0 * body.g * std::sin(y[2 * n]);  // per unit mass
      const double dth = -st.heights.dot(st.masses) * extra / Dm;
      th_ddot += dth;
      u_ddot.array() += extra - st.heights.array() * dth;
    }
    f[2 * n + 1] = th_ddot;
  };
  auto rk = ode::make_rk45(2 * n + 2, rhs, {.rtol = 1e-12, .atol = 1e-14});
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(2 * n + 2);
  y0[2 * n] = 0.5 * slenderness(body.structure);
  rk->reset(0.0, y0, {[n](double, CRef y, Ref g) { g[0] = y[2 * n]; }, {ode::Direction::falling}});
  auto energy = [&](const Eigen::VectorXd& y) {
    return mechanical_energy(body, Pivot::right, {y.head(n), y.segment(n, n), y[2 * n], y[2 * n + 1]});
  };
  const double e0 = energy(y0);
  double worst = 0;
  for (;;) {
    const ode::StepReport r = rk->step(10.0);
    worst = std::max(worst, std::abs(energy(rk->state()) / e0 - 1.0));
    if (r.reason != ode::Stop::step) break;
  }
  *phase_duration = rk->time();
  return worst;
}

}  // namespace

TEST_CASE("free undamped rocking conserves energy to 1e-9 over a whole rocking phase") {
  double duration = 0;
  const double drift = energy_drift_over_one_phase(false, &duration);
  CHECK(duration > 1.0);  // a real phase: tilted to alpha/2, it falls back in about 2 s
  CHECK(drift < 1e-9);
}

TEST_CASE("free undamped rocking of a 20-node tower conserves energy too (the general, not unrolled, loops)") {
  double duration = 0;
  const double drift = energy_drift_over_one_phase(false, &duration, undamped_tower_of_20());
  CHECK(duration > 1.0);
  CHECK(drift < 1e-9);
}

TEST_CASE("the gravity sign printed in Eq. 4 does not conserve energy (MODEL.md 9.2)") {
  double duration = 0;
  const double drift = energy_drift_over_one_phase(true, &duration);
  CHECK(drift > 1e-5);  // MODEL.md: about 4e-4 per second
}

TEST_CASE("full contact, undamped: a first-mode shape returns after one fixed-base period") {
  for (const RockingBody& body : {undamped_chimney(), undamped_tower_of_20()}) {
  CAPTURE(body.structure.heights.size());
  const Eigen::Index n = body.structure.heights.size();
  const Eigen::VectorXd phi = body.matrices.fixed_base.shapes.col(0);
  const double period = 2 * std::numbers::pi / body.matrices.fixed_base.omega[0];
  auto rk = ode::make_rk45(2 * n, [&](double, CRef y, Ref f) {
    full_contact_acceleration(body, 0.0, y.head(n), y.tail(n), f);  // u', u''
  }, {.rtol = 1e-12, .atol = 1e-15});
  Eigen::VectorXd y0 = Eigen::VectorXd::Zero(2 * n);
  y0.head(n) = 1e-3 * phi / phi[n - 1];  // 1 mm at the top
  rk->reset(0.0, y0, {});
  // rtol 1e-12 over one and a half periods: the global error stays within a
  // few hundred local tolerances, far inside 1e-9.
  ode::advance(*rk, period);
  CHECK((rk->state().head(n) - y0.head(n)).norm() < 1e-9 * y0.head(n).norm());
  // and half a period later it is the mirror image
  ode::advance(*rk, 1.5 * period);
  CHECK((rk->state().head(n) + y0.head(n)).norm() < 1e-9 * y0.head(n).norm());
  }
}
