module;
#include <algorithm>
#include <cctype>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.ground_motion;
import rocking.errors;

namespace rocking {

AccelerationUnit parse_acceleration_unit(std::string_view text) {
  if (text == "g") return AccelerationUnit::g;
  if (text == "m/s2") return AccelerationUnit::m_per_s2;
  if (text == "cm/s2" || text == "gal") return AccelerationUnit::cm_per_s2;
  if (text == "mm/s2") return AccelerationUnit::mm_per_s2;
  throw InputError(fmt::format("unknown acceleration unit '{}' (choose g, m/s2, cm/s2 (gal) or mm/s2)", text));
}

std::string unit_name(AccelerationUnit unit) {
  switch (unit) {
    case AccelerationUnit::g: return "g";
    case AccelerationUnit::m_per_s2: return "m/s2";
    case AccelerationUnit::cm_per_s2: return "cm/s2";
    case AccelerationUnit::mm_per_s2: return "mm/s2";
  }
  return "m/s2";
}

double to_si(AccelerationUnit unit) {
  switch (unit) {
    case AccelerationUnit::g: return gravity;
    case AccelerationUnit::m_per_s2: return 1.0;
    case AccelerationUnit::cm_per_s2: return 0.01;
    case AccelerationUnit::mm_per_s2: return 0.001;
  }
  return 1.0;
}

std::string RecordInfo::label() const {
  std::string out;
  for (const std::string* part : {&event, &station, &component})
    if (!part->empty()) out += (out.empty() ? "" : ", ") + *part;
  return out;
}

std::vector<double> GroundMotion::sample_times() const {
  std::vector<double> t(sample_count());
  for (std::size_t i = 0; i < t.size(); ++i) t[i] = time_of(i);
  return t;
}

std::vector<double> GroundMotion::sample_values() const {
  if (!samples_) return {};
  std::vector<double> v(samples_->values);
  for (double& x : v) x *= scale_;
  return v;
}

PulseShape parse_pulse_shape(std::string_view text) {
  if (text == "one-sine") return PulseShape::one_sine;
  if (text == "ricker") return PulseShape::ricker;
  throw InputError(fmt::format("unknown pulse '{}' (choose one-sine or ricker)", text));
}

GroundMotion GroundMotion::from_samples(std::string name, std::vector<double> times,
                                        std::vector<double> accelerations) {
  if (times.size() != accelerations.size() || times.size() < 2)
    throw InputError(fmt::format("{}: a record needs at least two samples", name));
  GroundMotion g;
  g.name_ = std::move(name);
  for (std::size_t i = 1; i < times.size(); ++i)
    if (!(times[i] > times[i - 1]))
      throw InputError(fmt::format("{}: sample times must increase (t[{}] = {} after {})", g.name_, i, times[i], times[i - 1]));
  for (std::size_t i = 1; i < times.size(); ++i)
    if (times[i] - times[i - 1] < min_record_dt * (1 - 1e-9))  // samples i dt apart meet the bound despite round-off
      throw InputError(fmt::format("{}: t[{}] = {:g} s comes {:g} s after the sample before: below {:g} s, not a "
                                   "record's time step", g.name_, i, times[i], times[i] - times[i - 1], min_record_dt));
  if (!(times.front() >= 0) || !(times.back() <= max_record_duration))
    throw InputError(fmt::format("{}: samples from t = {:g} s to {:g} s: a record lies within [0, {:g}] s", g.name_,
                                 times.front(), times.back(), max_record_duration));
  for (std::size_t i = 0; i < accelerations.size(); ++i)
    if (!(std::abs(accelerations[i]) <= max_acceleration_g * gravity))
      throw InputError(fmt::format("{}: acceleration [{}] = {:g} m/s2 is beyond {:g} g", g.name_, i, accelerations[i],
                                   max_acceleration_g));
  const double dt = (times.back() - times.front()) / static_cast<double>(times.size() - 1);
  const bool even = std::all_of(times.begin(), times.end(), [&, i = 0.0](double t) mutable {
    return std::abs(t - (times.front() + dt * i++)) <= 1e-9 * dt;
  });
  if (even && times.front() == 0.0) return evenly_sampled(std::move(g.name_), dt, std::move(accelerations));
  auto samples = std::make_shared<Samples>();
  g.duration_ = times.back();
  samples->times = std::move(times);
  samples->values = std::move(accelerations);
  for (double v : samples->values) samples->peak = std::max(samples->peak, std::abs(v));
  g.set_samples(std::move(samples));
  return g;
}

GroundMotion GroundMotion::pulse(PulseShape shape, double amplitude, double period) {
  if (!(period > 0) || !std::isfinite(period)) throw InputError(fmt::format("pulse period must be positive (got {})", period));
  if (!std::isfinite(amplitude)) throw InputError("pulse amplitude must be finite");
  GroundMotion g;
  g.shape_ = shape;
  g.amplitude_ = amplitude;
  g.period_ = period;
  if (shape == PulseShape::one_sine) {
    g.name_ = fmt::format("one-sine pulse, {:.3g} m/s2, T = {:.3g} s", amplitude, period);
    g.duration_ = period;
  } else {
    g.name_ = fmt::format("Ricker pulse, {:.3g} m/s2, f = {:.3g} Hz", amplitude, 1.0 / period);
    g.duration_ = 3.0 * period;  // t0 = 1.5 T; |a| < 1e-5 A beyond 2 t0
  }
  return g;
}

double GroundMotion::time_of(std::size_t i) const {
  return samples_->dt > 0 ? samples_->dt * static_cast<double>(i) : samples_->times[i];
}

std::size_t GroundMotion::sample_count() const { return samples_ ? samples_->values.size() : 0; }

double GroundMotion::acceleration_otherwise(double t) const {
  if (!samples_) {  // analytic pulse
    const double A = amplitude_ * scale_;
    if (shape_ == PulseShape::one_sine)
      return t >= 0 && t <= period_ ? A * std::sin(2 * std::numbers::pi * t / period_) : 0.0;
    const double u = std::pow(std::numbers::pi * (t - 1.5 * period_) / period_, 2);
    return A * (1 - 2 * u) * std::exp(-u);
  }
  // Evenly spaced samples are read inline (acceleration) within the record:
  // here they are asked for outside it.
  const Samples& sm = *samples_;
  if (sm.dt > 0 || !(t >= sm.times.front() && t <= duration_)) return 0.0;
  const std::size_t n = sm.values.size();
  std::size_t i = static_cast<std::size_t>(std::upper_bound(sm.times.begin(), sm.times.end(), t) - sm.times.begin());
  i = std::clamp<std::size_t>(i, 1, n - 1) - 1;
  const double s = (t - sm.times[i]) / (sm.times[i + 1] - sm.times[i]);
  return scale_ * ((1 - s) * sm.values[i] + s * sm.values[i + 1]);
}

double GroundMotion::next_breakpoint(double t) const {
  constexpr double none = std::numeric_limits<double>::infinity();
  if (!samples_) return shape_ == PulseShape::one_sine && t < period_ ? period_ : none;
  const Samples& sm = *samples_;
  const std::size_t n = sm.values.size();
  std::size_t i;
  if (sm.dt > 0) {
    const double x = std::floor(t * sm.inv_dt);
    i = x < 0 ? 0 : static_cast<std::size_t>(std::min(x, static_cast<double>(n)));
    while (i > 0 && time_of(i - 1) > t) --i;  // round-off in t / dt, either way
    while (i < n && time_of(i) <= t) ++i;
  } else {
    i = static_cast<std::size_t>(std::upper_bound(sm.times.begin(), sm.times.end(), t) - sm.times.begin());
  }
  return i < n ? time_of(i) : none;
}

double GroundMotion::max_step() const {
  return samples_ ? std::numeric_limits<double>::infinity() : period_ / 40.0;
}

double GroundMotion::peak() const {
  return (samples_ ? samples_->peak : std::abs(amplitude_)) * std::abs(scale_);
}

GroundMotion GroundMotion::scaled(double factor) const {
  if (!std::isfinite(factor)) throw InputError(fmt::format("scale factor must be finite (got {})", factor));
  GroundMotion g = *this;
  g.scale_ *= factor;
  if (!(g.peak() <= max_acceleration_g * gravity))
    throw InputError(fmt::format("scale factor {:g} takes {} to a peak of {:.4g} g, beyond {:g} g", factor, name_,
                                 g.peak() / gravity, max_acceleration_g));
  if (vertical_) g.vertical_ = std::make_shared<const GroundMotion>(vertical_->scaled(factor));
  if (other_) g.other_ = std::make_shared<const GroundMotion>(other_->scaled(factor));
  return g;
}

GroundMotion GroundMotion::with_vertical(const GroundMotion& v) const {
  GroundMotion g = *this;
  GroundMotion up = v;
  up.vertical_.reset();
  up.other_.reset();
  g.vertical_ = std::make_shared<const GroundMotion>(std::move(up));
  return g;
}

GroundMotion GroundMotion::with_other_horizontal(const GroundMotion& h) const {
  GroundMotion g = *this;
  GroundMotion other = h;
  other.vertical_.reset();
  other.other_.reset();
  g.other_ = std::make_shared<const GroundMotion>(std::move(other));
  return g;
}

GroundMotion GroundMotion::evenly_sampled(std::string name, double dt, std::vector<double> accelerations) {
  if (!(dt > 0) || !std::isfinite(dt)) throw InputError(fmt::format("{}: the sample interval must be positive", name));
  if (accelerations.size() < 2) throw InputError(fmt::format("{}: a record needs at least two samples", name));
  GroundMotion g;
  g.name_ = std::move(name);
  auto samples = std::make_shared<Samples>();
  samples->dt = dt;
  samples->inv_dt = 1.0 / dt;
  g.duration_ = dt * static_cast<double>(accelerations.size() - 1);
  samples->values = std::move(accelerations);
  for (double v : samples->values) samples->peak = std::max(samples->peak, std::abs(v));
  g.set_samples(std::move(samples));
  return g;
}

void GroundMotion::set_samples(std::shared_ptr<const Samples> samples) {
  const bool even = samples->dt > 0;
  even_values_ = even ? samples->values.data() : nullptr;
  even_inv_dt_ = even ? samples->inv_dt : 0.0;
  even_last_ = even ? samples->values.size() - 2 : 0;
  samples_ = std::move(samples);
}

std::array<double, 2> direction_cosines(double degrees) {
  const double quarters = degrees / 90.0;
  if (quarters == std::round(quarters) && std::abs(quarters) < 1e15) {  // exact on the axes
    switch (((static_cast<long long>(quarters) % 4) + 4) % 4) {
      case 0: return {1.0, 0.0};
      case 1: return {0.0, 1.0};
      case 2: return {-1.0, 0.0};
      default: return {0.0, -1.0};
    }
  }
  const double r = degrees * std::numbers::pi / 180.0;
  return {std::cos(r), std::sin(r)};
}

HorizontalPair pair_components(const GroundMotion& first, const GroundMotion& second) {
  const double dt1 = first.sample_interval(), dt2 = second.sample_interval();
  if (!(dt1 > 0) || !(dt2 > 0))
    throw InputError(fmt::format("{} and {}: a pair of horizontal components must both be records sampled evenly from "
                                 "t = 0", first.name(), second.name()));
  if (std::abs(dt1 - dt2) > 1e-9 * dt1)
    throw InputError(fmt::format("{} and {}: sampled every {:g} s and {:g} s; a pair of horizontal components needs one "
                                 "time step", first.name(), second.name(), dt1, dt2));
  HorizontalPair p;
  p.dt = dt1;
  p.first = first.sample_values();
  p.second = second.sample_values();
  const std::size_t n = std::max(p.first.size(), p.second.size());
  p.first.resize(n, 0.0);
  p.second.resize(n, 0.0);
  return p;
}

GroundMotion project(const GroundMotion& first, const GroundMotion& second, double degrees) {
  if (!std::isfinite(degrees)) throw InputError(fmt::format("azimuth {}: must be a finite angle in degrees", degrees));
  const HorizontalPair p = pair_components(first, second);
  const std::string c1 = first.info().component.empty() ? first.name() : first.info().component;
  const std::string c2 = second.info().component.empty() ? second.name() : second.info().component;
  auto along = [&](double at) {
    const auto [c, s] = direction_cosines(at);
    std::vector<double> a(p.first.size());
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = c * p.first[i] + s * p.second[i];
    const std::string where = fmt::format("{:g} deg from {} toward {}", at, c1, c2);
    GroundMotion g = GroundMotion::evenly_sampled(fmt::format("{} at {}", first.name(), where), p.dt, std::move(a));
    RecordInfo info = first.info();
    info.component = where;
    info.npts = p.first.size();
    info.stated_peak.reset();
    g.set_info(std::move(info));
    g.set_description(first.description());
    return g;
  };
  GroundMotion g = along(degrees).with_other_horizontal(along(degrees + 90));
  return first.vertical() ? g.with_vertical(*first.vertical()) : g;
}

}  // namespace rocking

