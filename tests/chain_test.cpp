// rocking.chain: the generic Lagrange assembly of a chain of rocking segments
// (MODEL.md 15) against the one-joint equations of rocking.dynamics, the closed
// forms of section 15, and energy. Integrations use GSL's rk8pd at rtol 1e-13
// (chain_ode.hpp), so that the tolerances below (1e-6 for event times and
// ratios, 1e-9 for energy) sit orders of magnitude above the integration error
// and far below any modelling error they are meant to catch.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <gsl/gsl_integration.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "chain_segment.hpp"
#include "chain_ode.hpp"
#include "close.hpp"
#include "chain_sums.hpp"
#include "chain_reference.hpp"
#include "records.hpp"
import rocking.chain;
import rocking.dynamics;
import rocking.scene;
import rocking.ground_motion;
import rocking.records;

using namespace rocking;
using Vec = Eigen::VectorXd;

namespace {

ChainSegment rigid_segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses) {
  return chain_segment<ChainSegment>(h, B, m0, std::move(heights), std::move(masses));
}

}  // namespace

TEST_CASE("one joint: the generic assembly gives the chimney's and the rigid block's equations to round-off") {
  std::mt19937 rng(54);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const Structure chimney = load_default_scene().structure;
  Structure block = chimney;
  block.rigid = true;
  double worst = 0;
  for (const Structure* st : {&chimney, static_cast<const Structure*>(&block)}) {
    const RockingBody body = make_body(*st);
    const Chain chain = make_chain(split_structure(*st, {}));
    ChainWorkspace w = make_workspace(chain);
    const int n = static_cast<int>(st->heights.size());
    REQUIRE(chain.size == (st->rigid ? 1 : 1 + n));
    for (int trial = 0; trial < 20; ++trial) {
      for (const Pivot p : pivots) {
        const int s = sign(p);
        const GroundAcceleration a{3.0 * U(rng), 2.0 * U(rng)};
        const double th = s * 0.15 * std::abs(U(rng)), th_dot = 0.3 * U(rng);
        Vec u = Vec::Zero(n), u_dot = Vec::Zero(n);
        if (!st->rigid)
          for (int i = 0; i < n; ++i) u[i] = 0.02 * U(rng), u_dot[i] = 0.2 * U(rng);
        Vec q(chain.size), q_dot(chain.size), q_ddot(chain.size);
        q << th, u.head(chain.size - 1);
        q_dot << th_dot, u_dot.head(chain.size - 1);
        const Phase phases[] = {Phase::rocking(p)};
        chain_acceleration(chain, phases, a, q, q_dot, q_ddot, w);
        if (st->rigid) {
          const double expected = rigid_rocking_acceleration(body, p, a, 0.0, Tilt(th));
          CHECK_MESSAGE(q_ddot[0] == close_to(expected, 1e-12), q_ddot[0] << " vs " << expected);
          worst = std::max(worst, std::abs(q_ddot[0] / expected - 1));
        } else {
          Vec rates(2 * n);
          const double expected = rocking_acceleration(body, p, a, 0.0, {u, u_dot, Tilt(th), th_dot}, rates);
          CHECK_MESSAGE(q_ddot[0] == close_to(expected, 1e-12), q_ddot[0] << " vs " << expected);
          const double err = (q_ddot.tail(n) - rates.tail(n)).lpNorm<Eigen::Infinity>() / rates.tail(n).lpNorm<Eigen::Infinity>();
          CHECK(err <= 1e-12);
          worst = std::max({worst, err, std::abs(q_ddot[0] / expected - 1)});
          // full contact (Eq. 1)
          const Phase contact[] = {Phase::full_contact()};
          q[0] = q_dot[0] = 0.0;
          chain_acceleration(chain, contact, a, q, q_dot, q_ddot, w);
          full_contact_acceleration(body, a.h, u, u_dot, rates);
          const double err_fc = (q_ddot.tail(n) - rates.tail(n)).lpNorm<Eigen::Infinity>() / rates.tail(n).lpNorm<Eigen::Infinity>();
          CHECK(err_fc <= 1e-12);
          CHECK(q_ddot[0] == 0.0);
          worst = std::max(worst, err_fc);
        }
      }
    }
  }
  MESSAGE("largest relative difference from rocking.dynamics: " << worst);
}

namespace {

// A slender block (joint 1, B = 0.15) on a heavy, wide one (joint 0, B = 3).
ChainData slender_on_wide() {
  ChainData d;
  d.segments.push_back(rigid_segment(0.0, 3.0, 2.0e4, {1.0, 2.0}, {2.0e4, 2.0e4}));
  d.segments.push_back(rigid_segment(2.0, 0.15, 100.0, {2.5, 3.0, 3.5}, {100.0, 100.0, 100.0}));
  return d;
}

}  // namespace

