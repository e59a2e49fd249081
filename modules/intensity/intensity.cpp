module;
#include <array>
#include <algorithm>
#include <numeric>
#include <cmath>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.intensity;
import rocking.errors;
import rocking.ground_motion;

namespace rocking {

namespace {

constexpr double pi = std::numbers::pi;

struct Samples {
  std::vector<double> t, a;
};

void require_record(const GroundMotion& g) {
  if (!g.piecewise_linear())
    throw InputError(fmt::format("{}: intensity measures are defined for records, not for an analytic pulse", g.name()));
}

Samples samples_of(const GroundMotion& g) {
  require_record(g);
  return {g.sample_times(), g.sample_values()};
}

void check_damping(double zeta) {
  if (!(zeta >= 0 && zeta < 1)) throw InputError(fmt::format("damping {} must be in [0, 1)", zeta));
}

// The oscillator's exact step over h for a(tau) = a0 + s tau: the particular
// solution p + q tau plus the free decay of what is left (y, y').
class Oscillator {
 public:
  Oscillator(double period, double zeta)
      : w_(2 * pi / period), zeta_(zeta), wd_(w_ * std::sqrt(1 - zeta * zeta)) {}
  double omega() const { return w_; }
  double max_step() const { return 2 * pi / w_ / 20; }

  // Position and velocity after tau from (x0, v0) under a0 + s tau.
  // The step is linear in (x0, v0, a0, s): its eight coefficients are
  // computed once per step length.
  void advance(double x0, double v0, double a0, double s, double tau, double& x, double& v) const {
    if (tau != tau_) set_step(tau);
    x = k_[0] * x0 + k_[1] * v0 + k_[2] * a0 + k_[3] * s;
    v = k_[4] * x0 + k_[5] * v0 + k_[6] * a0 + k_[7] * s;
  }

  // The largest |x| strictly inside a step whose velocity changes sign: where
  // v = 0, by safeguarded Newton on the exact solution.
  double interior_peak(double x0, double v0, double a0, double s, double h, double v1) const {
    double lo = 0, hi = h, tau = h * v0 / (v0 - v1);
    double x = x0, v = v0;
    for (int it = 0; it < 50; ++it) {
      const double e = std::exp(-zeta_ * w_ * tau);
      state(x0, v0, a0, s, tau, e, std::cos(wd_ * tau), std::sin(wd_ * tau), x, v);
      if ((v > 0) == (v0 > 0)) lo = tau;
      else hi = tau;
      const double acc = -(a0 + s * tau) - 2 * zeta_ * w_ * v - w_ * w_ * x;  // dv/dtau
      double next = acc != 0 ? tau - v / acc : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - tau) <= 1e-15 * h || hi - lo <= 1e-15 * h) break;
      tau = next;
    }
    return std::abs(x);
  }

 private:
  void set_step(double tau) const {
    tau_ = tau;
    const double E = std::exp(-zeta_ * w_ * tau), C = std::cos(wd_ * tau), S = std::sin(wd_ * tau);
    for (int j = 0; j < 4; ++j) {
      double u[4] = {0, 0, 0, 0};
      u[j] = 1;
      state(u[0], u[1], u[2], u[3], tau, E, C, S, k_[j], k_[4 + j]);
    }
  }
  void state(double x0, double v0, double a0, double s, double tau, double E, double C, double S, double& x,
             double& v) const {
    const double w2 = w_ * w_;
    const double q = -s / w2, p = (-a0 + 2 * zeta_ * s / w_) / w2;
    const double y0 = x0 - p, yd0 = v0 - q;
    x = E * (y0 * C + (yd0 + zeta_ * w_ * y0) / wd_ * S) + p + q * tau;
    v = E * (yd0 * C - (w2 * y0 + zeta_ * w_ * yd0) / wd_ * S) + q;
  }

  double w_, zeta_, wd_;
  mutable double tau_ = -1;
  mutable double k_[8] = {};
};