namespace rocking {

GroundTravel::State GroundTravel::at(double t) {
  const GroundMotion& g = *g_;
  if (!g.samples_) {
    const double A = g.amplitude_ * g.scale_, T = g.period_;
    if (t <= 0) return {};
    if (g.shape_ == PulseShape::one_sine) {
      const double w = 2 * std::numbers::pi / T, tt = std::min(t, T);
      const double v = A / w * (1 - std::cos(w * tt)), d_end = A / w * (tt - std::sin(w * tt) / w);
      return {t <= T ? v : 0.0, d_end};  // at rest after the pulse: v(T) = 0
    }
    const double b2 = std::pow(std::numbers::pi / T, 2), tau0 = -1.5 * T, tau = t - 1.5 * T;
    const double e0 = std::exp(-b2 * tau0 * tau0), e = std::exp(-b2 * tau * tau);
    return {A * (tau * e - tau0 * e0), A * ((e0 - e) / (2 * b2) - tau0 * e0 * t)};
  }
  const GroundMotion::Samples& sm = *g.samples_;
  const std::size_t n = sm.values.size();
  const double k = g.scale_;
  if (next_ > 0 && t < g.time_of(next_ - 1)) *this = GroundTravel(g);  // earlier than the walk: again from rest
  if (next_ == 0) {
    if (t < g.time_of(0)) return {};
    next_ = 1;
  }
  // Sample next_ - 1 is at or before t: walk on over the samples not after t.
  while (next_ < n && g.time_of(next_) <= t) {
    const double h = g.time_of(next_) - g.time_of(next_ - 1), a0 = k * sm.values[next_ - 1];
    const double s = (k * sm.values[next_] - a0) / h;
    d_ = d_ + v_ * h + a0 * h * h / 2 + s * h * h * h / 6;
    v_ = v_ + a0 * h + s * h * h / 2;
    ++next_;
  }
  const double tau = t - g.time_of(next_ - 1);
  if (next_ == n) return {v_, d_ + v_ * tau};  // at rest after the record's end: a_g = 0
  const double a0 = k * sm.values[next_ - 1], s = (k * sm.values[next_] - a0) / (g.time_of(next_) - g.time_of(next_ - 1));
  return {v_ + a0 * tau + s * tau * tau / 2, d_ + v_ * tau + a0 * tau * tau / 2 + s * tau * tau * tau / 6};
}

}  // namespace rocking

