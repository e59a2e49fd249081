// rocking.intensity: intensity measures against closed forms, the response
// spectrum against the oscillator's closed form (harmonic and ramp ground
// motions) and against an independent integration of El Centro (4th-order
// Runge-Kutta on the record at a twentieth of its step), the peak between
// samples, and IM scaling; RotD50 and RotD100 against the spectra of the
// records rotated explicitly at every degree, and the projection of two
// components at an azimuth (MODEL.md 14).
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <functional>
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

// max |x(t)| on [0, end] of a smooth closed form: the largest of a fine grid,
// refined by golden-section search within a grid step either side.
double closed_form_peak(const std::function<double(double)>& x, double end, double grid) {
  const int n = static_cast<int>(std::ceil(end / grid));
  double best = 0, at = 0;
  for (int i = 0; i <= n; ++i) {
    const double t = std::min(end, i * grid);
    if (std::abs(x(t)) > best) best = std::abs(x(t)), at = t;
  }
  double lo = std::max(0.0, at - grid), hi = std::min(end, at + grid);
  const double r = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 200; ++it) {
    const double m1 = hi - r * (hi - lo), m2 = lo + r * (hi - lo);
    (std::abs(x(m1)) > std::abs(x(m2)) ? hi : lo) = (std::abs(x(m1)) > std::abs(x(m2)) ? m2 : m1);
  }
  return std::max(best, std::abs(x(0.5 * (lo + hi))));
}

// Free decay from (y0, yd0) of x'' + 2 zeta w x' + w^2 x = 0.
double decay(double t, double y0, double yd0, double w, double zeta) {
  const double wd = w * std::sqrt(1 - zeta * zeta);
  return std::exp(-zeta * w * t) * (y0 * std::cos(wd * t) + (yd0 + zeta * w * y0) / wd * std::sin(wd * t));
}

GroundMotion sampled(const std::function<double(double)>& a, double dt, double end) {
  std::vector<double> t, v;
  for (long i = 0; i * dt <= end + 1e-12; ++i) {
    t.push_back(i * dt);
    v.push_back(a(i * dt));
  }
  return GroundMotion::from_samples("test", t, v);
}

}  // namespace

TEST_CASE("PSA of a harmonic ground motion equals the oscillator's closed form to 1e-8") {
  // a = A sin(W t) from rest, sampled at dt with W dt = 6e-5, so that the
  // record's linear interpolation changes the response by about (W dt)^2 / 12.
  const double A = 2.0, W = 2 * pi, end = 3.0;
  const GroundMotion g = sampled([&](double t) { return A * std::sin(W * t); }, 1e-5, end);
  for (double T : {0.25, 1.7, 4.0}) {
    for (double zeta : {0.0, 0.05}) {
      CAPTURE(T);
      CAPTURE(zeta);
      const double w = 2 * pi / T, D = std::pow(w * w - W * W, 2) + std::pow(2 * zeta * w * W, 2);
      const double c1 = -A * (w * w - W * W) / D, c2 = 2 * A * zeta * w * W / D;
      auto x = [&](double t) { return c1 * std::sin(W * t) + c2 * std::cos(W * t) + decay(t, -c2, -c1 * W, w, zeta); };
      const double expected = w * w * closed_form_peak(x, end, std::min(T, 1.0) / 200);
      CHECK(pseudo_spectral_acceleration(g, T, zeta) == close_to(expected, 1e-8));
    }
  }
}

TEST_CASE("PSA of a single ramp equals the closed form to 1e-8 (one sample interval, many sub-steps)") {
  const double s = 3.0, end = 2.3;
  const GroundMotion g = GroundMotion::from_samples("ramp", {0.0, end}, {0.0, s * end});
  for (double T : {0.05, 0.4, 3.0}) {
    CAPTURE(T);
    const double w = 2 * pi / T, zeta = 0.05;
    const double q = -s / (w * w), p = 2 * zeta * s / (w * w * w);
    auto x = [&](double t) { return p + q * t + decay(t, -p, -q, w, zeta); };
    CHECK(pseudo_spectral_acceleration(g, T, zeta) == close_to(w * w * closed_form_peak(x, end, T / 200), 1e-8));
  }
}

