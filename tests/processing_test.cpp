// Record processing (rocking.ground_motion's Processing): the Butterworth
// sections against the analog prototype's magnitude through the bilinear
// transform, the zero-phase filter applied to sinusoids (|H|^2, no phase),
// a polynomial drift removed by the detrend and a velocity drift by the
// velocity fit (1e-9), the taper, cut and resampling, the processed record
// naming what was done, and K-NET AOM001's displacement brought back to a
// plausible size, sample by sample equal to the same processing done by
// another route (a closed-form least-squares line, and the zero-phase filter
// as two direct convolutions with the impulse response of the analog
// prototype through the bilinear transform, by inverse FFT).
#include <doctest/doctest.h>
#include "close.hpp"
#include <gsl/gsl_fft_complex.h>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>
#include "records.hpp"
import rocking.ground_motion;
import rocking.intensity;
import rocking.errors;
import rocking.records;

using namespace rocking;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double README_RAW_PGD = 0.01409, README_PROCESSED_PGD = 0.000886;  // [m], as the README states them

// |H|^2 of the Butterworth prototype through the bilinear transform.
double butterworth_squared(int n, double fc, double f, double dt, bool highpass) {
  const double W = std::tan(pi * f * dt), Wc = std::tan(pi * fc * dt);
  const double ratio = highpass ? Wc / W : W / Wc;
  return 1.0 / (1.0 + std::pow(ratio, 2 * n));
}

// The impulse response of the Butterworth band (order n, corners hp and lp
// [Hz], either 0 for none) on samples dt apart: H(e^jw) is the analog
// prototype 1 / prod (s - p_k), p_k = exp(j pi (2k + n - 1) / 2n), at
// s = j tan(w/2) / tan(pi fc dt) (low-pass) or its reciprocal (high-pass),
// and h its inverse DFT on M points (M dt long beyond the response's decay).
std::vector<double> butterworth_impulse_response(int n, double hp, double lp, double dt, std::size_t M) {
  using C = std::complex<double>;
  std::vector<C> poles;
  for (int k = 1; k <= n; ++k) poles.push_back(std::polar(1.0, pi * (2.0 * k + n - 1) / (2.0 * n)));
  const auto prototype = [&](C s) {
    C d = 1.0;
    for (const C& p : poles) d *= s - p;
    return 1.0 / d;
  };
  std::vector<double> packed(2 * M);
  for (std::size_t k = 0; k < M; ++k) {
    C H = 1.0;
    const double w = 2 * pi * static_cast<double>(k) / static_cast<double>(M);
    if (k == 0 && hp > 0) H = 0.0;
    else if (k == M / 2 && lp > 0) H = 0.0;
    else {
      const double t = std::tan(0.5 * w);
      if (hp > 0) H *= prototype(1.0 / C(0.0, t / std::tan(pi * hp * dt)));
      if (lp > 0) H *= prototype(C(0.0, t / std::tan(pi * lp * dt)));
    }
    packed[2 * k] = H.real();
    packed[2 * k + 1] = H.imag();
  }
  gsl_fft_complex_radix2_inverse(packed.data(), 1, M);  // normalised by 1/M
  std::vector<double> h(M);
  for (std::size_t i = 0; i < M; ++i) h[i] = packed[2 * i];
  return h;
}

// Amplitude and phase of x at frequency f by least squares on the samples
// [from, to): x ~ c cos(w t) + s sin(w t).
std::pair<double, double> fit_sinusoid(const std::vector<double>& x, double f, double dt, std::size_t from, std::size_t to) {
  double cc = 0, cs = 0, ss = 0, xc = 0, xs = 0;
  for (std::size_t i = from; i < to; ++i) {
    const double t = dt * static_cast<double>(i), c = std::cos(2 * pi * f * t), s = std::sin(2 * pi * f * t);
    cc += c * c;
    cs += c * s;
    ss += s * s;
    xc += x[i] * c;
    xs += x[i] * s;
  }
  const double det = cc * ss - cs * cs;
  const double a = (xc * ss - xs * cs) / det, b = (xs * cc - xc * cs) / det;
  return {std::hypot(a, b), std::atan2(b, a)};
}

