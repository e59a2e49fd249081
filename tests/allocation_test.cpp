// rk45 allocates nothing per step: every work vector is sized at construction
// and reset; nor does rocking.chain's right-hand side or its reactions, which
// work in a workspace sized once, nor rocking.columns' equations. Counted by interposing malloc in this executable (Eigen allocates
// with std::malloc, operator new calls malloc too); glibc's own allocator
// (__libc_malloc) does the work.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <atomic>
#include <cmath>
#include <cstdlib>
import rocking.integrator;
import rocking.chain;
import rocking.columns;

namespace {
std::atomic<long> allocations{0};
}

extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}

using namespace rocking::ode;
using CRef = Eigen::Ref<const Eigen::VectorXd>;
using Ref = Eigen::Ref<Eigen::VectorXd>;

TEST_CASE("rk45 makes no heap allocation while stepping, with guards, events and breakpoints") {
  auto rk = make_rk45(2, [](double, CRef y, Ref f) { f[0] = y[1]; f[1] = -y[0]; }, {.rtol = 1e-9, .atol = 1e-9});
  std::vector<double> bps;
  for (int k = 1; k < 200; ++k) bps.push_back(0.1 * k);
  rk->set_breakpoints(breakpoint_list(bps));
  Eigen::VectorXd y0(2);
  y0 << 0.0, 1.0;
  rk->reset(0.0, y0, {[](double, CRef y, Ref g) { g[0] = y[0]; }, {Direction::either}});
  const long before = allocations.load();
  long events = 0;
  while (rk->time() < 20.0)
    if (rk->step(20.0).reason == Stop::event) ++events;
  CHECK(allocations.load() - before == 0);
  CHECK(events == 6);  // sin t crosses zero at pi, 2pi, ..., 6pi
  CHECK(rk->stats().steps > 200);
}

TEST_CASE("the chain's right-hand side, power, joint reactions and corner accelerations make no heap allocation") {
  using namespace rocking;
  ChainData d;
  for (int j = 0; j < 3; ++j) {
    ChainSegment s;
    s.base_height = 2.0 * j;
    s.half_width = 0.5;
    s.base_mass = 100.0;
    s.heights = (Eigen::VectorXd(2) << 2.0 * j + 1.0, 2.0 * j + 2.0).finished();
    s.masses = (Eigen::VectorXd(2) << 200.0, 100.0).finished();
    d.segments.push_back(s);
  }
  ChainTendon t;
  t.to = {2, 0.0, 2.0};
  t.prestress = 1e4;
  t.stiffness = 1e6;
  d.tendons.push_back(t);
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  const Phase phases[] = {Phase::rocking(Pivot::right), Phase::full_contact(), Phase::rocking(Pivot::left)};
  const Eigen::VectorXd q = (Eigen::VectorXd(3) << 0.01, 0.0, -0.02).finished(), v = (Eigen::VectorXd(3) << 0.1, 0.0, -0.2).finished();
  Eigen::VectorXd acc(3);
  JointReaction r[3];
  CornerAcceleration corners[3];
  ChainPower power;
  const long before = allocations.load();
  for (int k = 0; k < 100; ++k) {
    chain_acceleration(chain, phases, {0.5, 0.1}, q, v, acc, w, &power);
    chain_reactions(chain, phases, {0.5, 0.1}, q, v, r, acc, w, corners);
    power = chain_power(chain, phases, {0.5, 0.1}, q, v, w);
  }
  CHECK(allocations.load() - before == 0);
  CHECK(r[1].N > 0);
  CHECK(corners[1].left != 0.0);
  CHECK(power.ground != 0.0);
}

TEST_CASE("the rocking frame's right-hand sides, guard, impact, energy and top forces make no heap allocation") {
  using namespace rocking;
  Structure deck;
  deck.base_mass = 8000;
  deck.heights = (Eigen::VectorXd(3) << 3.0, 6.0, 9.0).finished();
  deck.masses = (Eigen::VectorXd(3) << 1e4, 8e3, 6e3).finished();
  deck.EI = (Eigen::VectorXd(3) << 6e8, 5e8, 4e8).finished();
  deck.damping_ratio = 0.05;
  const Columns c = make_columns({3, 0.3, 2.5, 3000.0, 6.0}, deck);
  const Eigen::VectorXd u = (Eigen::VectorXd(3) << 0.01, -0.02, 0.03).finished();
  Eigen::VectorXd v = (Eigen::VectorXd(3) << 0.1, 0.2, -0.3).finished();
  Eigen::VectorXd rates(6);
  double normal[3];
  const long before = allocations.load();
  double sum = 0;
  for (int k = 0; k < 100; ++k) {
    const Coordinates q{u, v, Tilt(0.01 * (k % 7)), 0.2};
    const double thdd = rocking_acceleration(c, Pivot::right, {0.5, 0.1}, 1e3, q, rates);
    const Phase rocking = Phase::rocking(Pivot::right);
    sum += top_contact_forces(c, rocking, {0.5, 0.1}, q, thdd, rates.tail(3), normal).smallest;
    full_contact_acceleration(c, 0.5, u, v, rates);
    sum += uplift_guard(c, Pivot::left, {0.5, 0.1}, 0.0, u, v);
    sum += mechanical_energy(c, rocking, q).total() + ground_input_power(c, rocking, {0.5, 0.1}, q) + viscous_power(c, v);
    sum += impact(c, Pivot::right, -0.1, v).theta_dot;
  }
  CHECK(allocations.load() - before == 0);
  CHECK(std::isfinite(sum));
}