TEST_CASE("the peak between samples is caught: a finer resampling of the same record gives the same PSA") {
  // Resampled linearly, a piecewise-linear record is the same function; a
  // spectrum that only looked at the samples would miss most of the peak at
  // periods near the sample interval.
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  const std::vector<double> t = g.sample_times(), a = g.sample_values();
  std::vector<double> tf, af;
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
    for (int k = 0; k < 8; ++k) {
      tf.push_back(t[i] + (t[i + 1] - t[i]) * k / 8.0);
      af.push_back(a[i] + (a[i + 1] - a[i]) * k / 8.0);
    }
  tf.push_back(t.back());
  af.push_back(a.back());
  const GroundMotion fine = GroundMotion::from_samples("fine", tf, af);
  for (double T : {0.01, 0.02, 0.05, 0.3}) {
    CAPTURE(T);
    CHECK(pseudo_spectral_acceleration(fine, T) == close_to(pseudo_spectral_acceleration(g, T), 1e-9));
  }
  // At T = dt the spectral acceleration is near the PGA, as it must be for a
  // rigid oscillator: within 2 %, the amplification of the record's content
  // near the oscillator's 100 Hz (0.6 % here).
  CHECK(pseudo_spectral_acceleration(g, 0.01) == close_to(g.peak(), 0.02));
}

TEST_CASE("PSA of El Centro at 0.5, 1 and 2 s agrees with an independent Runge-Kutta integration") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  for (double T : {0.5, 1.0, 2.0}) {
    CAPTURE(T);
    // Classic RK4 on (x, v) at h = dt / 20 = 1 ms, the record interpolated
    // linearly, the peak taken at the steps: the peak's sampling error is
    // about (w h)^2 / 8 <= 2e-5 and RK4's (w h)^4, so 1e-4 holds.
    const double w = 2 * pi / T, zeta = 0.05, h = 0.001;
    auto f = [&](double t, double x, double v, double& dx, double& dv) {
      dx = v;
      dv = -g.acceleration(t) - 2 * zeta * w * v - w * w * x;
    };
    double x = 0, v = 0, peak = 0;
    const long n = std::lround(g.duration() / h);
    for (long i = 0; i < n; ++i) {
      const double t = i * h;
      double k1x, k1v, k2x, k2v, k3x, k3v, k4x, k4v;
      f(t, x, v, k1x, k1v);
      f(t + h / 2, x + h / 2 * k1x, v + h / 2 * k1v, k2x, k2v);
      f(t + h / 2, x + h / 2 * k2x, v + h / 2 * k2v, k3x, k3v);
      f(t + h, x + h * k3x, v + h * k3v, k4x, k4v);
      x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
      v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
      peak = std::max(peak, std::abs(x));
    }
    CHECK(pseudo_spectral_acceleration(g, T) == close_to(w * w * peak, 1e-4));
  }
}