std::vector<double> samples(std::size_t n, double dt, auto f) {
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = f(dt * static_cast<double>(i));
  return out;
}

}  // namespace

TEST_CASE("Butterworth sections: |H| at chosen frequencies equals the prototype's through the bilinear transform (1e-6)") {
  for (const double dt : {0.01, 0.005}) {
    for (int n : {1, 2, 3, 4, 6, 8}) {
      for (const bool high : {false, true}) {
        const double fc = high ? 0.05 : 20.0;
        const std::vector<SecondOrderSection> s = butterworth(n, fc, dt, high);
        CHECK(s.size() == static_cast<std::size_t>((n + 1) / 2));
        for (double f : {0.01, 0.03, 0.05, 0.1, 0.5, 2.0, 10.0, 20.0, 30.0, 45.0}) {
          if (!(f < 0.5 / dt)) continue;
          CAPTURE(dt);
          CAPTURE(n);
          CAPTURE(high);
          CAPTURE(f);
          const double expected = std::sqrt(butterworth_squared(n, fc, f, dt, high));
          CHECK(magnitude(s, f, dt) == close_to(expected, 1e-6));
        }
        CHECK(magnitude(s, fc, dt) == close_to(std::sqrt(0.5), 1e-9));  // -3 dB at the corner
      }
    }
  }
  CHECK_THROWS_WITH_AS(butterworth(4, 60, 0.01, false), doctest::Contains("below the Nyquist frequency 50 Hz"), InputError);
  CHECK_THROWS_AS(butterworth(0, 1, 0.01, false), InputError);
}

TEST_CASE("the zero-phase band-pass scales a sinusoid by |H|^2 and leaves its phase (1e-6)") {
  const double dt = 0.01;
  std::vector<SecondOrderSection> band = butterworth(4, 0.1, dt, true);
  for (const SecondOrderSection& s : butterworth(4, 20, dt, false)) band.push_back(s);
  const std::size_t n = 40000;  // 400 s: the filters' transients die out well inside
  for (double f : {0.08, 0.15, 1.0, 18.0, 25.0}) {
    CAPTURE(f);
    const std::vector<double> x = samples(n, dt, [&](double t) { return std::sin(2 * pi * f * t + 0.3); });
    const std::vector<double> y = zero_phase(band, x);
    const auto [amplitude, phase] = fit_sinusoid(y, f, dt, n / 4, 3 * n / 4);
    const double expected = butterworth_squared(4, 0.1, f, dt, true) * butterworth_squared(4, 20, f, dt, false);
    CHECK(amplitude == close_to(expected, 1e-6));
    const auto [one, phase0] = fit_sinusoid(x, f, dt, n / 4, 3 * n / 4);
    CHECK(one == close_to(1.0, 1e-9));
    CHECK(phase == within(phase0, 1e-6));
  }
}

TEST_CASE("a polynomial drift added to a record is removed by the detrend, a velocity drift by the velocity fit (1e-9)") {
  const double dt = 0.01;
  const std::size_t n = 6000;
  const std::vector<double> signal =
      samples(n, dt, [](double t) { return std::sin(2 * pi * 1.3 * t) * std::exp(-0.05 * t) + 0.4 * std::sin(2 * pi * 4.1 * t); });
  double scale = 0;
  for (double v : signal) scale = std::max(scale, std::abs(v));
  for (int order : {0, 1, 2, 3}) {
    CAPTURE(order);
    const std::vector<double> clean = detrend(signal, dt, order);
    std::vector<double> drifted = clean;
    for (std::size_t i = 0; i < n; ++i) {
      const double t = dt * static_cast<double>(i);
      drifted[i] += 0.2 - 0.03 * t + (order >= 2 ? 1e-3 * t * t : 0.0) + (order >= 3 ? -2e-5 * t * t * t : 0.0);
      if (order == 0) drifted[i] = clean[i] + 0.2;
    }
    const std::vector<double> back = detrend(drifted, dt, order);
    double worst = 0;
    for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(back[i] - clean[i]));
    CHECK(worst < 1e-9 * scale);
  }
  // A drift in velocity v = 0.05 t - 0.002 t^2: an acceleration 0.05 - 0.004 t.
  const std::vector<double> clean = velocity_fit(signal, dt, 2);
  std::vector<double> drifted = clean;
  for (std::size_t i = 0; i < n; ++i) drifted[i] += 0.05 - 0.004 * dt * static_cast<double>(i);
  const std::vector<double> back = velocity_fit(drifted, dt, 2);
  double worst = 0;
  for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(back[i] - clean[i]));
  CHECK(worst < 1e-9 * scale);
}

