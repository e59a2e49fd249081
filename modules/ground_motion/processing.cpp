// Record processing (ground_motion.cppm: Processing, with its equations):
// cut, polynomial detrend, cosine taper, zero-phase Butterworth band-pass,
// velocity-fit baseline correction and resampling, in that order. The
// Butterworth sections are designed here, in double precision: Debian's
// filter-design libraries do not serve (liquid-dsp designs in single
// precision, too coarse for a corner of a few hundredths of the sampling
// rate's thousandth; rtfilter does not expose its coefficients, so its
// response could not be checked against the prototype's). Polynomial fits
// are least squares by Eigen's column-pivoting QR on tau = 2 t / T - 1.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>
#include <utility>
#include <fmt/format.h>
#include <fmt/ranges.h>
module rocking.ground_motion;
import rocking.errors;

namespace rocking {

namespace {

constexpr double pi = std::numbers::pi;

// Least-squares fit of sum_j c_j tau^j, j in [first, last], tau = 2 t / T - 1 on
// [-1, 1] (conditioning), to y at t_i = i dt; returns the fitted values or,
// with `derivative`, their time derivative.
std::vector<double> polynomial_fit(const std::vector<double>& y, double dt, int first, int last, bool derivative) {
  const Eigen::Index n = static_cast<Eigen::Index>(y.size()), m = last - first + 1;
  const double T = dt * static_cast<double>(n - 1);
  Eigen::MatrixXd V(n, m);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double tau = 2.0 * static_cast<double>(i) / static_cast<double>(n - 1) - 1.0;
    for (int j = first; j <= last; ++j) V(i, j - first) = std::pow(tau, j);
  }
  const Eigen::VectorXd c = V.colPivHouseholderQr().solve(Eigen::Map<const Eigen::VectorXd>(y.data(), n));
  std::vector<double> out(y.size(), 0.0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double tau = 2.0 * static_cast<double>(i) / static_cast<double>(n - 1) - 1.0;
    double sum = 0;
    for (int j = first; j <= last; ++j) {
      const double cj = c[j - first];
      if (!derivative) sum += cj * std::pow(tau, j);
      else if (j > 0) sum += cj * j * std::pow(tau, j - 1) * 2.0 / T;  // d tau / dt = 2 / T
    }
    out[static_cast<std::size_t>(i)] = sum;
  }
  return out;
}

void run_sections(const std::vector<SecondOrderSection>& sections, std::vector<double>& x) {
  for (const SecondOrderSection& s : sections) {
    double z1 = 0, z2 = 0;  // direct form II transposed
    for (double& v : x) {
      const double in = v, out = s.b0 * in + z1;
      z1 = s.b1 * in - s.a1 * out + z2;
      z2 = s.b2 * in - s.a2 * out;
      v = out;
    }
  }
}

std::string number(double v) { return fmt::format("{:g}", v); }

// The record read every dt from t = 0 to its end.
std::vector<double> read_every(const GroundMotion& g, double dt) {
  const std::size_t n = static_cast<std::size_t>(std::floor(g.duration() / dt + 1e-9)) + 1;
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = g.acceleration(dt * static_cast<double>(i));
  return out;
}

}  // namespace

std::vector<SecondOrderSection> butterworth(int order, double corner_hz, double dt, bool highpass) {
  if (order < 1 || order > 8) throw InputError(fmt::format("Butterworth order {}: must be 1 to 8", order));
  if (!(dt > 0) || !(corner_hz > 0) || !(corner_hz < 0.5 / dt))
    throw InputError(fmt::format("Butterworth corner {:g} Hz: must be positive and below the Nyquist frequency {:g} Hz",
                                 corner_hz, 0.5 / dt));
  const double W = std::tan(pi * corner_hz * dt), W2 = W * W;  // the prewarped corner
  std::vector<SecondOrderSection> out;
  for (int k = 1; k <= order / 2; ++k) {
    // The pole pair -sin(theta) +- i cos(theta): s^2 + c s + 1, c = 2 sin(theta), at W.
    const double c = 2.0 * std::sin(pi * (2.0 * k - 1.0) / (2.0 * order));
    const double a0 = 1 + c * W + W2;
    SecondOrderSection s;
    s.a1 = 2 * (W2 - 1) / a0;
    s.a2 = (1 - c * W + W2) / a0;
    if (highpass) {
      s.b0 = 1 / a0;
      s.b1 = -2 / a0;
      s.b2 = 1 / a0;
    } else {
      s.b0 = W2 / a0;
      s.b1 = 2 * W2 / a0;
      s.b2 = W2 / a0;
    }
    out.push_back(s);
  }
  if (order % 2 == 1) {  // the real pole -1: s + 1, at W
    SecondOrderSection s;
    s.a1 = (W - 1) / (W + 1);
    s.b0 = (highpass ? 1 : W) / (W + 1);
    s.b1 = highpass ? -s.b0 : s.b0;
    out.push_back(s);
  }
  return out;
}