TEST_CASE("PGA, PGV, PGD, Arias intensity, CAV and D5-95 against closed forms") {
  const double A = 3.0, L = 2.0, g0 = gravity;
  // Constant a = A on [0, L].
  const RecordMeasures c = measure_record(GroundMotion::from_samples("c", {0.0, L}, {A, A}), {});
  CHECK(c.pga == close_to(A, 1e-12));
  CHECK(c.pgv == close_to(A * L, 1e-12));
  CHECK(c.pgd == close_to(A * L * L / 2, 1e-12));
  CHECK(c.arias == close_to(pi / (2 * g0) * A * A * L, 1e-14));
  CHECK(c.cav == close_to(A * L, 1e-14));
  CHECK(c.d5_95 == close_to(0.9 * L, 1e-12));
  // A ramp a = s t: int a^2 grows as t^3, so D5-95 = L (0.95^(1/3) - 0.05^(1/3)).
  const RecordMeasures r = measure_record(GroundMotion::from_samples("r", {0.0, L}, {0.0, A}), {});
  CHECK(r.d5_95 == close_to(L * (std::cbrt(0.95) - std::cbrt(0.05)), 1e-12));
  CHECK(r.arias == close_to(pi / (2 * g0) * A * A * L / 3, 1e-14));
  // From -A to A: v = -A t + A t^2 / L peaks between the samples at t = L/2.
  const RecordMeasures s = measure_record(GroundMotion::from_samples("s", {0.0, L}, {-A, A}), {});
  CHECK(s.pgv == close_to(A * L / 4, 1e-14));
  CHECK(s.cav == close_to(A * L / 2, 1e-14));
  CHECK(s.pgd == close_to(A * L * L / 6, 1e-14));
  // Then held at A for L: v = A (t - L) crosses zero at t = L, where
  // d = -A L^2 / 6 is a minimum; by 2 L, d = -A L^2/6 + A L^2/2.
  const RecordMeasures u = measure_record(GroundMotion::from_samples("u", {0.0, L, 2 * L}, {-A, A, A}), {});
  CHECK(u.pgd == close_to(A * L * L / 3, 1e-14));
  // Displacement peaking between samples: a = -A on [0, L], then rising to
  // 7 A over [L, 2 L] (a = -A + k tau, k = 8 A / L): v = -A L - A tau + k tau^2 / 2
  // is zero at tau = (A + sqrt(A^2 + 2 k A L)) / k, inside the interval.
  const RecordMeasures w = measure_record(GroundMotion::from_samples("w", {0.0, L, 2 * L}, {-A, -A, 7 * A}), {});
  const double k = 8 * A / L, tau = (A + std::sqrt(A * A + 2 * k * A * L)) / k;
  CHECK(tau < L);
  const double d_min = -A * L * L / 2 - A * L * tau - A * tau * tau / 2 + k * tau * tau * tau / 6;
  CHECK(std::abs(d_min) > std::abs(-A * L * L / 2 - A * L * L - A * L * L / 2 + k * L * L * L / 6));  // beyond the end's
  CHECK(w.pgd == close_to(std::abs(d_min), 1e-12));
}

TEST_CASE("IM scaling is exact: the scaled record's IM equals the level") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/elcentro_1940_ns.at2");
  for (const char* name : {"pga", "pgv", "sa:1", "sa:0.2", "saavg:0.2:2"}) {
    CAPTURE(name);
    const IntensityMeasure im = parse_intensity_measure(name);
    CHECK(im.name() == name);
    for (double level : {0.1, 0.75, 2.5}) {
      const double sf = level / intensity(g, im);
      CHECK(intensity(g.scaled(sf), im) == close_to(level, 1e-9));
    }
  }
  CHECK(intensity(g, parse_intensity_measure("pga")) == close_to(0.3188, 1e-3));
  CHECK_THROWS_WITH_AS(parse_intensity_measure("sa"),
                       "intensity measure 'sa': choose sf, pga, pgv, sa:T, saavg:T1:T2, rotd50:T or rotd100:T", InputError);
  CHECK_THROWS_WITH_AS(parse_intensity_measure("sa:-1"), "intensity measure 'sa:-1': '-1' is not a period in seconds", InputError);
  CHECK_THROWS_WITH_AS(parse_intensity_measure("saavg:2:1"), "intensity measure 'saavg:2:1': T2 must exceed T1", InputError);
  CHECK_THROWS_AS(measure_record(g, {0.0}), InputError);
  CHECK_THROWS_AS(measure_record(g, {1.0}, 1.0), InputError);
  // T1 stands for the structure's first period, kT1 for a multiple of it.
  const IntensityMeasure at_t1 = parse_intensity_measure("sa:T1", 0.05, 0.4);
  CHECK(at_t1.kind == IntensityMeasure::Kind::sa);
  CHECK(at_t1.t1 == 0.4);
  const IntensityMeasure avg = parse_intensity_measure("saavg:0.2T1:3T1", 0.05, 0.4);
  CHECK(avg.t1 == close_to(0.08, 1e-12));
  CHECK(avg.t2 == close_to(1.2, 1e-12));
  CHECK_THROWS_WITH_AS(parse_intensity_measure("sa:T1"),
                       "intensity measure 'sa:T1': 'T1' needs the structure's first period (give a scene that has one; "
                       "a rigid block has none)",
                       InputError);
  CHECK_THROWS_AS(parse_intensity_measure("sa:xT1", 0.05, 0.4), InputError);
  CHECK_THROWS_AS(parse_intensity_measure("sa:-2T1", 0.05, 0.4), InputError);
  CHECK_THROWS_AS(measure_record(GroundMotion::pulse(PulseShape::one_sine, 1, 1), {}), InputError);
}

