// The response spectrum of a 10-minute record (60,000 samples at 100 Hz) at
// 100 periods from 0.01 to 10 s, and everything `rocking record` measures.
// The record is synthetic (a fixed-seed random walk through a few damped
// oscillations) so that the benchmark needs no file.
#include <benchmark/benchmark.h>
#include <cmath>
#include <random>
#include <vector>
import rocking;

namespace {

rocking::GroundMotion ten_minutes() {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double dt = 0.01;
  std::vector<double> t, a;
  double x = 0, v = 0;
  for (int i = 0; i < 60000; ++i) {
    // A 2 Hz, 30 % damped filter of white noise: ground-motion-like content.
    const double w = 2 * 3.14159265 * 2.0, f = noise(rng);
    v += dt * (-2 * 0.3 * w * v - w * w * x + 50 * f);
    x += dt * v;
    t.push_back(i * dt);
    a.push_back(w * w * x);
  }
  return rocking::GroundMotion::from_samples("synthetic 10 min", t, a);
}

void spectrum_100_periods(benchmark::State& state) {
  const rocking::GroundMotion g = ten_minutes();
  const std::vector<double> periods = rocking::log_periods(0.01, 10.0, 100);
  for (auto _ : state) benchmark::DoNotOptimize(rocking::response_spectrum(g, periods));
  state.counters["samples"] = static_cast<double>(g.sample_count());
  state.counters["periods"] = static_cast<double>(periods.size());
}
BENCHMARK(spectrum_100_periods)->Unit(benchmark::kMillisecond);

void all_measures_21_periods(benchmark::State& state) {
  const rocking::GroundMotion g = ten_minutes();
  for (auto _ : state) benchmark::DoNotOptimize(rocking::measure_record(g, rocking::standard_periods()));
}
BENCHMARK(all_measures_21_periods)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