TEST_CASE("a slender block on a heavy wide block: first impact at the energy quadrature, r = 1 - 2 m B^2 / J_p, the lower block never lifts") {
  const ChainData d = slender_on_wide();
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  const SegmentSums up = sums_above(d, 1);
  const double B = d.segments[1].half_width, g = d.g;
  const double alpha = std::atan(B * up.mass / up.first);
  const double th0 = 0.6 * alpha;
  const std::vector<Phase> phases = {Phase::full_contact(), Phase::rocking(Pivot::right)};

  const double t_quad = release_to_impact_time(th0, up, B, g);

  double worst_guard = -1e300;  // largest (s M - N B) / (N B) of joint 0, either pivot
  std::vector<JointReaction> reactions(2);
  Vec q_ddot(chain.size);
  auto rhs = [&](double, const double* y, double* f) {
    const Eigen::Map<const Vec> q(y, 2), v(y + 2, 2);
    chain_acceleration(chain, phases, {}, q, v, q_ddot, w);
    f[0] = y[2], f[1] = y[3], f[2] = q_ddot[0], f[3] = q_ddot[1];
  };
  auto watch = [&](double, const double* y) {
    const Eigen::Map<const Vec> q(y, 2), v(y + 2, 2);
    chain_reactions(chain, phases, {}, q, v, reactions, q_ddot, w);
    for (const Pivot p : pivots)
      worst_guard = std::max(worst_guard, uplift_guard(chain, 0, p, reactions[0]) / (reactions[0].N * d.segments[0].half_width));
  };
  const chain_ode::Crossing hit = chain_ode::integrate(rhs, 0.0, {0.0, th0, 0.0, 0.0}, 10.0,
                                                       [](double, const double* y) { return y[1]; }, watch);
  REQUIRE(hit.found);
  CHECK_MESSAGE(hit.t == close_to(t_quad, 1e-6), "impact at " << hit.t << " s, quadrature " << t_quad << " s");
  MESSAGE("first impact " << hit.t << " s vs quadrature " << t_quad << " s: " << std::abs(hit.t / t_quad - 1));
  CHECK(worst_guard < 0);
  MESSAGE("joint 0's largest guard / (N B) before the impact: " << worst_guard);

  const Vec q = Eigen::Map<const Vec>(hit.y.data(), 2), q_dot = Eigen::Map<const Vec>(hit.y.data() + 2, 2);
  const ImpactOutcome out = chain_impact(chain, phases, 1, Vec::Zero(2), q_dot);
  REQUIRE(out.status == ImpactStatus::unique);
  CHECK(out.phases[0] == Phase::full_contact());  // the lower block stays down through the impact
  CHECK(out.phases[1] == Phase::rocking(Pivot::left));
  CHECK(out.uplifted.empty());
  const double r = 1.0 - 2.0 * up.mass * B * B / up.J;
  CHECK_MESSAGE(out.q_dot[1] / q_dot[1] == close_to(r, 1e-6), "ratio " << out.q_dot[1] / q_dot[1] << " vs " << r);
  MESSAGE("rate ratio " << out.q_dot[1] / q_dot[1] << " vs Eq. 10's " << r);
  (void)q;
}

namespace {

// The first uplift of a rigid stack at rest under a_g = c t with constant a_v:
// the time at which a joint's guard (its reactions) reaches its corner, found
// by Brent's method on the guard.
struct Uplift {
  int joint = -1;
  Pivot pivot = Pivot::right;
  double t = 0;
};
Uplift first_uplift(const Chain& chain, double c, double a_v, double t_max) {
  ChainWorkspace w = make_workspace(chain);
  const std::vector<Phase> phases(chain.joints);
  const Vec zero = Vec::Zero(chain.size);
  Vec q_ddot(chain.size);
  std::vector<JointReaction> r(chain.joints);
  struct Args {
    const Chain* chain;
    ChainWorkspace* w;
    const std::vector<Phase>* phases;
    const Vec* zero;
    Vec* q_ddot;
    std::vector<JointReaction>* r;
    double c, a_v;
    int joint;
    Pivot p;
  } args{&chain, &w, &phases, &zero, &q_ddot, &r, c, a_v, 0, Pivot::right};
  auto guard = [](double t, void* vp) {
    auto& a = *static_cast<Args*>(vp);
    chain_reactions(*a.chain, *a.phases, {a.c * t, a.a_v}, *a.zero, *a.zero, *a.r, *a.q_ddot, *a.w);
    return uplift_guard(*a.chain, a.joint, a.p, (*a.r)[a.joint]);
  };
  Uplift best;
  best.t = t_max;
  for (int j = 0; j < chain.joints; ++j)
    for (const Pivot p : pivots) {
      args.joint = j;
      args.p = p;
      gsl_function F{guard, &args};
      if (guard(0.0, &args) >= 0 || guard(t_max, &args) <= 0) continue;
      gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
      gsl_root_fsolver_set(s, &F, 0.0, t_max);
      double lo = 0, hi = t_max;
      for (int it = 0; it < 200; ++it) {
        gsl_root_fsolver_iterate(s);
        lo = gsl_root_fsolver_x_lower(s);
        hi = gsl_root_fsolver_x_upper(s);
        if (gsl_root_test_interval(lo, hi, 0.0, 1e-14) == GSL_SUCCESS) break;
      }
      gsl_root_fsolver_free(s);
      if (0.5 * (lo + hi) < best.t) best = {j, p, 0.5 * (lo + hi)};
    }
  return best;
}

void check_ramp(const ChainData& d, int expected_joint) {
  const Chain chain = make_chain(d);
  const double c = 0.5, a_v = -0.15 * d.g;  // a_g = 0.5 t m/s^2, a shaken-down ground
  std::vector<double> threshold;
  for (int j = 0; j < chain.joints; ++j) {
    const SegmentSums s = sums_above(d, j);
    threshold.push_back(d.segments[j].half_width / (s.first / s.mass));  // B_j / (H_cg,j - h_j)
  }
  const int smallest = static_cast<int>(std::min_element(threshold.begin(), threshold.end()) - threshold.begin());
  REQUIRE(smallest == expected_joint);
  const double t_exact = threshold[smallest] * (d.g + a_v) / c;
  const Uplift u = first_uplift(chain, c, a_v, 10.0 * t_exact);
  CHECK(u.joint == smallest);
  CHECK(u.pivot == Pivot::left);  // a_g > 0: the inertia forces push left
  CHECK_MESSAGE(u.t == close_to(t_exact, 1e-6), "joint " << u.joint << " lifts at " << u.t << " s, exact " << t_exact);
  MESSAGE("joint " << u.joint << " lifts at " << u.t << " s, closed form " << t_exact << ": " << std::abs(u.t / t_exact - 1));
  // Just past the guard the corner accelerates away from the face; just
  // before, it would be pressed into it.
  ChainWorkspace w = make_workspace(chain);
  const std::vector<Phase> phases(chain.joints);
  const Vec zero = Vec::Zero(chain.size);
  CHECK(corner_acceleration(chain, phases, u.joint, Pivot::left, {c * u.t * (1 + 1e-6), a_v}, zero, zero, w) > 0);
  CHECK(corner_acceleration(chain, phases, u.joint, Pivot::left, {c * u.t * (1 - 1e-6), a_v}, zero, zero, w) < 0);
}

}  // namespace