double magnitude(const std::vector<SecondOrderSection>& sections, double f_hz, double dt) {
  const std::complex<double> z1 = std::polar(1.0, -2 * pi * f_hz * dt), z2 = z1 * z1;  // z^-1, z^-2
  std::complex<double> h = 1.0;
  for (const SecondOrderSection& s : sections) h *= (s.b0 + s.b1 * z1 + s.b2 * z2) / (1.0 + s.a1 * z1 + s.a2 * z2);
  return std::abs(h);
}

std::vector<double> zero_phase(const std::vector<SecondOrderSection>& sections, std::vector<double> x) {
  run_sections(sections, x);
  std::ranges::reverse(x);
  run_sections(sections, x);
  std::ranges::reverse(x);
  return x;
}

std::vector<double> detrend(const std::vector<double>& a, double dt, int order) {
  const std::vector<double> fit = polynomial_fit(a, dt, 0, order, false);
  std::vector<double> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] - fit[i];
  return out;
}

std::vector<double> velocity_fit(const std::vector<double>& a, double dt, int order) {
  std::vector<double> v(a.size(), 0.0);  // exact for the piecewise-linear a, from rest
  for (std::size_t i = 1; i < a.size(); ++i) v[i] = v[i - 1] + 0.5 * dt * (a[i - 1] + a[i]);
  // The polynomial (with its constant) fit to v; its derivative leaves a.
  const std::vector<double> slope = polynomial_fit(v, dt, 0, order, true);
  std::vector<double> out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] - slope[i];
  return out;
}

std::vector<double> cosine_taper(std::vector<double> a, double fraction) {
  const std::size_t n = a.size();
  const std::size_t m = static_cast<std::size_t>(std::floor(fraction * static_cast<double>(n)));
  for (std::size_t i = 0; i < m && i < n; ++i) {
    const double w = 0.5 * (1 - std::cos(pi * static_cast<double>(i) / static_cast<double>(m)));
    a[i] *= w;
    a[n - 1 - i] *= w;
  }
  return a;
}

std::string Processing::describe() const {
  std::vector<std::string> parts;
  if (cut) parts.push_back(fmt::format("cut {}-{} s", number((*cut)[0]), number((*cut)[1])));
  if (detrend >= 0) parts.push_back(detrend == 0 ? "mean removed" : fmt::format("detrend {}", detrend));
  if (taper > 0) parts.push_back(fmt::format("taper {} %", number(100 * taper)));
  if (highpass > 0 && lowpass > 0)
    parts.push_back(fmt::format("Butterworth {}-{} Hz order {} zero-phase", number(highpass), number(lowpass), order));
  else if (highpass > 0) parts.push_back(fmt::format("Butterworth high-pass {} Hz order {} zero-phase", number(highpass), order));
  else if (lowpass > 0) parts.push_back(fmt::format("Butterworth low-pass {} Hz order {} zero-phase", number(lowpass), order));
  if (velocity_fit >= 0) parts.push_back(fmt::format("velocity fit {}", velocity_fit));
  if (dt > 0) parts.push_back(fmt::format("dt {} s", number(dt)));
  return fmt::format("{}", fmt::join(parts, ", "));
}

