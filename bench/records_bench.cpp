// The response spectrum of a 10-minute record (60,000 samples at 100 Hz) at
// 100 periods from 0.01 to 10 s, everything `rocking record` measures, and
// its processing (baseline, taper, zero-phase band-pass, velocity fit);
// and the cost of vertical shaking (MODEL.md 14): the chimney under 40 s of a
// record alone, with a vertical record of zero amplitude (the same response:
// the overhead itself) and with a vertical record of half its PGA.
// The records are synthetic (a fixed-seed random walk through a few damped
// oscillations) so that the benchmark needs no file.
#include <benchmark/benchmark.h>
#include <cmath>
#include <random>
#include <vector>
import rocking;

namespace {

rocking::GroundMotion synthetic(int samples, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double dt = 0.01;
  std::vector<double> t, a;
  double x = 0, v = 0;
  for (int i = 0; i < samples; ++i) {
    // A 2 Hz, 30 % damped filter of white noise: ground-motion-like content.
    const double w = 2 * 3.14159265 * 2.0, f = noise(rng);
    v += dt * (-2 * 0.3 * w * v - w * w * x + 50 * f);
    x += dt * v;
    t.push_back(i * dt);
    a.push_back(w * w * x);
  }
  return rocking::GroundMotion::from_samples("synthetic", t, a);
}

rocking::GroundMotion ten_minutes() { return synthetic(60000); }

void spectrum_100_periods(benchmark::State& state) {
  const rocking::GroundMotion g = ten_minutes();
  const std::vector<double> periods = rocking::log_periods(0.01, 10.0, 100);
  for (auto _ : state) benchmark::DoNotOptimize(rocking::response_spectrum(g, periods));
  state.counters["samples"] = static_cast<double>(g.sample_count());
  state.counters["periods"] = static_cast<double>(periods.size());
}
BENCHMARK(spectrum_100_periods)->Unit(benchmark::kMillisecond);

// Processing the same record as `--process detrend=1,taper=0.05,highpass=0.1,
// lowpass=25,order=4,vfit=2` does: to cost less than its spectrum.
void process_10_minutes(benchmark::State& state) {
  const rocking::GroundMotion g = ten_minutes();
  const rocking::Processing p = rocking::parse_processing("detrend=1,taper=0.05,highpass=0.1,lowpass=25,order=4,vfit=2");
  for (auto _ : state) benchmark::DoNotOptimize(rocking::process(g, p));
}
BENCHMARK(process_10_minutes)->Unit(benchmark::kMillisecond);

void all_measures_21_periods(benchmark::State& state) {
  const rocking::GroundMotion g = ten_minutes();
  for (auto _ : state) benchmark::DoNotOptimize(rocking::measure_record(g, rocking::standard_periods()));
}
BENCHMARK(all_measures_21_periods)->Unit(benchmark::kMillisecond);

// 0: no vertical motion; 1: a vertical motion of zero amplitude; 2: one of half the horizontal PGA.
void chimney_vertical(benchmark::State& state) {
  const rocking::GroundMotion h = synthetic(4000);
  rocking::GroundMotion g = h.scaled(0.8 * rocking::gravity / h.peak());
  const rocking::GroundMotion v = synthetic(4000, 11);
  if (state.range(0) == 1) g = g.with_vertical(v.scaled(0.0));
  if (state.range(0) == 2) g = g.with_vertical(v.scaled(0.4 * rocking::gravity / v.peak()));
  const rocking::ContactModel m = rocking::make_contact_model(rocking::load_default_scene(), false);
  const rocking::RunOptions o;
  long rhs = 0;
  for (auto _ : state) {
    const rocking::RunResult r = rocking::simulate(m, g, o);
    rhs = r.stats.rhs;
    benchmark::DoNotOptimize(r.peaks);
  }
  state.counters["rhs"] = static_cast<double>(rhs);
}
BENCHMARK(chimney_vertical)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