TEST_CASE("a rigid stack under a ramp a_g = c t: the joint with the smaller static threshold lifts first, at threshold (g + a_v) / c") {
  SUBCASE("slender top: the upper joint lifts first") {
    ChainData d;
    d.segments.push_back(rigid_segment(0.0, 1.0, 800.0, {1.0, 2.0}, {1000.0, 1000.0}));
    d.segments.push_back(rigid_segment(2.0, 0.2, 50.0, {2.5, 3.0, 3.5}, {100.0, 100.0, 100.0}));
    check_ramp(d, 1);
  }
  SUBCASE("squat top: the base joint lifts first") {
    ChainData d;
    d.segments.push_back(rigid_segment(0.0, 0.3, 300.0, {1.0, 2.0, 3.0}, {400.0, 400.0, 400.0}));
    d.segments.push_back(rigid_segment(3.0, 1.0, 200.0, {3.4, 3.8}, {300.0, 300.0}));
    check_ramp(d, 0);
  }
}

TEST_CASE("a top that cannot lift: the run equals the one-joint structure with the same masses") {
  ChainData d;
  d.segments.push_back(rigid_segment(0.0, 0.5, 1000.0, {1.0, 2.0, 3.0}, {800.0, 800.0, 600.0}));
  d.segments.push_back(rigid_segment(3.0, 0.8, 300.0, {3.5, 4.0}, {400.0, 200.0}));
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  Structure merged;  // the top's slab joins the node it stands on
  merged.rigid = true;
  merged.half_width = 0.5;
  merged.base_mass = 1000.0;
  merged.heights = (Vec(5) << 1.0, 2.0, 3.0, 3.5, 4.0).finished();
  merged.masses = (Vec(5) << 800.0, 800.0, 900.0, 400.0, 200.0).finished();
  const RockingBody body = make_body(merged);
  const std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::full_contact()};
  auto ground = [](double t) {  // smooth: no breakpoint for either run
    return GroundAcceleration{2.0 * std::sin(2 * std::numbers::pi * t / 0.7) * std::exp(-t), 1.5 * std::sin(2 * std::numbers::pi * t / 0.3) * std::exp(-t)};
  };
  Vec q(2), v(2), acc(2);
  std::vector<JointReaction> r(2);
  double worst_guard = -1e300, worst_diff = 0, peak = 0;
  auto rhs = [&](double t, const double* y, double* f) {
    q << y[0], 0.0;
    v << y[1], 0.0;
    chain_acceleration(chain, phases, ground(t), q, v, acc, w);
    f[0] = y[1];
    f[1] = acc[0];
    f[2] = y[3];
    f[3] = rigid_rocking_acceleration(body, Pivot::right, ground(t), 0.0, Tilt(y[2]));
  };
  auto watch = [&](double t, const double* y) {
    q << y[0], 0.0;
    v << y[1], 0.0;
    chain_reactions(chain, phases, ground(t), q, v, r, acc, w);
    for (const Pivot p : pivots) worst_guard = std::max(worst_guard, uplift_guard(chain, 1, p, r[1]) / (r[1].N * 0.8));
    worst_diff = std::max(worst_diff, std::abs(y[0] - y[2]));
    peak = std::max(peak, std::abs(y[0]));
  };
  const double th0 = 0.4 * slenderness(merged);
  const chain_ode::Crossing hit = chain_ode::integrate(rhs, 0.0, {th0, 0.0, th0, 0.0}, 5.0,
                                                       [](double, const double* y) { return y[0]; }, watch);
  CHECK(hit.t > 0.3);  // a real rocking phase, through the pulse's first cycles
  CHECK(worst_guard < 0);
  CHECK(worst_diff <= 1e-10 * peak);
  MESSAGE("one-joint vs chain, largest |theta difference| / peak theta: " << worst_diff / peak << " over " << hit.t
                                                                        << " s; top joint's largest guard / (N B) " << worst_guard);
}