TEST_CASE("the GeoNet file's velocity agrees with its own stated peak velocity") {
  // The V2A states the peak of its own (filtered) velocity; integrating its
  // acceleration from rest gives the same to within the processing's
  // difference (1 %).
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion g = read_record(*dir + "/formats/20161113_110259_WTMC_20.V2A");
  const RecordMeasures m = measure_record(g, standard_periods());
  CHECK(m.pgv == close_to(1.01655, 0.01));
  CHECK(m.pga == close_to(9.7331, 1e-6));
  CHECK(m.periods.size() == 21);
  CHECK(m.psa.size() == 21);
}

namespace {

// A synthetic pair of horizontal components: two different filtered noises.
GroundMotion noise(unsigned seed, double dt, int n) {
  std::vector<double> a;
  double x = 0, v = 0;
  unsigned state = seed;
  for (int i = 0; i < n; ++i) {
    state = state * 1664525u + 1013904223u;
    const double f = static_cast<double>(state >> 8) / static_cast<double>(1u << 24) - 0.5;
    const double w = 2 * pi * 3.0;
    v += dt * (-2 * 0.3 * w * v - w * w * x + 200 * f);
    x += dt * v;
    a.push_back(w * w * x);
  }
  return GroundMotion::evenly_sampled("noise " + std::to_string(seed), dt, a);
}

// RotD50 and RotD100 by another route: each record rotated explicitly (its
// samples projected at every degree), its PSA computed alone, the median and
// maximum of the 180 taken.
RotD rotated_explicitly(const GroundMotion& a1, const GroundMotion& a2, double T) {
  std::vector<double> psa;
  for (int k = 0; k < 180; ++k) psa.push_back(pseudo_spectral_acceleration(project(a1, a2, k), T));
  std::ranges::sort(psa);
  return {0.5 * (psa[89] + psa[90]), psa[179]};
}

}  // namespace

TEST_CASE("the projection at 0 and 90 degrees is the first and the second component, sample for sample") {
  const GroundMotion a1 = noise(1, 0.01, 500), a2 = noise(2, 0.01, 400);
  CHECK(project(a1, a2, 0).sample_values() == a1.sample_values());
  const std::vector<double> second = project(a1, a2, 90).sample_values();
  std::vector<double> padded = a2.sample_values();
  padded.resize(500, 0.0);  // the shorter component padded with zeros
  CHECK(second == padded);
  const std::vector<double> back = project(a1, a2, 180).sample_values();
  for (std::size_t i = 0; i < back.size(); ++i) CHECK(back[i] == -a1.sample_values()[i]);
  const GroundMotion at30 = project(a1, a2, 30);
  CHECK(at30.acceleration(0.5) == close_to(std::cos(pi / 6) * a1.acceleration(0.5) + 0.5 * a2.acceleration(0.5), 1e-12));
  REQUIRE(at30.other_horizontal());
  CHECK(at30.other_horizontal()->acceleration(0.5) ==
        close_to(-0.5 * a1.acceleration(0.5) + std::cos(pi / 6) * a2.acceleration(0.5), 1e-12));
  CHECK_THROWS_WITH_AS(project(a1, noise(3, 0.02, 100), 10), doctest::Contains("needs one time step"), InputError);
}