// The peak |x| over one oscillator step from (x, v) to (x1, v1) under a0 + s tau, given the peak so far.
double step_peak(const Oscillator& osc, double x, double v, double x1, double v1, double a0, double s, double hs,
                 double peak) {
  if ((v > 0 && v1 < 0) || (v < 0 && v1 > 0)) {
    // The Hermite cubic through (x, v) at both ends finds the interior
    // extremum to about (w hs)^4 / 384 < 3e-5 of the response: the exact
    // search runs only where that could set a new peak.
    const double c2 = (3 * (x1 - x) / hs - 2 * v - v1) / hs, c3 = (v + v1 - 2 * (x1 - x) / hs) / (hs * hs);
    double tau = 0.5 * hs;
    if (c3 != 0) {
      const double disc = std::max(0.0, c2 * c2 - 3 * c3 * v);
      const double q = -(c2 + std::copysign(std::sqrt(disc), c2));
      const double r1 = q / (3 * c3), r2 = q != 0 ? v / q : -1.0;
      tau = r1 > 0 && r1 < hs ? r1 : r2;
    } else if (c2 != 0) {
      tau = -v / (2 * c2);
    }
    const double estimate = std::abs(x + tau * (v + tau * (c2 + tau * c3)));
    if (estimate > (1 - 1e-3) * peak) peak = std::max(peak, osc.interior_peak(x, v, a0, s, hs, v1));
  }
  return std::max(peak, std::abs(x1));
}

// max |x| of the oscillator from rest over the record.
double peak_displacement(const Samples& r, double period, double zeta) {
  const Oscillator osc(period, zeta);
  double x = 0, v = 0, peak = 0;
  for (std::size_t i = 0; i + 1 < r.t.size(); ++i) {
    const double h = r.t[i + 1] - r.t[i];
    const double s = (r.a[i + 1] - r.a[i]) / h;
    const int m = std::max(1, static_cast<int>(std::ceil(h / osc.max_step() - 1e-9)));
    const double hs = h / m;
    for (int k = 0; k < m; ++k) {
      const double a0 = r.a[i] + s * hs * k;
      double x1, v1;
      osc.advance(x, v, a0, s, hs, x1, v1);
      peak = step_peak(osc, x, v, x1, v1, a0, s, hs, peak);
      x = x1;
      v = v1;
    }
  }
  return peak;
}

// PSA at each period [m/s^2].
std::vector<double> spectrum_of(const Samples& r, const std::vector<double>& periods, double damping) {
  check_damping(damping);
  std::vector<double> out;
  for (double T : periods) {
    check_period(T);
    out.push_back(std::pow(2 * pi / T, 2) * peak_displacement(r, T, damping));
  }
  return out;
}

// The time within [t0, t0 + h] at which int_t0^t a^2 reaches `target`
// (from `start`, its value at t0), a = a0 + s tau: bisection on the cubic.
double arias_crossing(double t0, double h, double a0, double s, double start, double target) {
  auto cumulative = [&](double tau) {
    return start + a0 * a0 * tau + a0 * s * tau * tau + s * s * tau * tau * tau / 3;
  };
  double lo = 0, hi = h;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * h; ++it) {
    const double mid = 0.5 * (lo + hi);
    (cumulative(mid) < target ? lo : hi) = mid;
  }
  return t0 + 0.5 * (lo + hi);
}

}  // namespace

GroundHistory integrate_record(const GroundMotion& g) {
  const Samples r = samples_of(g);
  GroundHistory h;
  h.t = r.t;
  h.a = r.a;
  h.v.resize(r.t.size());
  h.d.resize(r.t.size());
  GroundTravel travel(g);
  for (std::size_t i = 0; i < r.t.size(); ++i) {
    const GroundTravel::State s = travel.at(r.t[i]);
    h.v[i] = s.v;
    h.d[i] = s.d;
  }
  return h;
}