namespace {

// Largest |E(t) - E(0)| / E(0) of a free, undamped motion from rest at q0 up to
// the first time an open joint's theta returns to 0 (or t_end).
double energy_drift(const Chain& chain, const std::vector<Phase>& phases, const Vec& q0, double t_end, double* duration) {
  ChainWorkspace w = make_workspace(chain);
  const int n = chain.size;
  Vec acc(n);
  auto rhs = [&](double, const double* y, double* f) {
    const Eigen::Map<const Vec> q(y, n), v(y + n, n);
    chain_acceleration(chain, phases, {}, q, v, acc, w);
    for (int k = 0; k < n; ++k) f[k] = y[n + k], f[n + k] = acc[k];
  };
  std::vector<double> y0(2 * n, 0.0);
  for (int k = 0; k < n; ++k) y0[k] = q0[k];
  const double e0 = chain_energy(chain, phases, q0, Vec::Zero(n), w).total();
  double worst = 0;
  auto watch = [&](double, const double* y) {
    const Eigen::Map<const Vec> q(y, n), v(y + n, n);
    worst = std::max(worst, std::abs(chain_energy(chain, phases, q, v, w).total() / e0 - 1));
  };
  auto guard = [&](double, const double* y) {
    double g = 1e300;
    for (int j = 0; j < chain.joints; ++j)
      if (phases[j].is_rocking()) g = std::min(g, phases[j].sign() * y[j]);
    return g;
  };
  const chain_ode::Crossing hit = chain_ode::integrate(rhs, 0.0, y0, t_end, guard, watch);
  *duration = hit.t;
  return worst;
}

}  // namespace

TEST_CASE("free undamped rocking at two joints conserves energy to 1e-9 between impacts") {
  SUBCASE("two rigid blocks rocking about opposite corners") {
    ChainData d;
    d.segments.push_back(rigid_segment(0.0, 0.4, 500.0, {1.0, 2.0}, {1000.0, 1000.0}));
    d.segments.push_back(rigid_segment(2.0, 0.2, 100.0, {2.5, 3.0, 3.5}, {200.0, 200.0, 200.0}));
    const Chain chain = make_chain(d);
    const std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::rocking(Pivot::left)};
    double duration = 0;
    const double drift = energy_drift(chain, phases, (Vec(2) << 0.08, -0.05).finished(), 10.0, &duration);
    CHECK(duration > 0.1);
    CHECK(drift <= 1e-9);
    MESSAGE("rigid stack: relative energy drift " << drift << " over " << duration << " s");
  }
  SUBCASE("the chimney cracked at node 3 (a rigid top on the flexible shaft), both joints rocking, elastic and joint-node rotation coordinates moving") {
    Structure s = load_default_scene({"structure.damping_ratio=0.0"}).structure;
    const ChainJointSpec crack[] = {{3, 1.5, 5000.0, true}};
    const Chain chain = make_chain(split_structure(s, crack));
    REQUIRE(chain.size == 2 + 3 + 1);  // theta 0, theta 1, u of nodes 1-3, phi of node 3
    const std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::rocking(Pivot::right)};
    double duration = 0;
    const Vec q0 = (Vec(6) << 0.05, 0.02, 0.002, 0.005, 0.01, 0.0008).finished();
    const double drift = energy_drift(chain, phases, q0, 1.5, &duration);
    CHECK(duration > 0.1);
    CHECK(drift <= 1e-9);
    MESSAGE("cracked chimney: relative energy drift " << drift << " over " << duration << " s");
  }
}

TEST_CASE("with damping, a tendon and ground motion at both joints, the energy balance closes: dE/dt = P_ground - P_damping") {
  Structure s = load_default_scene().structure;  // Rayleigh 3.5 %
  const ChainJointSpec crack[] = {{3, 1.5, 5000.0, true}};
  ChainData d = split_structure(s, crack);
  ChainTendon t;
  t.from = {-1, 0.0, 0.0};
  t.to = {0, 0.3, 0.0, 2};  // off the centre line, moving with node 3 (the shaft's top)
  t.prestress = 5e5;
  t.stiffness = 2e7;
  d.tendons.push_back(t);
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  const std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::rocking(Pivot::right)};
  const int n = chain.size;
  auto ground = [](double t) {
    return GroundAcceleration{3.0 * std::sin(2 * std::numbers::pi * t / 0.9), 1.5 * std::sin(2 * std::numbers::pi * t / 0.4 + 0.3)};
  };
  Vec acc(n);
  auto rhs = [&](double t, const double* y, double* f) {
    const Eigen::Map<const Vec> q(y, n), v(y + n, n);
    chain_acceleration(chain, phases, ground(t), q, v, acc, w);
    for (int k = 0; k < n; ++k) f[k] = y[n + k], f[n + k] = acc[k];
    const ChainPower p = chain_power(chain, phases, ground(t), q, v, w);
    f[2 * n] = p.ground - p.damping;
  };
  std::vector<double> y0(2 * n + 1, 0.0);
  y0[0] = 0.03;
  y0[1] = 0.02;
  const Vec q0 = Eigen::Map<const Vec>(y0.data(), n);
  const double e0 = chain_energy(chain, phases, q0, Vec::Zero(n), w).total();
  double worst = 0, scale = 0, tendon_peak = 0;
  auto watch = [&](double, const double* y) {
    const Eigen::Map<const Vec> q(y, n), v(y + n, n);
    const ChainEnergy e = chain_energy(chain, phases, q, v, w);
    worst = std::max(worst, std::abs(e.total() - e0 - y[2 * n]));
    scale = std::max({scale, std::abs(e.total() - e0), std::abs(y[2 * n]), e.kinetic, e.tendons});
    tendon_peak = std::max(tendon_peak, e.tendons);
  };
  auto guard = [](double, const double* y) { return std::min(y[0], y[1]); };
  const chain_ode::Crossing hit = chain_ode::integrate(rhs, 0.0, y0, 1.5, guard, watch);
  CHECK(hit.t > 0.1);
  CHECK(tendon_peak > 0);
  CHECK(worst <= 1e-9 * scale);
  MESSAGE("balance residual " << worst << " J against a scale of " << scale << " J over " << hit.t << " s");
}