TEST_CASE("RotD50 and RotD100 equal the median and maximum of the spectra of the records rotated at every degree (1e-10)") {
  // The oscillator is linear: superposing the components' responses is the
  // rotated record's response to round-off, and both routes locate the
  // peaks between steps to round-off.
  const GroundMotion a1 = noise(1, 0.01, 1500), a2 = noise(2, 0.01, 1500);
  const std::vector<double> periods = {0.05, 0.3, 1.0, 3.0};
  const std::vector<RotD> r = rotd_spectrum(a1, a2, periods);
  for (std::size_t k = 0; k < periods.size(); ++k) {
    CAPTURE(periods[k]);
    const RotD expected = rotated_explicitly(a1, a2, periods[k]);
    CHECK(r[k].rotd50 == close_to(expected.rotd50, 1e-10));
    CHECK(r[k].rotd100 == close_to(expected.rotd100, 1e-10));
    CHECK(r[k].rotd50 <= r[k].rotd100);
    // RotD100 is at least either component's own PSA; RotD50 between their extremes' bounds
    CHECK(r[k].rotd100 >= pseudo_spectral_acceleration(a1, periods[k]) * (1 - 1e-12));
    CHECK(r[k].rotd100 >= pseudo_spectral_acceleration(a2, periods[k]) * (1 - 1e-12));
  }
  // Rotation invariance: the pair turned by a whole number of degrees has the same RotD.
  const GroundMotion turned = project(a1, a2, 37);
  const std::vector<RotD> t = rotd_spectrum(turned, *turned.other_horizontal(), periods);
  for (std::size_t k = 0; k < periods.size(); ++k) {
    CHECK(t[k].rotd50 == close_to(r[k].rotd50, 1e-9));
    CHECK(t[k].rotd100 == close_to(r[k].rotd100, 1e-9));
  }
}

TEST_CASE("RotD of the Waiau file's two horizontals: against explicit rotation, and as an intensity measure") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string waiau = *dir + "/formats/20161113_110259_WTMC_20.V2A";
  const GroundMotion g = read_record(waiau, {.other_horizontal = true});
  REQUIRE(g.other_horizontal());
  CHECK(g.info().component == "N28W");
  CHECK(g.other_horizontal()->info().component == "S62W");
  const RotD r = rotd_spectrum(g, *g.other_horizontal(), {1.0}).front();
  const RotD expected = rotated_explicitly(g, *g.other_horizontal(), 1.0);
  CHECK(r.rotd50 == close_to(expected.rotd50, 1e-6));
  CHECK(r.rotd100 == close_to(expected.rotd100, 1e-6));
  for (const char* name : {"rotd50:1", "rotd100:0.5"}) {
    CAPTURE(name);
    const IntensityMeasure im = parse_intensity_measure(name);
    CHECK(im.name() == name);
    const double sf = 0.7 / intensity(g, im);
    CHECK(intensity(g.scaled(sf), im) == close_to(0.7, 1e-9));  // scaled with its pair
  }
  CHECK(intensity(g, parse_intensity_measure("rotd50:1")) == close_to(r.rotd50 / gravity, 1e-12));
  // A record without its pair cannot have a RotD.
  CHECK_THROWS_WITH_AS(intensity(read_record(waiau), parse_intensity_measure("rotd50:1")),
                       doctest::Contains("needs its two horizontal components"), InputError);
  CHECK_THROWS_WITH_AS(read_record(*dir + "/elcentro_1940_ns.at2", {.other_horizontal = true}),
                       doctest::Contains("holds no other horizontal component"), InputError);
}