TEST_CASE("taper, cut and resampling, a processed record naming its processing, bad specifications in one line") {
  const std::vector<double> ones(101, 1.0);
  const std::vector<double> t = cosine_taper(ones, 0.1);
  CHECK(t.front() == 0.0);
  CHECK(t.back() == 0.0);
  CHECK(t[5] == close_to(0.5, 1e-12));
  CHECK(t[50] == 1.0);
  const GroundMotion g = GroundMotion::evenly_sampled("ramp", 0.01, samples(1001, 0.01, [](double s) { return s; }));
  const GroundMotion cut = process(g, parse_processing("cut=2:5"));
  CHECK(cut.duration() == close_to(3.0, 1e-12));
  CHECK(cut.acceleration(0.0) == close_to(2.0, 1e-12));
  CHECK(cut.acceleration(1.5) == close_to(3.5, 1e-12));
  const GroundMotion coarse = process(g, parse_processing("dt=0.05"));
  CHECK(coarse.sample_interval() == 0.05);
  CHECK(coarse.sample_count() == 201);
  CHECK(coarse.acceleration(3.05) == close_to(3.05, 1e-12));  // a ramp resamples exactly
  const Processing p = parse_processing("detrend=1,taper=0.05,highpass=0.1,lowpass=25,order=4,vfit=2");
  CHECK(p.describe() == "detrend 1, taper 5 %, Butterworth 0.1-25 Hz order 4 zero-phase, velocity fit 2");
  const GroundMotion done = process(g, p);
  CHECK(done.info().processing == p.describe());
  CHECK(done.description().find("processed: detrend 1") != std::string::npos);
  for (const char* bad : {"highpass=-1", "order=9", "taper=0.7", "cut=5:2", "speed=3", "highpass", "lowpass=1,highpass=2",
                          "detrend=1.5", "dt=0"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(parse_processing(bad), InputError);
  }
  CHECK_THROWS_WITH_AS(parse_processing("order=9"), "order=9: must be a whole number from 1 to 8", InputError);
  CHECK_THROWS_WITH_AS(process(g, parse_processing("lowpass=60")), doctest::Contains("at or above the Nyquist frequency 50 Hz"),
                       InputError);
  CHECK_THROWS_WITH_AS(process(g, parse_processing("cut=2:50")), doctest::Contains("the record ends at 10 s"), InputError);
  const GroundMotion long_one = GroundMotion::evenly_sampled("long", 0.1, std::vector<double>(1001, 0.5));  // 100 s
  CHECK_THROWS_WITH_AS(process(long_one, parse_processing("dt=1e-6")), doctest::Contains("(at most 1e+07)"), InputError);
}

TEST_CASE("K-NET AOM001 EW, processed: its displacement drift removed (PGD as the README states it)") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string file = *dir + "/formats/AOM0011801241951.EW";
  const RecordMeasures raw = measure_record(read_record(file), {});
  RecordOptions o;
  o.process = parse_processing("detrend=1,taper=0.05,highpass=0.1,lowpass=20,order=4");
  const GroundMotion g = read_record(file, o);
  const RecordMeasures done = measure_record(g, {});
  CHECK(g.info().processing == "detrend 1, taper 5 %, Butterworth 0.1-20 Hz order 4 zero-phase");
  // The README's figures, to half a unit of their last digit: a regression
  // guard for what the README states. The filter itself is anchored above
  // (the bilinear prototype's |H|, |H|^2 on sinusoids, drifts removed to 1e-9).
  CHECK(raw.pgd == within(README_RAW_PGD, 5e-6));
  CHECK(done.pgd == within(README_PROCESSED_PGD, 5e-7));
  CHECK(done.pgd < 0.2 * raw.pgd);
  CHECK(done.pga == close_to(raw.pga, 0.02));  // the shaking itself is kept (README: within 2 %)
}