Processing parse_processing(std::string_view text) {
  Processing p;
  const auto fail = [&](std::string_view part, std::string_view what) {
    throw InputError(fmt::format("{}: {}", part, what));
  };
  const auto value = [&](std::string_view part, std::string_view v) {
    double x = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), x);
    if (ec != std::errc() || end != v.data() + v.size() || !std::isfinite(x)) fail(part, "not a number");
    return x;
  };
  const auto whole = [&](std::string_view part, std::string_view v, int lo, int hi) {
    const double x = value(part, v);
    if (x != std::floor(x) || x < lo || x > hi) fail(part, fmt::format("must be a whole number from {} to {}", lo, hi));
    return static_cast<int>(x);
  };
  if (text.empty()) throw InputError("empty (give e.g. highpass=0.1,lowpass=25,taper=0.05,detrend=1)");
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    const std::string_view part = text.substr(at, comma - at);
    at = comma + 1;
    const std::size_t eq = part.find('=');
    if (eq == std::string_view::npos) fail(part, "expected KEY=VALUE (keys: cut, detrend, taper, highpass, lowpass, order, vfit, dt)");
    const std::string_view key = part.substr(0, eq), v = part.substr(eq + 1);
    if (key == "highpass" || key == "lowpass") {
      const double f = value(part, v);
      if (!(f > 0)) fail(part, "a corner must be positive [Hz]");
      (key == "highpass" ? p.highpass : p.lowpass) = f;
    } else if (key == "order") {
      p.order = whole(part, v, 1, 8);
    } else if (key == "taper") {
      p.taper = value(part, v);
      if (!(p.taper >= 0 && p.taper <= 0.5)) fail(part, "the fraction at each end must be in [0, 0.5]");
    } else if (key == "detrend") {
      p.detrend = whole(part, v, 0, 6);
    } else if (key == "vfit") {
      p.velocity_fit = whole(part, v, 1, 6);
    } else if (key == "dt") {
      p.dt = value(part, v);
      if (!(p.dt >= 1e-6 && p.dt <= 10)) fail(part, "must be in [1e-06, 10] s");
    } else if (key == "cut") {
      const std::size_t colon = v.find(':');
      if (colon == std::string_view::npos) fail(part, "expected cut=T0:T1 [s]");
      const double t0 = value(part, v.substr(0, colon)), t1 = value(part, v.substr(colon + 1));
      if (!(t0 >= 0 && t1 > t0)) fail(part, "needs 0 <= T0 < T1");
      p.cut = std::array<double, 2>{t0, t1};
    } else {
      fail(part, "unknown key (keys: cut, detrend, taper, highpass, lowpass, order, vfit, dt)");
    }
  }
  if (p.highpass > 0 && p.lowpass > 0 && !(p.highpass < p.lowpass)) fail("highpass, lowpass", "the high-pass corner must be below the low-pass one");
  return p;
}

GroundMotion process(const GroundMotion& g, const Processing& p) {
  if (!g.piecewise_linear()) throw InputError(fmt::format("{}: an analytic pulse is not processed", g.name()));
  // A record resampled beyond this many samples is a mistake, not a record (and would take gigabytes).
  constexpr double max_samples = 1e7;
  if (p.dt > 0 && g.duration() / p.dt > max_samples)
    throw InputError(fmt::format("{}: processing dt={:g} makes {:.3g} samples of its {:g} s (at most {:g})", g.name(), p.dt,
                                 g.duration() / p.dt, g.duration(), max_samples));
  double dt = g.sample_interval();
  std::vector<double> a;
  if (p.cut) {
    const auto [t0, t1] = *p.cut;
    if (!(t1 <= g.duration() + 1e-9))
      throw InputError(fmt::format("{}: processing cut {:g}-{:g} s: the record ends at {:g} s", g.name(), t0, t1, g.duration()));
    if (!(dt > 0)) dt = p.dt > 0 ? p.dt : g.duration() / static_cast<double>(g.sample_count() - 1);
    const std::size_t n = static_cast<std::size_t>(std::floor((t1 - t0) / dt + 1e-9)) + 1;
    for (std::size_t i = 0; i < n; ++i) a.push_back(g.acceleration(t0 + dt * static_cast<double>(i)));
  } else if (dt > 0) {
    a = g.sample_values();
  } else {  // unevenly sampled: read at the interval asked for
    if (!(p.dt > 0))
      throw InputError(fmt::format("{}: unevenly sampled; processing needs dt=... to resample it first", g.name()));
    dt = p.dt;
    a = read_every(g, dt);
  }
  if (a.size() < 2) throw InputError(fmt::format("{}: processing leaves fewer than two samples", g.name()));
  if (p.detrend >= 0) a = detrend(a, dt, p.detrend);
  if (p.taper > 0) a = cosine_taper(std::move(a), p.taper);
  std::vector<SecondOrderSection> band;
  for (const auto& [corner, high] : {std::pair{p.highpass, true}, std::pair{p.lowpass, false}})
    if (corner > 0) {
      if (!(corner < 0.5 / dt))
        throw InputError(fmt::format("{}: processing corner {:g} Hz: at or above the Nyquist frequency {:g} Hz of its "
                                     "{:g} s samples", g.name(), corner, 0.5 / dt, dt));
      for (const SecondOrderSection& s : butterworth(p.order, corner, dt, high)) band.push_back(s);
    }
  if (!band.empty()) a = zero_phase(band, std::move(a));
  if (p.velocity_fit >= 0) a = velocity_fit(a, dt, p.velocity_fit);
  GroundMotion out = GroundMotion::evenly_sampled(g.name(), dt, std::move(a));
  if (p.dt > 0 && p.dt != dt) {
    out = GroundMotion::evenly_sampled(g.name(), p.dt, read_every(out, p.dt));
  }
  RecordInfo info = g.info();
  info.processing = p.describe();
  info.dt = out.sample_interval();
  info.npts = out.sample_count();
  info.stated_peak.reset();
  out.set_info(std::move(info));
  out.set_description(g.description().empty() ? "processed: " + p.describe()
                                              : fmt::format("{}; processed: {}", g.description(), p.describe()));
  return out;
}

}  // namespace rocking
