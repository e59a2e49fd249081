// rk45 allocates nothing per step: every work vector is sized at construction
// and reset. Counted by interposing malloc in this executable (Eigen allocates
// with std::malloc, operator new calls malloc too); glibc's own allocator
// (__libc_malloc) does the work.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <atomic>
#include <cstdlib>
import rocking.integrator;

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
