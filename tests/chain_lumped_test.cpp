// rocking.chain's lumped path against its general one, state by state: a
// segment enters M and Q through its slab frame and its lumped mass and
// moments, a flexible one with its nodes' sums over u and u' and its own u
// columns' terms (ChainWorkspace::per_point false), where the general path
// sums every mass point's Jacobian (per_point true). Both are the same equations, so on
// random states, ground accelerations and every combination of joint phases
// their right-hand sides, reactions, powers and energies agree to round-off:
// 1e-12 relative (of each vector's largest entry for a component that may
// cancel to nothing; of g sum m y_rest, absolute, for gravity's energy). The
// corner accelerations that chain_reactions gives from its own factorisation
// agree with corner_acceleration's trial solve, and anchor_position's
// positions with the general path's points, to 1e-12 of the chain's height.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "chain_segment.hpp"
#include "close.hpp"
#include "vector_close.hpp"
import rocking.chain;
import rocking.geometry;
import rocking.dynamics;

using namespace rocking;
using Vec = Eigen::VectorXd;

namespace {

constexpr double tol = 1e-12;

ChainSegment segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses,
                     bool rigid = true, std::vector<double> EI = {}) {
  return chain_segment<ChainSegment>(h, B, m0, std::move(heights), std::move(masses), rigid, std::move(EI));
}

// The chains compared: the stacked blocks, the segmental pier with its tendon,
// a flexible shaft under two rigid segments, with a tendon anchored on a
// moving node, and a flexible shaft on a rigid pedestal under a rigid top (its
// slab frame turning and translating with the pedestal).
std::vector<std::pair<std::string, ChainData>> chains() {
  std::vector<std::pair<std::string, ChainData>> out;
  ChainData blocks;
  blocks.segments.push_back(segment(0.0, 0.4, 50.0, {0.25, 0.75, 1.0}, {550.0, 550.0, 50.0}));
  blocks.segments.push_back(segment(1.0, 0.15, 0.0, {1.15, 1.45, 1.75}, {40.0, 40.0, 40.0}));
  out.emplace_back("stacked blocks", blocks);

  ChainData pier;
  for (int j = 0; j < 4; ++j)
    pier.segments.push_back(segment(2.0 * j, 0.75, 500.0, {2.0 * j + 1.0, 2.0 * j + 2.0},
                                    {9800.0, j == 3 ? 100000.0 : 500.0}));
  ChainTendon tendon;
  tendon.to = {3, 0.0, 2.0};
  tendon.prestress = 1.5e6;
  tendon.stiffness = 3.9e7;
  tendon.free_length = 8.0;
  pier.tendons.push_back(tendon);
  out.emplace_back("segmental pier", pier);

  ChainData shaft;
  shaft.rayleigh = {0.3, 0.002};
  shaft.segments.push_back(segment(0.0, 1.0, 3000.0, {2.0, 4.0, 6.0}, {2000.0, 1500.0, 1000.0}, false, {4e9, 3e9, 2e9}));
  shaft.segments.push_back(segment(6.0, 0.6, 400.0, {7.0, 8.0}, {600.0, 300.0}));
  shaft.segments.push_back(segment(8.0, 0.3, 0.0, {8.5, 9.0}, {100.0, 80.0}));
  ChainTendon tie;
  tie.from = {0, 0.5, 0.0, 2};
  tie.to = {2, -0.1, 1.0};
  tie.prestress = 2e4;
  tie.stiffness = 5e6;
  shaft.tendons.push_back(tie);
  out.emplace_back("flexible shaft under two rigid segments", shaft);

  ChainData pedestal;
  pedestal.rayleigh = {0.2, 0.003};
  pedestal.segments.push_back(segment(0.0, 1.2, 5000.0, {0.5, 1.0}, {3000.0, 800.0}));
  pedestal.segments.push_back(segment(1.0, 0.8, 1200.0, {3.0, 5.0, 7.0}, {1800.0, 1400.0, 900.0}, false, {5e9, 4e9, 3e9}));
  pedestal.segments.push_back(segment(7.0, 0.4, 0.0, {7.5, 8.0}, {150.0, 120.0}));
  out.emplace_back("flexible shaft on a rigid pedestal under a rigid top", pedestal);
  return out;
}

// Every combination of full contact, rocking left and rocking right.
std::vector<std::vector<Phase>> every_phase(int joints) {
  std::vector<std::vector<Phase>> out;
  int combinations = 1;
  for (int j = 0; j < joints; ++j) combinations *= 3;
  for (int k = 0; k < combinations; ++k) {
    std::vector<Phase> p;
    for (int j = 0, code = k; j < joints; ++j, code /= 3)
      p.push_back(code % 3 == 0 ? Phase::full_contact() : Phase::rocking(code % 3 == 1 ? Pivot::left : Pivot::right));
    out.push_back(p);
  }
  return out;
}

}  // namespace