RecordMeasures measure_record(const GroundMotion& g, const std::vector<double>& periods, double damping) {
  check_damping(damping);
  for (double T : periods) check_period(T);  // before any work
  const GroundHistory hist = integrate_record(g);
  const std::vector<double>& t = hist.t;
  const std::vector<double>& a = hist.a;
  const std::vector<double>& v = hist.v;
  const std::vector<double>& d = hist.d;
  RecordMeasures m;
  m.damping = damping;
  double energy = 0;  // int a^2 dt
  std::vector<double> cumulative(t.size(), 0.0);
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (std::abs(a[i]) > m.pga) {
      m.pga = std::abs(a[i]);
      m.pga_time = t[i];
    }
    m.pgv = std::max(m.pgv, std::abs(v[i]));
    m.pgd = std::max(m.pgd, std::abs(d[i]));
    if (i + 1 == t.size()) break;
    const double h = t[i + 1] - t[i], a0 = a[i], a1 = a[i + 1], s = (a1 - a0) / h;
    // Between samples: v peaks where a = 0, d where v = 0.
    if (s != 0) {
      const double tau = -a0 / s;
      if (tau > 0 && tau < h) m.pgv = std::max(m.pgv, std::abs(v[i] + a0 * tau + s * tau * tau / 2));
    }
    const double qa = s / 2, qb = a0, qc = v[i];  // v(tau) = qa tau^2 + qb tau + qc
    auto d_at = [&](double tau) { return d[i] + v[i] * tau + a0 * tau * tau / 2 + s * tau * tau * tau / 6; };
    if (qa != 0) {
      const double disc = qb * qb - 4 * qa * qc;
      if (disc >= 0) {
        const double root = std::sqrt(disc);
        const double q = -0.5 * (qb + std::copysign(root, qb));
        for (double tau : {q / qa, q != 0 ? qc / q : -1.0})
          if (tau > 0 && tau < h) m.pgd = std::max(m.pgd, std::abs(d_at(tau)));
      }
    } else if (qb != 0) {
      const double tau = -qc / qb;
      if (tau > 0 && tau < h) m.pgd = std::max(m.pgd, std::abs(d_at(tau)));
    }
    energy += h * (a0 * a0 + a0 * a1 + a1 * a1) / 3;
    cumulative[i + 1] = energy;
    m.cav += (a0 >= 0) == (a1 >= 0) ? h * (std::abs(a0) + std::abs(a1)) / 2
                                    : h * (a0 * a0 + a1 * a1) / (2 * (std::abs(a0) + std::abs(a1)));
  }
  m.arias = pi / (2 * gravity) * energy;
  if (energy > 0) {
    auto crossing = [&](double fraction) {
      const double target = fraction * energy;
      const std::size_t i = static_cast<std::size_t>(
          std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
      if (i == 0) return t[0];
      const double h = t[i] - t[i - 1];
      return arias_crossing(t[i - 1], h, a[i - 1], (a[i] - a[i - 1]) / h, cumulative[i - 1], target);
    };
    m.t5 = crossing(0.05);
    m.t95 = crossing(0.95);
    m.d5_95 = m.t95 - m.t5;
  }
  m.periods = periods;
  m.psa = spectrum_of({t, a}, periods, damping);
  return m;
}

std::array<double, 2> strong_shaking_window(const GroundMotion& g) {
  const RecordMeasures m = measure_record(g, {});
  const double margin = std::max(2.0, 0.25 * m.d5_95);
  return {std::max(0.0, m.t5 - margin), std::min(g.duration(), m.t95 + margin)};
}

double pseudo_spectral_acceleration(const GroundMotion& g, double period, double damping) {
  return response_spectrum(g, {period}, damping).front();
}

std::vector<double> response_spectrum(const GroundMotion& g, const std::vector<double>& periods, double damping) {
  return spectrum_of(samples_of(g), periods, damping);
}