TEST_CASE("bad chains are refused with the field named") {
  ChainData d;
  d.segments.push_back(rigid_segment(0.0, 0.5, 100.0, {1.0, 2.0}, {100.0, 100.0}));
  d.segments.push_back(rigid_segment(2.0, 0.0, 100.0, {3.0}, {100.0}));
  CHECK_THROWS_WITH_AS(make_chain(d), doctest::Contains("segments[1].half_width"), std::invalid_argument);
  d.segments[1].half_width = 0.3;
  d.segments[1].base_height = 1.5;
  CHECK_THROWS_WITH_AS(make_chain(d), doctest::Contains("segments[1].base_height"), std::invalid_argument);
  d.segments[1].base_height = 2.0;
  ChainTendon t;
  t.to = {2, 0.0, 1.0};
  d.tendons.push_back(t);
  CHECK_THROWS_WITH_AS(make_chain(d), doctest::Contains("tendons[0].to.segment"), std::invalid_argument);
  const Structure chimney = load_default_scene().structure;
  const ChainJointSpec flexible_on_flexible[] = {{3, 1.0, 1000.0}};
  CHECK_THROWS_WITH_AS(make_chain(split_structure(chimney, flexible_on_flexible)), doctest::Contains("segments[1].rigid"),
                       std::invalid_argument);
  const ChainJointSpec at_top[] = {{4, 1.0, 0.0}};
  CHECK_THROWS_WITH_AS(split_structure(chimney, at_top), doctest::Contains("joint[1].node"), std::invalid_argument);
  const ChainJointSpec out_of_order[] = {{3, 1.0, 0.0}, {2, 1.0, 0.0}};
  CHECK_THROWS_WITH_AS(split_structure(chimney, out_of_order), doctest::Contains("joint[2].node"), std::invalid_argument);
}

TEST_CASE("over a run with impacts, energy plus the losses the momentum law takes stays constant to 1e-9") {
  ChainData d;
  d.segments.push_back(rigid_segment(0.0, 0.4, 500.0, {1.0, 2.0}, {1000.0, 1000.0}));
  d.segments.push_back(rigid_segment(2.0, 0.2, 100.0, {2.5, 3.0, 3.5}, {200.0, 200.0, 200.0}));
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  const int n = chain.size;
  std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::rocking(Pivot::left)};
  std::vector<double> y = {0.08, -0.05, 0.0, 0.0};
  const double e0 = chain_energy(chain, phases, Vec::Map(y.data(), n), Vec::Zero(n), w).total();
  double losses = 0, worst = 0, t = 0;
  int impacts = 0, uplifts = 0;
  Vec acc(n);
  std::vector<JointReaction> r(chain.joints);
  auto rhs = [&](double, const double* s, double* f) {
    chain_acceleration(chain, phases, {}, Vec::Map(s, n), Vec::Map(s + n, n), acc, w);
    for (int k = 0; k < n; ++k) f[k] = s[n + k], f[n + k] = acc[k];
  };
  // Positive while every phase lasts: s theta of an open joint, the distance
  // of a closed joint's resultant from its nearer corner.
  auto guards = [&](const double* s, std::vector<double>& g) {
    chain_reactions(chain, phases, {}, Vec::Map(s, n), Vec::Map(s + n, n), r, acc, w);
    for (int j = 0; j < chain.joints; ++j)
      g[j] = phases[j].is_rocking() ? phases[j].sign() * s[j]
                                    : -std::max(uplift_guard(chain, j, Pivot::right, r[j]), uplift_guard(chain, j, Pivot::left, r[j])) /
                                          (r[j].N * d.segments[j].half_width);
  };
  std::vector<double> g(chain.joints);
  auto guard = [&](double, const double* s) {
    guards(s, g);
    return *std::min_element(g.begin(), g.end());
  };
  auto watch = [&](double, const double* s) {
    const double e = chain_energy(chain, phases, Vec::Map(s, n), Vec::Map(s + n, n), w).total();
    worst = std::max(worst, std::abs(e + losses - e0) / e0);
  };
  while (t < 4.0 && impacts < 40) {
    const chain_ode::Crossing hit = chain_ode::integrate(rhs, t, y, 4.0, guard, watch);
    t = hit.t;
    y = hit.y;
    if (!hit.found) break;
    guards(y.data(), g);
    const int j = static_cast<int>(std::min_element(g.begin(), g.end()) - g.begin());
    if (phases[j].is_rocking()) {  // impact
      y[j] = 0.0;
      const Vec q = Vec::Map(y.data(), n), v = Vec::Map(y.data() + n, n);
      if (std::abs(v[j]) < 1e-3) break;  // the motion is dying out: chattering would follow
      const double before = chain_energy(chain, phases, q, v, w).total();
      const ImpactOutcome out = chain_impact(chain, phases, j, q, v);
      REQUIRE(out.status == ImpactStatus::unique);
      phases = out.phases;
      for (int k = 0; k < n; ++k) y[n + k] = out.q_dot[k];
      const double after = chain_energy(chain, phases, q, out.q_dot, w).total();
      CHECK(after <= before);
      losses += before - after;
      ++impacts;
    } else {  // uplift about the corner the resultant reached
      phases[j] = Phase::rocking(uplift_guard(chain, j, Pivot::right, r[j]) > 0 ? Pivot::right : Pivot::left);
      y[j] = y[n + j] = 0.0;
      ++uplifts;
    }
  }
  CHECK(impacts >= 3);
  CHECK(losses > 0);
  CHECK(worst <= 1e-9);
  MESSAGE(impacts << " impacts, " << uplifts << " uplifts in " << t << " s; impact losses " << losses / e0
                  << " of E0; largest |E + losses - E0| / E0 " << worst);
}

