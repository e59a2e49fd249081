// rocking.chain's closed form for a rigid top on a closed chain
// (docs/chain.md "A rigid top on a closed chain") against the assembly it
// replaces (ChainWorkspace::rigid_top false): every joint but the top one
// closed, the top rigid and rocking about either corner, or closed. Both
// are the same equations, so on random states, with and without ground
// accelerations (horizontal and vertical) and applied generalised forces
// (a device's moment on a closed joint's theta enters that joint's M alone;
// on the top's theta and the elastic coordinates, the motion), they agree
// to round-off: q'' from chain_acceleration and chain_reactions, the ground's
// and the damping's powers, every joint's N, V and M, and every closed
// joint's corner accelerations and their gains, each to 1e-12 relative (of
// its vector's largest entry for a component that may cancel to nothing).
// On the cracked chimney's chain (data/scenes/chimney_cracked.toml), the
// stacked blocks (data/scenes/stacked_blocks.toml) and a flexible shaft on a
// rigid pedestal under a rigid top. Where the closed form does not hold (a
// tendon, a flexible top, a joint below the top rocking, a flexible segment under a
// rigid one under the top, per_point) it is not taken.
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
import rocking.scene;

using namespace rocking;
using Vec = Eigen::VectorXd;

namespace {

constexpr double tol = 1e-12;

ChainSegment segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses,
                     bool rigid = true, std::vector<double> EI = {}) {
  return chain_segment<ChainSegment>(h, B, m0, std::move(heights), std::move(masses), rigid, std::move(EI));
}

ChainData pedestal_chain() {
  ChainData pedestal;
  pedestal.rayleigh = {0.2, 0.003};
  pedestal.segments.push_back(segment(0.0, 1.2, 5000.0, {0.5, 1.0}, {3000.0, 800.0}));
  pedestal.segments.push_back(segment(1.0, 0.8, 1200.0, {3.0, 5.0, 7.0}, {1800.0, 1400.0, 900.0}, false, {5e9, 4e9, 3e9}));
  pedestal.segments.push_back(segment(7.0, 0.4, 0.0, {7.5, 8.0}, {150.0, 120.0}));
  return pedestal;
}

std::vector<std::pair<std::string, ChainData>> chains() {
  std::vector<std::pair<std::string, ChainData>> out;
  const std::string scenes = ROCKING_SCENES;
  out.emplace_back("cracked chimney", jointed_model(load_scene(scenes + "/chimney_cracked.toml")).chain.data);
  out.emplace_back("stacked blocks", jointed_model(load_scene(scenes + "/stacked_blocks.toml")).chain.data);
  out.emplace_back("flexible shaft on a rigid pedestal under a rigid top", pedestal_chain());
  return out;
}

}  // namespace

TEST_CASE("a rigid top on a closed chain, rocking or closed: the closed form gives the assembly's q'', powers, reactions and corner accelerations to 1e-12") {
  std::mt19937 rng(54);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (const auto& [name, data] : chains()) {
    CAPTURE(name);
    const Chain c = make_chain(data);
    ChainWorkspace fast = make_workspace(c), general = make_workspace(c);
    general.rigid_top = false;
    const int n = c.size, J = c.joints, top = J - 1;
    const double weight = c.segment_mass[top] * c.data.g;  // the top's weight, the scale of the applied forces
    int compared = 0;
    for (const Phase top_phase : {Phase::rocking(Pivot::left), Phase::rocking(Pivot::right), Phase::full_contact()}) {
      std::vector<Phase> phases(J, Phase::full_contact());
      phases[top] = top_phase;
      CAPTURE(top_phase.sign());
      REQUIRE(chain_rigid_top(c, phases, fast));
      CHECK_FALSE(chain_rigid_top(c, phases, general));
      for (int trial = 0; trial < 16; ++trial) {
        CAPTURE(trial);
        Vec q = Vec::Zero(n), v = Vec::Zero(n);
        if (top_phase.is_rocking()) {  // a closed joint's theta and theta' are 0
          // Up to 0.15 rad: the closed form's cos and sin take their series
          // below 1/16 rad and the library's above, both held here.
          q[top] = top_phase.sign() * 0.15 * std::abs(U(rng));
          v[top] = 0.5 * U(rng);
        }
        for (int k = J; k < n; ++k) {
          q[k] = 0.01 * U(rng);
          v[k] = 0.2 * U(rng);
        }
        // Ground: none, horizontal, vertical, both; applied forces on every
        // other trial (on every coordinate, closed joints' theta too).
        const int g = trial % 4;
        const GroundAcceleration a{(g & 1) ? 4.0 * U(rng) : 0.0, (g & 2) ? 2.0 * U(rng) : 0.0};
        const bool applied = (trial / 4) % 2 == 1;
        for (int k = 0; k < n; ++k) fast.applied[k] = general.applied[k] = applied ? 0.3 * weight * U(rng) : 0.0;
        CAPTURE(a.h);
        CAPTURE(a.v);
        CAPTURE(applied);

        Vec acc_f(n), acc_g(n);
        ChainPower power_f, power_g;
        chain_acceleration(c, phases, a, q, v, acc_f, fast, &power_f);
        chain_acceleration(c, phases, a, q, v, acc_g, general, &power_g);
        check_vector(acc_f, acc_g, tol);
        Vec powers_f(2), powers_g(2);
        powers_f << power_f.ground, power_f.damping;
        powers_g << power_g.ground, power_g.damping;
        check_vector(powers_f, powers_g, tol);

        std::vector<JointReaction> r_f(J), r_g(J);
        std::vector<CornerAcceleration> k_f(J), k_g(J);
        chain_reactions(c, phases, a, q, v, r_f, acc_f, fast, k_f);
        chain_reactions(c, phases, a, q, v, r_g, acc_g, general, k_g);
        check_vector(acc_f, acc_g, tol);
        // Each joint's reaction on its own scale (the top's forces are far
        // smaller than the base's): N, V and M / B_j, the force at the
        // joint's corner that gives its moment (0 while it rocks).
        Vec corners_f(2 * J), corners_g(2 * J), gains_f(2 * J), gains_g(2 * J);
        for (int j = 0; j < J; ++j) {
          CAPTURE(j);
          const double B = c.data.segments[static_cast<std::size_t>(j)].half_width;
          Vec forces_f(3), forces_g(3);
          forces_f << r_f[j].N, r_f[j].V, r_f[j].M / B;
          forces_g << r_g[j].N, r_g[j].V, r_g[j].M / B;
          check_vector(forces_f, forces_g, tol);
          corners_f.segment(2 * j, 2) << k_f[j].left, k_f[j].right;
          corners_g.segment(2 * j, 2) << k_g[j].left, k_g[j].right;
          gains_f.segment(2 * j, 2) << k_f[j].left_gain, k_f[j].right_gain;
          gains_g.segment(2 * j, 2) << k_g[j].left_gain, k_g[j].right_gain;
        }
        check_vector(corners_f, corners_g, tol);
        check_vector(gains_f, gains_g, tol);
        // chain_reactions without the corners gives the same reactions.
        std::vector<JointReaction> r_alone(J);
        chain_reactions(c, phases, a, q, v, r_alone, acc_f, fast);
        for (int j = 0; j < J; ++j) {
          CHECK(r_alone[j].N == r_f[j].N);
          CHECK(r_alone[j].V == r_f[j].V);
          CHECK(r_alone[j].M == r_f[j].M);
        }
        ++compared;
      }
    }
    CHECK(compared == 48);
  }
}

