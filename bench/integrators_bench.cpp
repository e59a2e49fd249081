// Cost of the three integrator backends on one problem: the chimney on a fixed
// base (MODEL.md 3: M u'' + C u' + K u = -M 1 a_g, 8 states) under 10 s of a
// 2 Hz sine ground motion of 0.3 g, sampled every 0.01 s like a record (the
// samples are breakpoints). Reports wall time per solve, ns per rhs evaluation
// and per accepted step, and the counts. Run with `make bench`.
#include <rocking/eigen.hpp>
#include <benchmark/benchmark.h>
#include <cmath>
#include <numbers>
#include <vector>
import rocking;

namespace {

using namespace rocking;
using CRef = Eigen::Ref<const Eigen::VectorXd>;
using Ref = Eigen::Ref<Eigen::VectorXd>;

struct FixedBase {
  StructuralMatrices sm = assemble(load_default_scene().structure);
  Eigen::MatrixXd Minv_K = sm.M.inverse() * sm.K, Minv_C = sm.M.inverse() * sm.C;
  Eigen::Index n = sm.M.rows();
  static double ground(double t) { return 0.3 * 9.81 * std::sin(2 * std::numbers::pi * 2.0 * t); }
  // Piecewise-linear between 0.01 s samples, as a record is.
  static double sampled_ground(double t) {
    const double dt = 0.01, k = std::floor(t / dt), s = t / dt - k;
    return (1 - s) * ground(k * dt) + s * ground((k + 1) * dt);
  }
  void rhs(double t, CRef y, Ref f) const {
    f.head(n) = y.tail(n);
    f.tail(n).noalias() = -Minv_K * y.head(n) - Minv_C * y.tail(n);
    f.tail(n).array() -= sampled_ground(t);
  }
};

void solve(benchmark::State& state, ode::Backend backend) {
  const FixedBase model;
  std::vector<double> samples;
  for (int k = 1; k < 1000; ++k) samples.push_back(0.01 * k);
  const ode::Options options{.rtol = 1e-6, .atol = 1e-9};
  ode::Stats stats;
  for (auto _ : state) {
    auto in = ode::make_integrator(backend, 2 * model.n,
                                   [&](double t, CRef y, Ref f) { model.rhs(t, y, f); }, options);
    in->set_breakpoints(ode::breakpoint_list(samples));
    in->reset(0.0, Eigen::VectorXd::Zero(2 * model.n), {});
    ode::advance(*in, 10.0);
    stats = in->stats();
    benchmark::DoNotOptimize(in->state().data());
  }
  using C = benchmark::Counter;
  const double runs = static_cast<double>(state.iterations());
  state.counters["rhs"] = static_cast<double>(stats.rhs);
  state.counters["steps"] = static_cast<double>(stats.steps);
  state.counters["s_per_rhs"] = C(runs * static_cast<double>(stats.rhs), C::kIsRate | C::kInvert);
  state.counters["s_per_step"] = C(runs * static_cast<double>(stats.steps), C::kIsRate | C::kInvert);
}

}  // namespace

BENCHMARK_CAPTURE(solve, rk45, rocking::ode::Backend::rk45)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(solve, cvode, rocking::ode::Backend::cvode)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(solve, arkode, rocking::ode::Backend::arkode)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