TEST_CASE("K-NET AOM001 EW, processed, equals the same processing by another route, sample by sample") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string file = *dir + "/formats/AOM0011801241951.EW";
  const GroundMotion raw = read_record(file);
  RecordOptions o;
  o.process = parse_processing("detrend=1,taper=0.05,highpass=0.1,lowpass=20,order=4");
  const std::vector<double> done = read_record(file, o).sample_values();
  std::vector<double> x = raw.sample_values();
  const double dt = raw.sample_interval();
  const std::size_t N = x.size();
  REQUIRE(done.size() == N);
  // The least-squares line, in closed form.
  double si = 0, sx = 0, sii = 0, six = 0;
  for (std::size_t i = 0; i < N; ++i) {
    const double t = static_cast<double>(i);
    si += t, sx += x[i], sii += t * t, six += t * x[i];
  }
  const double Nd = static_cast<double>(N), slope = (Nd * six - si * sx) / (Nd * sii - si * si),
               intercept = (sx - slope * si) / Nd;
  for (std::size_t i = 0; i < N; ++i) x[i] -= intercept + slope * static_cast<double>(i);
  // The cosine taper over 5 % of the samples at each end.
  const std::size_t m = static_cast<std::size_t>(std::floor(0.05 * Nd));
  for (std::size_t i = 0; i < m; ++i) {
    const double w = 0.5 * (1 - std::cos(pi * static_cast<double>(i) / static_cast<double>(m)));
    x[i] *= w;
    x[N - 1 - i] *= w;
  }
  // The filter: its impulse response on 2^17 points (1311 s at 100 Hz; the
  // 0.1 Hz corner's slowest pole decays by e in about 4 s), causal to round-off
  // (the wrapped-around half is the aliasing left), kept where it is above
  // 1e-16 of its peak.
  const std::size_t M = std::size_t{1} << 17;
  const std::vector<double> h_full = butterworth_impulse_response(4, 0.1, 20, dt, M);
  const double h_peak = std::ranges::max(h_full, {}, [](double v) { return std::abs(v); });
  double wrapped = 0;
  for (std::size_t i = M / 2; i < M; ++i) wrapped = std::max(wrapped, std::abs(h_full[i]));
  CHECK(wrapped <= 1e-14 * std::abs(h_peak));
  std::size_t L = M / 2;
  while (L > 1 && std::abs(h_full[L - 1]) < 1e-16 * std::abs(h_peak)) --L;
  // Forward from rest at the first sample, then backward from rest at the
  // last: two direct convolutions, each cut at the record's ends.
  std::vector<double> y1(N, 0.0), y(N, 0.0);
  for (std::size_t n = 0; n < N; ++n)
    for (std::size_t k = 0; k < L && k <= n; ++k) y1[n] += h_full[k] * x[n - k];
  for (std::size_t n = 0; n < N; ++n)
    for (std::size_t k = 0; k < L && n + k < N; ++k) y[n] += h_full[k] * y1[n + k];
  const double peak = std::ranges::max(y, {}, [](double v) { return std::abs(v); });
  double worst = 0;
  for (std::size_t n = 0; n < N; ++n) worst = std::max(worst, std::abs(done[n] - y[n]));
  MESSAGE("impulse response kept to " << L << " samples, its wrapped-around half at most " << wrapped / std::abs(h_peak)
                                      << " of its peak; largest difference " << worst << " m/s2 of a peak "
                                      << std::abs(peak) << " m/s2");
  // Two double-precision routes through ~1e4-term sums: round-off, some 1e-13 of the peak.
  CHECK(worst <= 1e-11 * std::abs(peak));
  // The README's processed PGD (a regression guard above) on this anchor.
  const RecordMeasures by_convolution = measure_record(GroundMotion::evenly_sampled("by convolution", dt, y), {});
  CHECK(README_PROCESSED_PGD == within(by_convolution.pgd, 5e-7));
}