namespace {

// Four rigid post-tensioned segments (1.5 m tall, B = 0.35 m) on the ground,
// a central tendon from the foundation to the top: in the engine's data and in
// the independent reference's (tests/chain_reference.hpp, written from MODEL.md alone).
constexpr double pier_h = 1.5, pier_B = 0.35, pier_slab = 3000.0, pier_mid = 6000.0, pier_top = 1000.0;
constexpr double pier_P0 = 1.5e5, pier_k = 1.0e7;

ChainData pier() {
  ChainData d;
  for (int j = 0; j < 4; ++j)
    d.segments.push_back(rigid_segment(j * pier_h, pier_B, pier_slab, {j * pier_h + 0.75, (j + 1) * pier_h}, {pier_mid, pier_top}));
  ChainTendon t;
  t.from = {-1, 0.0, 0.0};
  t.to = {3, 0.0, pier_h};
  t.prestress = pier_P0;
  t.stiffness = pier_k;
  d.tendons.push_back(t);
  return d;
}

chainref::Chain pier_reference() {
  chainref::Chain c;
  for (int j = 0; j < 4; ++j) {
    chainref::Segment s;
    s.h = j * pier_h;
    s.B = pier_B;
    s.m0 = pier_slab;
    s.masses = {{j * pier_h + 0.75, pier_mid}, {(j + 1) * pier_h, pier_top}};
    c.seg.push_back(s);
  }
  c.H_top = 4 * pier_h;
  c.tendon = chainref::Tendon{true, 0.0, pier_P0, pier_k};
  return c;
}

}  // namespace