TEST_CASE("the closed form for a rigid top on a closed chain is not taken where it does not hold") {
  const ChainData pedestal = pedestal_chain();
  const Chain c = make_chain(pedestal);
  ChainWorkspace w = make_workspace(c);
  const std::vector<Phase> top_rocks{Phase::full_contact(), Phase::full_contact(), Phase::rocking(Pivot::left)};
  CHECK(chain_rigid_top(c, top_rocks, w));
  CHECK(chain_rigid_top(c, std::vector<Phase>(3, Phase::full_contact()), w));
  // a joint below the top rocking
  CHECK_FALSE(chain_rigid_top(c, std::vector<Phase>{Phase::rocking(Pivot::right), Phase::full_contact(), Phase::rocking(Pivot::left)}, w));
  CHECK_FALSE(chain_rigid_top(c, std::vector<Phase>{Phase::full_contact(), Phase::rocking(Pivot::right), Phase::full_contact()}, w));
  // per_point
  w.per_point = true;
  CHECK_FALSE(chain_rigid_top(c, top_rocks, w));
  // a tendon
  ChainData tied = pedestal;
  ChainTendon tendon;
  tendon.to = {2, 0.0, 1.0};
  tendon.prestress = 1e4;
  tendon.stiffness = 1e6;
  tied.tendons.push_back(tendon);
  const Chain ct = make_chain(tied);
  CHECK_FALSE(chain_rigid_top(ct, top_rocks, make_workspace(ct)));
  // a flexible top (on a rigid segment)
  ChainData flexible_top;
  flexible_top.segments.push_back(segment(0.0, 1.0, 1000.0, {1.0}, {2000.0}));
  flexible_top.segments.push_back(segment(1.0, 0.5, 500.0, {3.0, 5.0}, {800.0, 600.0}, false, {2e9, 1e9}));
  const Chain cf = make_chain(flexible_top);
  CHECK_FALSE(chain_rigid_top(cf, std::vector<Phase>{Phase::full_contact(), Phase::rocking(Pivot::left)}, make_workspace(cf)));
  // a flexible segment below a rigid one below the top (the middle one turns with phi)
  ChainData turning;
  turning.segments.push_back(segment(0.0, 1.0, 3000.0, {2.0, 4.0}, {2000.0, 1500.0}, false, {4e9, 3e9}));
  turning.segments.push_back(segment(4.0, 0.6, 400.0, {5.0}, {600.0}));
  turning.segments.push_back(segment(5.0, 0.3, 0.0, {5.5}, {100.0}));
  const Chain cm = make_chain(turning);
  CHECK_FALSE(chain_rigid_top(cm, std::vector<Phase>{Phase::full_contact(), Phase::full_contact(), Phase::rocking(Pivot::right)},
                                make_workspace(cm)));
}