TEST_CASE("the lumped segments, rigid and flexible, give the general path's right-hand sides, reactions, corner accelerations, powers, energies and positions to 1e-12") {
  std::mt19937 rng(55);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const auto& [name, data] : chains()) {
    CAPTURE(name);
    const Chain c = make_chain(data);
    ChainWorkspace lumped = make_workspace(c), general = make_workspace(c);
    general.per_point = true;
    const int n = c.size, J = c.joints;
    double weight_height = 0;
    for (int i = 0; i < c.points; ++i) weight_height += c.data.g * c.masses[i] * c.rest_height[i];
    const double height = *std::max_element(c.rest_height.begin(), c.rest_height.end());
    int compared = 0;
    for (const std::vector<Phase>& phases : every_phase(J)) {
      for (int trial = 0; trial < 4; ++trial) {
        Vec q(n), v(n);
        for (int k = 0; k < n; ++k) {
          q[k] = k < J ? 0.05 * U(rng) : 0.01 * U(rng);
          v[k] = k < J ? 0.5 * U(rng) : 0.2 * U(rng);
        }
        for (int j = 0; j < J; ++j) {  // a rocking joint's theta on its pivot's side; a closed one's at 0
          q[j] = phases[j].is_rocking() ? phases[j].sign() * std::abs(q[j]) : 0.0;
          if (!phases[j].is_rocking()) v[j] = 0.0;
        }
        const GroundAcceleration a{4.0 * U(rng), 2.0 * U(rng)};
        Vec acc_l(n), acc_g(n), acc_r(n);
        ChainPower power_l;
        chain_acceleration(c, phases, a, q, v, acc_l, lumped, &power_l);
        chain_acceleration(c, phases, a, q, v, acc_g, general);
        check_vector(acc_l, acc_g, tol);

        const ChainPower power_g = chain_power(c, phases, a, q, v, general);
        const ChainPower power_alone = chain_power(c, phases, a, q, v, lumped);
        CHECK(power_l.ground == close_to(power_g.ground, tol));
        CHECK(power_alone.ground == close_to(power_g.ground, tol));
        CHECK(power_l.damping == close_to(power_g.damping, tol, 0.0));

        const ChainEnergy e_l = chain_energy(c, phases, q, v, lumped), e_g = chain_energy(c, phases, q, v, general);
        CHECK(e_l.kinetic == close_to(e_g.kinetic, tol));
        // Gravity's energy is a difference of heights (y - y_rest, y up to the
        // top): each path's round-off is relative to g sum m y_rest, not to the
        // difference, so the check is absolute, tol of that scale.
        CHECK(e_l.gravity == within(e_g.gravity, tol * weight_height));
        CHECK(e_l.elastic == close_to(e_g.elastic, tol, 0.0));
        CHECK(e_l.tendons == close_to(e_g.tendons, tol, 0.0));

        // anchor_position walks the frames for positions alone: every slab's
        // and node's against the general path's points (its kinematics of
        // this state, just now), to tol of the chain's height.
        for (int j = 0, pt = 0; j < J; ++j) {
          const int nodes = static_cast<int>(c.local_heights[j].size());
          for (int i = -1; i < nodes; ++i, ++pt) {
            const Eigen::Vector2d at = anchor_position(c, phases, {.segment = j, .x = 0.0, .z = 0.0, .node = i}, q, lumped);
            CHECK(at.x() == within(general.points(pt, 0), tol * height));
            CHECK(at.y() == within(general.points(pt, 1), tol * height));
          }
        }

        std::vector<JointReaction> r_l(J), r_g(J);
        std::vector<CornerAcceleration> corners(J);
        chain_reactions(c, phases, a, q, v, r_l, acc_r, lumped, corners);
        check_vector(acc_r, acc_g, tol);
        chain_reactions(c, phases, a, q, v, r_g, acc_g, general);
        Vec reactions_l(3 * J), reactions_g(3 * J);
        for (int j = 0; j < J; ++j) {
          reactions_l.segment(3 * j, 3) << r_l[j].N, r_l[j].V, r_l[j].M;
          reactions_g.segment(3 * j, 3) << r_g[j].N, r_g[j].V, r_g[j].M;
        }
        check_vector(reactions_l, reactions_g, tol);

        Vec corner_l(2 * J), corner_g(2 * J);
        for (int j = 0; j < J; ++j) {
          for (Pivot s : pivots) {
            const int slot = 2 * j + (s == Pivot::left ? 0 : 1);
            corner_l[slot] = corners[j][s];
            corner_g[slot] = phases[j].is_rocking() ? 0.0 : corner_acceleration(c, phases, j, s, a, q, v, general);
          }
        }
        check_vector(corner_l, corner_g, tol);
        ++compared;
      }
    }
    CHECK(compared == 4 * static_cast<int>(every_phase(J).size()));
  }
}