TEST_CASE("segmental pier under El Centro: the engine agrees with an independent integration to 1e-6 up to the first impact, and so does the tendon") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion record = read_record(*dir + "/elcentro_1940_ns.at2");
  const std::vector<double> times = record.sample_times(), values = record.sample_values();
  REQUIRE(times.size() > 100);
  const Chain chain = make_chain(pier());
  ChainWorkspace w = make_workspace(chain);
  const int n = chain.size;
  REQUIRE(n == 4);
  // every joint open, the pier leaning right, from rest in the record's strong motion
  const std::vector<Phase> phases(4, Phase::rocking(Pivot::right));
  const std::vector<double> q0 = {0.012, 0.008, 0.005, 0.003};
  const double t0 = 2.0;
  Vec acc(n);
  auto rhs = [&](double t, const double* y, double* f) {
    chain_acceleration(chain, phases, {record.acceleration(t)}, Vec::Map(y, n), Vec::Map(y + n, n), acc, w);
    for (int k = 0; k < n; ++k) f[k] = y[n + k], f[n + k] = acc[k];
  };
  auto guard = [&](double, const double* y) {
    double g = 1e300;
    for (int j = 0; j < n; ++j) g = std::min(g, phases[j].sign() * y[j]);
    return g;
  };
  const chainref::Chain ref = pier_reference();
  const chainref::Phases ref_phases = {+1, +1, +1, +1};
  double worst_e = 0, peak_e = 0;
  auto watch = [&](double, const double* y) {  // the tendon against the reference's geometry
    const std::vector<double> q(y, y + n), qd(y + n, y + 2 * n);
    const double e = tendon_elongation(chain, phases, 0, Vec::Map(y, n), w);
    const double e_ref = chainref::tendon_state(ref, chainref::kinematics(ref, ref_phases, q, qd), qd).e;
    worst_e = std::max(worst_e, std::abs(e - e_ref));
    peak_e = std::max(peak_e, std::abs(e_ref));
  };
  // the record's samples are breakpoints: one integration per sample interval
  std::vector<double> y(2 * n, 0.0);
  for (int k = 0; k < n; ++k) y[k] = q0[k];
  double t = t0;
  bool hit = false;
  for (std::size_t i = 1; i < times.size() && !hit; ++i) {
    if (times[i] <= t) continue;
    const chain_ode::Crossing c = chain_ode::integrate(rhs, t, y, times[i], guard, watch);
    t = c.t;
    y = c.y;
    hit = c.found;
  }
  REQUIRE(hit);
  chainref::Ground G;
  G.ah_rec.t = times;
  G.ah_rec.a = values;
  chainref::IntegOpts opts;
  opts.rtol = 1e-13;
  opts.atol = 1e-15;
  const chainref::ImpactResult r = chainref::first_impact(ref, ref_phases, q0, std::vector<double>(n, 0.0), t0, times.back(), G, opts);
  REQUIRE(r.joint >= 0);
  CHECK(t - t0 > 0.01);  // the tendon closes the top joint within about 13 ms: a real phase all the same
  CHECK(phases[r.joint].sign() * y[r.joint] <= 1e-12);  // the same joint closes in both
  CHECK_MESSAGE(t == close_to(r.t, 1e-6), "first impact at " << t << " s, reference " << r.t << " s");
  double rate_scale = 0, angle_scale = 0, worst_rate = 0, worst_angle = 0;
  for (int k = 0; k < n; ++k) {
    rate_scale = std::max(rate_scale, std::abs(r.qd[k]));
    angle_scale = std::max(angle_scale, std::abs(q0[k]));
    worst_rate = std::max(worst_rate, std::abs(y[n + k] - r.qd[k]));
    worst_angle = std::max(worst_angle, std::abs(y[k] - r.q[k]));
  }
  CHECK(worst_rate <= 1e-6 * rate_scale);
  CHECK(worst_angle <= 1e-6 * angle_scale);
  CHECK(worst_e <= 1e-9 * peak_e);
  MESSAGE("joint " << r.joint << " impacts first at " << t << " s (reference " << r.t << " s, " << std::abs(t / r.t - 1)
                   << "); rates differ by " << worst_rate / rate_scale << ", angles by " << worst_angle / angle_scale
                   << " of their scales; tendon elongation by " << worst_e << " m (peak " << peak_e << " m)");
}

TEST_CASE("segmental pier under El Centro, the base joint rocking: the closed joints' reactions and the impact agree with the independent reference") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion record = read_record(*dir + "/elcentro_1940_ns.at2");
  const std::vector<double> times = record.sample_times(), values = record.sample_values();
  const Chain chain = make_chain(pier());
  ChainWorkspace w = make_workspace(chain);
  const int n = chain.size;
  const std::vector<Phase> phases = {Phase::rocking(Pivot::right), Phase::full_contact(), Phase::full_contact(), Phase::full_contact()};
  const chainref::Chain ref = pier_reference();
  const chainref::Phases ref_phases = {+1, 0, 0, 0};
  const double t0 = 2.0, th0 = 0.01;
  Vec acc(n);
  std::vector<JointReaction> r(chain.joints);
  auto rhs = [&](double t, const double* y, double* f) {
    chain_acceleration(chain, phases, {record.acceleration(t)}, Vec::Map(y, n), Vec::Map(y + n, n), acc, w);
    for (int k = 0; k < n; ++k) f[k] = y[n + k], f[n + k] = acc[k];
  };
  chainref::Ground G;
  G.ah_rec.t = times;
  G.ah_rec.a = values;
  double worst_reaction = 0, worst_guard = -1e300;
  auto watch = [&](double t, const double* y) {
    chain_reactions(chain, phases, {record.acceleration(t)}, Vec::Map(y, n), Vec::Map(y + n, n), r, acc, w);
    const std::vector<chainref::Reaction> rr = chainref::closed_joint_reactions(ref, ref_phases, {y[0]}, {y[n]}, t, G);
    for (int j = 1; j < 4; ++j) {
      const double scale = std::abs(rr[j].N);
      worst_reaction = std::max({worst_reaction, std::abs(r[j].N - rr[j].N) / scale, std::abs(r[j].V - rr[j].V) / scale,
                                 std::abs(r[j].M - rr[j].M) / (scale * pier_B)});
      for (const Pivot p : pivots) worst_guard = std::max(worst_guard, uplift_guard(chain, j, p, r[j]) / (r[j].N * pier_B));
    }
  };
  auto guard = [&](double, const double* y) { return y[0]; };
  std::vector<double> y(2 * n, 0.0);
  y[0] = th0;
  double t = t0;
  bool hit = false;
  for (std::size_t i = 1; i < times.size() && !hit; ++i) {
    if (times[i] <= t) continue;
    const chain_ode::Crossing c = chain_ode::integrate(rhs, t, y, times[i], guard, watch);
    t = c.t;
    y = c.y;
    hit = c.found;
  }
  REQUIRE(hit);
  chainref::IntegOpts opts;
  opts.rtol = 1e-13;
  opts.atol = 1e-15;
  const chainref::ImpactResult ri = chainref::first_impact(ref, ref_phases, {th0}, {0.0}, t0, times.back(), G, opts);
  REQUIRE(ri.joint == 0);
  CHECK(t - t0 > 0.2);
  CHECK_MESSAGE(t == close_to(ri.t, 1e-6), "first impact at " << t << " s, reference " << ri.t << " s");
  CHECK(y[n] == close_to(ri.qd[0], 1e-6));
  CHECK(worst_reaction <= 1e-9);
  CHECK(worst_guard < 0);  // the upper joints stay closed while the base rocks
  // the impact: the engine's outcome, and the reference's momentum law into the same phases
  y[0] = 0.0;
  const ImpactOutcome out = chain_impact(chain, phases, 0, Vec::Map(y.data(), n), Vec::Map(y.data() + n, n));
  REQUIRE(out.status == ImpactStatus::unique);
  chainref::Phases post(4);
  for (int j = 0; j < 4; ++j) post[j] = out.phases[j].sign();
  const chainref::PostImpact pi = chainref::momentum_impact(ref, ref_phases, ri.q, ri.qd, 0, post);
  double worst_post = 0, post_scale = 0;
  for (int j = 0, i = 0; j < 4; ++j) {
    if (post[j] == 0) continue;
    worst_post = std::max(worst_post, std::abs(out.q_dot[j] - pi.qd[i]));
    post_scale = std::max(post_scale, std::abs(pi.qd[i]));
    ++i;
  }
  CHECK(post_scale > 0);
  CHECK(worst_post <= 1e-6 * post_scale);
  MESSAGE("base joint impacts at " << t << " s (reference " << ri.t << " s, " << std::abs(t / ri.t - 1) << "), rate "
                                   << y[n] << " vs " << ri.qd[0] << "; closed joints' reactions within " << worst_reaction
                                   << " of N; after the impact phases " << post[0] << post[1] << post[2] << post[3]
                                   << ", rates within " << worst_post / post_scale);
}