namespace rocking {

// A component's orientation from its name (case and blanks aside).
Orientation component_orientation(std::string_view name) {
  std::string n;
  for (char c : name)
    if (!std::isspace(static_cast<unsigned char>(c))) n += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (std::string_view v : {"up", "upward", "down", "dwn", "dn", "ud", "u-d", "u/d", "v", "ver", "vert", "vertical", "z"})
    if (n == v) return Orientation::vertical;
  for (std::string_view h : {"n", "s", "e", "w", "ns", "n-s", "sn", "ew", "e-w", "we", "l", "t", "long", "tran",
                             "trans", "longitudinal", "transverse", "h1", "h2", "north", "south", "east", "west"})
    if (n == h) return Orientation::horizontal;
  auto digits = [](std::string_view s) {
    return !s.empty() && std::ranges::all_of(s, [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
  };
  if (n.size() <= 3 && digits(n)) return Orientation::horizontal;  // an azimuth: 000, 090, 360
  // A bearing: N28W, S01E, N89.5W
  if (n.size() >= 3 && (n.front() == 'n' || n.front() == 's') && (n.back() == 'e' || n.back() == 'w')) {
    const std::string_view angle = std::string_view(n).substr(1, n.size() - 2);
    if (std::ranges::all_of(angle, [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || c == '.'; }) &&
        digits(angle.substr(0, 1)))
      return Orientation::horizontal;
  }
  // A SEED channel code (band, instrument, orientation): HNZ, BNZ, HN1, HNE
  if (n.size() == 3 && std::isalpha(static_cast<unsigned char>(n[0])) && std::string_view("nhlg").find(n[1]) != std::string_view::npos) {
    if (n[2] == 'z') return Orientation::vertical;
    if (std::string_view("ne12").find(n[2]) != std::string_view::npos) return Orientation::horizontal;
  }
  return Orientation::unknown;
}

}  // namespace rocking