std::vector<RotD> rotd_spectrum(const GroundMotion& first, const GroundMotion& second, const std::vector<double>& periods,
                                double damping) {
  check_damping(damping);
  for (double T : periods) check_period(T);  // before any work
  const HorizontalPair pair = pair_components(first, second);
  constexpr int azimuths = 180;
  std::array<std::array<double, 2>, azimuths> along{};
  for (int k = 0; k < azimuths; ++k) along[static_cast<std::size_t>(k)] = direction_cosines(k);
  // Each component's oscillator state at the start of every step, with the
  // step's ground acceleration a0 + s tau; the last entry is the end state.
  struct Step {
    double x[2], v[2], a0[2], s[2];
  };
  std::vector<RotD> out;
  std::vector<Step> steps;
  std::vector<double> bound;
  std::vector<std::size_t> order;
  std::array<double, azimuths> psa{};
  for (double T : periods) {
    const Oscillator osc(T, damping);
    const std::size_t n = pair.first.size();
    const double h = pair.dt;
    const int m = std::max(1, static_cast<int>(std::ceil(h / osc.max_step() - 1e-9)));
    const double hs = h / m;
    steps.clear();
    Step at{};
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double a[2][2] = {{pair.first[i], pair.first[i + 1]}, {pair.second[i], pair.second[i + 1]}};
      for (int k = 0; k < m; ++k) {
        for (int c = 0; c < 2; ++c) {
          at.s[c] = (a[c][1] - a[c][0]) / h;
          at.a0[c] = a[c][0] + at.s[c] * hs * k;
        }
        steps.push_back(at);
        for (int c = 0; c < 2; ++c) osc.advance(at.x[c], at.v[c], at.a0[c], at.s[c], hs, at.x[c], at.v[c]);
      }
    }
    steps.push_back(at);
    // No azimuth's response exceeds the vector's length: within step j,
    // |x1 cos + x2 sin| <= hypot(peak |x1|, peak |x2|) = bound[j]. A step
    // whose bound is below an azimuth's peak so far cannot raise it, and is
    // skipped; the peaks start from the steps of the largest bounds, so that
    // most steps are. The peaks are those of the full scan (a maximum, over
    // the same steps that can reach it).
    const std::size_t count = steps.size() - 1;
    bound.resize(count);
    for (std::size_t j = 0; j < count; ++j) {
      const Step& p = steps[j];
      const Step& q = steps[j + 1];
      double each[2];
      for (int c = 0; c < 2; ++c) each[c] = step_peak(osc, p.x[c], p.v[c], q.x[c], q.v[c], p.a0[c], p.s[c], hs, 0.0);
      bound[j] = std::hypot(each[0], each[1]) * (1 + 1e-12);  // rounding cannot lift a projection above it
    }
    order.resize(count);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const std::size_t first = std::min<std::size_t>(count, 64);
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(first), order.end(),
                      [&](std::size_t a, std::size_t b) { return bound[a] > bound[b]; });
    for (std::size_t k = 0; k < azimuths; ++k) {
      const double c = along[k][0], s = along[k][1];
      double peak = 0;
      const auto visit = [&](std::size_t j) {
        const Step& p = steps[j];
        const Step& q = steps[j + 1];
        peak = step_peak(osc, c * p.x[0] + s * p.x[1], c * p.v[0] + s * p.v[1], c * q.x[0] + s * q.x[1],
                         c * q.v[0] + s * q.v[1], c * p.a0[0] + s * p.a0[1], c * p.s[0] + s * p.s[1], hs, peak);
      };
      for (std::size_t i = 0; i < first; ++i) visit(order[i]);
      for (std::size_t j = 0; j < count; ++j)
        if (bound[j] > peak) visit(j);
      psa[k] = std::pow(2 * pi / T, 2) * peak;
    }
    std::array<double, azimuths> sorted = psa;
    std::ranges::sort(sorted);
    out.push_back({0.5 * (sorted[azimuths / 2 - 1] + sorted[azimuths / 2]), sorted.back()});
  }
  return out;
}

void check_period(double T) {
  if (!(T >= shortest_period && T <= longest_period))
    throw InputError(fmt::format("period {:g} s: must be in [{:g}, {:g}] s", T, shortest_period, longest_period));
}

std::vector<double> standard_periods() {
  return {0.01, 0.02, 0.03, 0.05, 0.075, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4,
          0.5,  0.75, 1.0,  1.5,  2.0,   3.0, 4.0,  5.0, 7.5,  10.0};
}

std::vector<double> log_periods(double from, double to, int n) {
  check_period(from);
  check_period(to);
  std::vector<double> out;
  for (int i = 0; i < n; ++i)
    out.push_back(n == 1 ? from : from * std::pow(to / from, static_cast<double>(i) / (n - 1)));
  return out;
}

std::string IntensityMeasure::name() const {
  switch (kind) {
    case Kind::scale_factor: return "sf";
    case Kind::pga: return "pga";
    case Kind::pgv: return "pgv";
    case Kind::sa: return fmt::format("sa:{:g}", t1);
    case Kind::saavg: return fmt::format("saavg:{:g}:{:g}", t1, t2);
    case Kind::rotd50: return fmt::format("rotd50:{:g}", t1);
    case Kind::rotd100: return fmt::format("rotd100:{:g}", t1);
  }
  return "sf";
}

std::string IntensityMeasure::unit() const {
  switch (kind) {
    case Kind::scale_factor: return "";
    case Kind::pgv: return "m/s";
    default: return "g";
  }
}