TEST_CASE("the pier's tendon: one open joint stretches it by the rotation of the top anchor about that joint's corner") {
  const Chain chain = make_chain(pier());
  ChainWorkspace w = make_workspace(chain);
  const double H = 4 * pier_h;
  double sum_shares = 0;
  Vec all(4);
  for (int j = 0; j < 4; ++j)
    for (const Pivot p : pivots) {
      const int s = sign(p);
      std::vector<Phase> phases(4);
      phases[j] = Phase::rocking(p);
      Vec q = Vec::Zero(4);
      q[j] = s * 0.02;
      const double h = j * pier_h, th = q[j];
      // the top anchor (0, H) turned clockwise by theta about the corner (s B, h)
      const double x = s * pier_B - s * pier_B * std::cos(th) + (H - h) * std::sin(th);
      const double y = h + s * pier_B * std::sin(th) + (H - h) * std::cos(th);
      const double e = std::hypot(x, y) - H;
      CHECK(std::abs(tendon_elongation(chain, phases, 0, q, w) - e) <= 1e-14);
      if (p == Pivot::right) sum_shares += e, all[j] = th;
    }
  // With every joint open at once the straight tendon's elongation is the sum
  // of these shares to first order in theta only (MODEL.md 15 takes the
  // distance between the anchors); the difference is reported, not checked.
  const std::vector<Phase> open(4, Phase::rocking(Pivot::right));
  const double e_all = tendon_elongation(chain, open, 0, all, w);
  CHECK(e_all > 0);
  MESSAGE("all four joints open at 0.02 rad: elongation " << e_all << " m, sum of the joints' shares " << sum_shares
                                                          << " m, first order sum B theta " << 4 * pier_B * 0.02 << " m");
}

TEST_CASE("a stack in full contact: each joint's friction demand is a_g / (g + a_v), and a ground falling faster than gravity puts every joint in tension") {
  const Chain chain = make_chain(pier());
  ChainWorkspace w = make_workspace(chain);
  const std::vector<Phase> phases(4);
  const Vec zero = Vec::Zero(4);
  Vec acc(4);
  std::vector<JointReaction> r(4);
  const double g = chain.data.g, a_g = 2.5, a_v = 0.3 * g;
  chain_reactions(chain, phases, {a_g, a_v}, zero, zero, r, acc, w);
  for (int j = 0; j < 4; ++j) {
    // the part above j moves with the ground: V = -m a_g (the face holds it back), N = m (g + a_v) + P0
    const double m = (4 - j) * (pier_slab + pier_mid + pier_top);
    CHECK(r[j].N == close_to(m * (g + a_v) + pier_P0, 1e-12));
    CHECK(friction_demand(r[j]) == close_to(m * a_g / (m * (g + a_v) + pier_P0), 1e-12));
  }
  const Chain bare = make_chain([] {
    ChainData d = pier();
    d.tendons.clear();
    return d;
  }());
  ChainWorkspace wb = make_workspace(bare);
  chain_reactions(bare, phases, {0.0, -1.2 * g}, zero, zero, r, acc, wb);
  for (int j = 0; j < 4; ++j) CHECK(r[j].N < 0);
  CHECK(friction_demand(r[0]) == std::numeric_limits<double>::infinity());
}