IntensityMeasure parse_intensity_measure(std::string_view text, double damping, double first_period) {
  check_damping(damping);
  IntensityMeasure im;
  im.damping = damping;
  std::vector<std::string> parts;
  for (std::size_t at = 0;;) {
    const std::size_t colon = text.find(':', at);
    parts.emplace_back(text.substr(at, colon == std::string_view::npos ? std::string_view::npos : colon - at));
    if (colon == std::string_view::npos) break;
    at = colon + 1;
  }
  auto period = [&](const std::string& p) {
    // "T1" and "kT1" (0.2T1, 1.5T1): multiples of the structure's first period.
    const bool of_t1 = p.ends_with("T1");
    const std::string number = of_t1 ? p.substr(0, p.size() - 2) : p;
    if (of_t1 && !(first_period > 0))
      throw InputError(fmt::format("intensity measure '{}': '{}' needs the structure's first period (give a scene that "
                                   "has one; a rigid block has none)",
                                   text, p));
    std::size_t used = 0;
    double T = of_t1 && number.empty() ? 1 : 0;
    if (!number.empty()) {
      try {
        T = std::stod(number, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used != number.size()) T = 0;
    }
    if (of_t1) T *= first_period;
    if (!(T > 0) || !std::isfinite(T))
      throw InputError(fmt::format("intensity measure '{}': '{}' is not a period in seconds{}", text, p,
                                   first_period > 0 ? " or a multiple of T1" : ""));
    if (!(T >= shortest_period && T <= longest_period))
      throw InputError(fmt::format("intensity measure '{}': period {:g} s must be in [{:g}, {:g}] s", text, T,
                                   shortest_period, longest_period));
    return T;
  };
  const std::string& k = parts[0];
  if ((k == "sf" || k == "pga" || k == "pgv") && parts.size() == 1) {
    im.kind = k == "sf" ? IntensityMeasure::Kind::scale_factor : k == "pga" ? IntensityMeasure::Kind::pga
                                                                             : IntensityMeasure::Kind::pgv;
  } else if (k == "sa" && parts.size() == 2) {
    im.kind = IntensityMeasure::Kind::sa;
    im.t1 = period(parts[1]);
  } else if ((k == "rotd50" || k == "rotd100") && parts.size() == 2) {
    im.kind = k == "rotd50" ? IntensityMeasure::Kind::rotd50 : IntensityMeasure::Kind::rotd100;
    im.t1 = period(parts[1]);
  } else if (k == "saavg" && parts.size() == 3) {
    im.kind = IntensityMeasure::Kind::saavg;
    im.t1 = period(parts[1]);
    im.t2 = period(parts[2]);
    if (!(im.t2 > im.t1)) throw InputError(fmt::format("intensity measure '{}': T2 must exceed T1", text));
  } else {
    throw InputError(fmt::format("intensity measure '{}': choose sf, pga, pgv, sa:T, saavg:T1:T2, rotd50:T or rotd100:T",
                                 text));
  }
  return im;
}

double intensity(const GroundMotion& g, const IntensityMeasure& im) {
  using Kind = IntensityMeasure::Kind;
  switch (im.kind) {
    case Kind::scale_factor: return 1.0;
    case Kind::pga:
      require_record(g);
      return g.peak() / gravity;
    case Kind::pgv: return measure_record(g, {}, im.damping).pgv;
    case Kind::sa: return pseudo_spectral_acceleration(g, im.t1, im.damping) / gravity;
    case Kind::saavg: {
      const std::vector<double> psa = response_spectrum(g, log_periods(im.t1, im.t2, 10), im.damping);
      double log_sum = 0;
      for (double s : psa) log_sum += std::log(s);
      return std::exp(log_sum / static_cast<double>(psa.size())) / gravity;
    }
    case Kind::rotd50:
    case Kind::rotd100: {
      const GroundMotion* other = g.other_horizontal();
      if (!other)
        throw InputError(fmt::format("{}: {} needs its two horizontal components (a file that holds both, or a pair)",
                                     g.name(), im.name()));
      const RotD r = rotd_spectrum(g, *other, {im.t1}, im.damping).front();
      return (im.kind == Kind::rotd50 ? r.rotd50 : r.rotd100) / gravity;
    }
  }
  return 1.0;
}

}  // namespace rocking
