module;
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
#include <fmt/format.h>
#include <gsl/gsl_blas.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multifit_nlinear.h>
#include <gsl/gsl_vector.h>
module rocking.fitting;
import rocking.errors;

namespace rocking {

namespace {

bool has_role(const LawInfo& info, ParameterRole role) {
  return std::any_of(info.parameters.begin(), info.parameters.end(), [&](const LawParameter& p) { return p.role == role; });
}

// A law depends on time when a parameter of it is a rate's.
bool rate_dependent(const LawInfo& info) {
  return has_role(info, ParameterRole::rate_coefficient) || has_role(info, ParameterRole::reference_rate);
}

const LawInfo& law_info(const std::string& name) {
  static const std::vector<LawInfo> laws = device_laws();
  for (const LawInfo& l : laws)
    if (l.name == name) return l;
  std::string names;
  for (const LawInfo& l : laws) names += (names.empty() ? "" : ", ") + l.name;
  throw InputError(fmt::format("law '{}': unknown (the laws: {})", name, names));
}

DeviceLaw law_from(const LawInfo& info, const std::vector<double>& values) {
  return make_law(info.name, [&](std::string_view key) -> std::optional<double> {
    for (std::size_t i = 0; i < info.parameters.size(); ++i)
      if (info.parameters[i].key == key) return values[i];
    return std::nullopt;
  });
}

// The elongation rate at each sample: central differences over the times
// (unit steps without them), one-sided at the ends.
std::vector<double> rates(const CyclicTest& test) {
  const std::size_t n = test.e.size();
  auto time = [&](std::size_t i) { return test.t.empty() ? static_cast<double>(i) : test.t[i]; };
  std::vector<double> v(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 < n ? i + 1 : i;
    if (b > a) v[i] = (test.e[b] - test.e[a]) / (time(b) - time(a));
  }
  return v;
}

double range_of(const std::vector<double>& x) {
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  return *hi - *lo;
}

double peak_of(const std::vector<double>& x) {
  double p = 0;
  for (double v : x) p = std::max(p, std::abs(v));
  return p;
}

// Least-squares slope of F on e over samples [a, b).
double slope(const CyclicTest& test, std::size_t a, std::size_t b) {
  double se = 0, sf = 0;
  const double n = static_cast<double>(b - a);
  for (std::size_t i = a; i < b; ++i) {
    se += test.e[i];
    sf += test.F[i];
  }
  const double me = se / n, mf = sf / n;
  double see = 0, sef = 0;
  for (std::size_t i = a; i < b; ++i) {
    see += (test.e[i] - me) * (test.e[i] - me);
    sef += (test.e[i] - me) * (test.F[i] - mf);
  }
  return see > 0 ? sef / see : 0.0;
}

// What the data say about a yielding law (see the top of fitting.cppm).
struct DataScales {
  double k0 = 0, k2 = 0, d_y = 0, force = 0, rate = 0;
  double onset = 0;  // |e| where |F| first exceeds 2 % of its peak
  double loop_area = 0;  // |closed integral of F de| / (peak F x elongation range)
};
DataScales data_scales(const CyclicTest& test) {
  const std::size_t n = test.e.size();
  DataScales s;
  s.force = peak_of(test.F);
  s.rate = peak_of(rates(test));
  for (std::size_t i = 0; i < n; ++i)
    if (std::abs(test.F[i]) > 0.02 * s.force) {
      s.onset = std::abs(test.e[i]);
      break;
    }
  double area = 0;
  for (std::size_t i = 1; i < n; ++i) area += 0.5 * (test.F[i] + test.F[i - 1]) * (test.e[i] - test.e[i - 1]);
  area += 0.5 * (test.F[0] + test.F[n - 1]) * (test.e[0] - test.e[n - 1]);  // closes the path
  s.loop_area = std::abs(area) / std::max(s.force * range_of(test.e), std::numeric_limits<double>::min());
  // Reversals split the history into branches; the widest branch that starts
  // at a reversal unloads elastically from yield to yield (2 d_y wide), else
  // the first branch loads from rest (d_y wide).
  std::vector<std::size_t> starts{0};
  int direction = 0;
  for (std::size_t i = 1; i < n; ++i) {
    const double de = test.e[i] - test.e[i - 1];
    const int d = de > 0 ? 1 : de < 0 ? -1 : 0;
    if (d == 0) continue;
    if (direction != 0 && d != direction) starts.push_back(i - 1);
    direction = d;
  }
  starts.push_back(n - 1);
  std::size_t a = 0, b = n - 1;
  double widest = -1;
  for (std::size_t k = 1; k + 1 < starts.size(); ++k) {
    const double w = std::abs(test.e[starts[k + 1]] - test.e[starts[k]]);
    if (w > widest) {
      widest = w;
      a = starts[k];
      b = starts[k + 1];
    }
  }
  const bool from_rest = widest < 0;
  if (from_rest) b = starts[1];
  const double span = test.e[b] - test.e[a];
  // First tenth and last third of the branch, by elongation.
  std::size_t first_end = a + 1, last_begin = b;
  for (std::size_t i = a; i <= b; ++i) {
    const double x = (test.e[i] - test.e[a]) / span;
    if (x <= 0.1) first_end = i + 1;
    if (x < 2.0 / 3.0) last_begin = i + 1;
  }
  first_end = std::max(first_end, std::min(a + 3, b + 1));
  last_begin = std::min(last_begin, b >= 2 ? b - 2 : 0);
  s.k0 = std::abs(slope(test, a, first_end));
  s.k2 = std::abs(slope(test, last_begin, b + 1));
  if (!(s.k0 > 0)) s.k0 = s.force / std::max(range_of(test.e), std::numeric_limits<double>::min());
  const double x_y = s.k0 > s.k2 ? (std::abs(test.F[b] - test.F[a]) - s.k2 * std::abs(span)) / (s.k0 - s.k2) : 0.0;
  s.d_y = x_y > 0 ? (from_rest ? x_y : 0.5 * x_y) : 0.1 * range_of(test.e);
  return s;
}

// The start of parameter p from the data, by its role (see the top of fitting.cppm).
double starting_value(const LawParameter& p, const DataScales& s, double exponent) {
  double v = p.default_value;
  switch (p.role) {
    case ParameterRole::stiffness: v = s.k0; break;
    case ParameterRole::yield_elongation: v = s.d_y; break;
    case ParameterRole::onset_elongation: v = s.onset; break;
    case ParameterRole::force: v = 0.5 * s.force; break;
    case ParameterRole::reference_rate: v = 0.05 * s.rate; break;
    case ParameterRole::rate_coefficient: v = s.force / std::pow(std::max(s.rate, 1e-300), exponent); break;
    case ParameterRole::hardening_ratio: v = std::clamp(s.k2 / s.k0, 0.01, 0.5); break;
    case ParameterRole::rate_exponent:
    case ParameterRole::shape: v = v == 0 ? 0.1 : v; break;
  }
  return std::max(v, p.minimum + (std::abs(v) > 0 ? 1e-3 * std::abs(v) : 1e-3));
}

// The law's force along the test at the given rates (see law_force_history),
// which a fit computes once for all its evaluations.
std::vector<double> force_history(const DeviceLaw& law, const CyclicTest& test, const std::vector<double>& v) {
  const std::size_t n = test.e.size();
  std::vector<double> F(n, 0.0);
  if (n == 0) return F;
  const bool stateful = law_states(law) > 0;
  const double substep = range_of(test.e) / 400;
  double z = 0;
  F[0] = law_force(law, test.e[0], v[0], z);
  for (std::size_t i = 1; i < n; ++i) {
    if (stateful) {
      const double de = test.e[i] - test.e[i - 1];
      const double dt = test.t.empty() ? 1.0 : test.t[i] - test.t[i - 1];
      const double e_dot = de / dt;
      const double steps = std::abs(de) / substep;  // at most 400, unless the range overflows
      const int m = steps > 1 && steps <= 400 ? static_cast<int>(std::ceil(steps)) : 1;
      const double h = dt / m;
      for (int j = 0; j < m; ++j) {
        const double e = test.e[i - 1] + e_dot * h * j;
        const double k1 = law_rate(law, e, e_dot, z);
        const double k2 = law_rate(law, e + 0.5 * e_dot * h, e_dot, z + 0.5 * h * k1);
        const double k3 = law_rate(law, e + 0.5 * e_dot * h, e_dot, z + 0.5 * h * k2);
        const double k4 = law_rate(law, e + e_dot * h, e_dot, z + h * k3);
        z += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
      }
    }
    F[i] = law_force(law, test.e[i], v[i], z);
  }
  return F;
}

// The searched variables q and the law's parameters p (see the top of fitting.cppm).
struct Search {
  const LawInfo* info = nullptr;
  const CyclicTest* test = nullptr;
  std::vector<double> rates;             // of the test, at each sample
  std::vector<double> values;            // every parameter, the fixed ones set
  std::vector<std::size_t> free;         // indices of the free parameters
  std::vector<double> scale;             // per free parameter
  std::vector<bool> unit_interval;       // per free parameter: in [0, 1] (its complement is fitted with it)
  std::vector<std::pair<std::size_t, std::size_t>> complements;  // parameter i = 1 - parameter j
  double force_scale = 1;
  bool exclusive(std::size_t k) const { return info->parameters[free[k]].minimum_exclusive; }
  double parameter(std::size_t k, double q) const {
    if (unit_interval[k]) return 0.5 * (1 - std::cos(q));
    const double min = info->parameters[free[k]].minimum;
    return exclusive(k) ? min + scale[k] * std::exp(q) : min + scale[k] * std::abs(q);
  }
  double derivative(std::size_t k, double q) const {  // dp/dq
    if (unit_interval[k]) return 0.5 * std::sin(q);
    return exclusive(k) ? scale[k] * std::exp(q) : scale[k];
  }
  double start(std::size_t k, double p) const {  // q of the starting value p
    if (unit_interval[k]) return std::acos(1 - 2 * std::clamp(p, 0.01, 0.99));
    return exclusive(k) ? 0.0 : 1.0;
  }
  std::vector<double> parameters(const gsl_vector* q) const {
    std::vector<double> v = values;
    for (std::size_t k = 0; k < free.size(); ++k) v[free[k]] = parameter(k, gsl_vector_get(q, k));
    for (const auto& [i, j] : complements) v[i] = 1 - v[j];
    return v;
  }
};

int residuals(const gsl_vector* q, void* data, gsl_vector* f) {
  const Search& s = *static_cast<const Search*>(data);
  try {
    const std::vector<double> F = force_history(law_from(*s.info, s.parameters(q)), *s.test, s.rates);
    for (std::size_t i = 0; i < F.size(); ++i) {
      const double r = (F[i] - s.test->F[i]) / s.force_scale;
      if (!std::isfinite(r)) return GSL_EDOM;
      gsl_vector_set(f, i, r);
    }
  } catch (const InputError&) {
    return GSL_EDOM;
  }
  return GSL_SUCCESS;
}

}  // namespace

std::vector<double> law_force_history(const DeviceLaw& law, const CyclicTest& test) {
  return force_history(law, test, rates(test));
}

double Fit::value(const std::string& key) const {
  for (const FittedParameter& p : parameters)
    if (p.key == key) return p.value;
  throw InputError(fmt::format("the {} law has no parameter '{}'", law, key));
}

// The parameters --fix holds, checked against the law's (their values set in
// s.values); which are held.
std::vector<bool> hold_parameters(const LawInfo& info, const FitRequest& request, Search& s) {
  std::vector<bool> held(info.parameters.size(), false);
  for (const auto& [key, value] : request.fixed) {
    auto it = std::find_if(info.parameters.begin(), info.parameters.end(),
                           [&](const LawParameter& p) { return p.key == key; });
    if (it == info.parameters.end()) {
      std::string keys;
      for (const LawParameter& p : info.parameters) keys += (keys.empty() ? "" : ", ") + p.key;
      throw InputError(fmt::format("--fix {}: the {} law has no such parameter (its parameters: {})", key, info.name, keys));
    }
    if (!within(*it, value))
      throw InputError(fmt::format("--fix {}={:g}: must be {}", key, value, bounds_text(*it)));
    const std::size_t i = static_cast<std::size_t>(it - info.parameters.begin());
    s.values[i] = value;
    held[i] = true;
  }
  return held;
}

// A parameter fitted as one minus another (Bouc-Wen's alpha + beta = 1)
// follows it unless the user holds it; then it is the other that follows.
// Sets s.complements and s.free; returns, per parameter, the one it follows
// (-1: none).
std::vector<int> link_parameters(const LawInfo& info, const std::vector<bool>& held, Search& s) {
  auto index_of = [&](const std::string& key) {
    for (std::size_t j = 0; j < info.parameters.size(); ++j)
      if (info.parameters[j].key == key) return j;
    throw InputError(fmt::format("law {}: no parameter {}", info.name, key));
  };
  std::vector<int> derived(info.parameters.size(), -1);
  for (std::size_t i = 0; i < info.parameters.size(); ++i) {
    if (info.parameters[i].fitted_as_one_minus.empty()) continue;
    const std::size_t j = index_of(info.parameters[i].fitted_as_one_minus);
    if (held[i] && held[j]) continue;
    const std::size_t follower = held[i] ? j : i, leader = held[i] ? i : j;
    derived[follower] = static_cast<int>(leader);
    s.complements.emplace_back(follower, leader);
    if (held[leader]) s.values[follower] = 1 - s.values[leader];
  }
  for (std::size_t i = 0; i < held.size(); ++i)
    if (!held[i] && derived[i] < 0) {
      s.free.push_back(i);
      s.unit_interval.push_back(std::find_if(s.complements.begin(), s.complements.end(), [&](const auto& c) {
                                  return c.second == i;
                                }) != s.complements.end());
    }
  if (s.free.empty()) throw InputError(fmt::format("--fix holds every parameter of the {} law: nothing to fit", info.name));
  return derived;
}

// A test the law can be fitted to, or an InputError saying why not: enough
// finite samples, an elongation that moves, time increasing, a time column
// for a rate-dependent law, a force, and loops for a yielding law.
DataScales check_test(const CyclicTest& test, const LawInfo& info, std::size_t free_parameters) {
  const std::string& src = test.source;
  const std::size_t n = test.e.size();
  const std::size_t needed = std::max<std::size_t>(10, 3 * free_parameters);
  if (n < needed)
    throw InputError(fmt::format("{}: {} samples: too few to fit {} parameters (at least {})", src, n, free_parameters, needed));
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(test.e[i]) || !std::isfinite(test.F[i]) || (!test.t.empty() && !std::isfinite(test.t[i])))
      throw InputError(fmt::format("{}: sample {} is not a finite number", src, i + 1));
  if (!(range_of(test.e) > 1e-12 * std::max(1.0, peak_of(test.e))))
    throw InputError(fmt::format("{}: the elongation never moves: nothing to fit", src));
  if (!test.t.empty())
    for (std::size_t i = 1; i < n; ++i)
      if (!(test.t[i] > test.t[i - 1]))
        throw InputError(fmt::format("{}: time does not increase at sample {} ({} s after {} s)", src, i + 1, test.t[i],
                                     test.t[i - 1]));
  if (test.t.empty() && rate_dependent(info))
    throw InputError(fmt::format("{}: the {} law depends on the elongation rate: the test needs a time column", src,
                                 info.name));
  const DataScales scales = data_scales(test);
  if (!(scales.force > 0)) throw InputError(fmt::format("{}: the force is zero throughout: nothing to fit", src));
  if (has_role(info, ParameterRole::yield_elongation) && scales.loop_area < 0.01)
    throw InputError(fmt::format("{}: the test never yields (its loops enclose {:.2g} % of peak force x elongation "
                                 "range): fit --law elastic, or use a test that goes past yield",
                                 src, 100 * scales.loop_area));
  return scales;
}

// What the least squares found: every parameter's value and standard error.
struct Solution {
  std::vector<double> values, errors;
  int iterations = 0;
  double rcond = 0;
};

// GSL's trust-region Levenberg-Marquardt from `start` (the free parameters'
// starting values) on the residuals of s; RunError if it does not converge.
Solution least_squares(Search& s, const std::vector<double>& start) {
  const LawInfo& info = *s.info;
  const std::size_t n = s.test->e.size(), p = s.free.size();
  gsl_multifit_nlinear_fdf fdf{};
  fdf.f = residuals;
  fdf.df = nullptr;
  fdf.fvv = nullptr;
  fdf.n = n;
  fdf.p = p;
  fdf.params = &s;
  gsl_multifit_nlinear_parameters params = gsl_multifit_nlinear_default_parameters();
  params.trs = gsl_multifit_nlinear_trs_lm;
  params.scale = gsl_multifit_nlinear_scale_more;
  gsl_multifit_nlinear_workspace* w = gsl_multifit_nlinear_alloc(gsl_multifit_nlinear_trust, &params, n, p);
  gsl_vector* q = gsl_vector_alloc(p);
  gsl_matrix* covar = gsl_matrix_alloc(p, p);
  for (std::size_t k = 0; k < p; ++k) gsl_vector_set(q, k, s.start(k, start[k]));
  gsl_error_handler_t* previous = gsl_set_error_handler_off();
  int status = gsl_multifit_nlinear_init(q, &fdf, w);
  int why = 0;
  if (status == GSL_SUCCESS) status = gsl_multifit_nlinear_driver(500, 1e-12, 1e-12, 1e-14, nullptr, nullptr, &why, w);
  Solution out;
  out.iterations = static_cast<int>(gsl_multifit_nlinear_niter(w));
  const gsl_vector* best = gsl_multifit_nlinear_position(w);
  out.values = s.parameters(best);
  double ssr = 0;
  gsl_blas_ddot(gsl_multifit_nlinear_residual(w), gsl_multifit_nlinear_residual(w), &ssr);
  gsl_multifit_nlinear_covar(gsl_multifit_nlinear_jac(w), 0.0, covar);
  gsl_multifit_nlinear_rcond(&out.rcond, w);
  const double s2 = ssr / static_cast<double>(n > p ? n - p : 1);
  out.errors.assign(info.parameters.size(), 0.0);
  for (std::size_t k = 0; k < p; ++k)
    out.errors[s.free[k]] = std::abs(s.derivative(k, gsl_vector_get(best, k))) * std::sqrt(s2 * gsl_matrix_get(covar, k, k));
  for (const auto& [i, j] : s.complements) out.errors[i] = out.errors[j];
  gsl_matrix_free(covar);
  gsl_vector_free(q);
  gsl_multifit_nlinear_free(w);
  gsl_set_error_handler(previous);
  const bool finite = std::all_of(out.values.begin(), out.values.end(), [](double v) { return std::isfinite(v); });
  if ((status != GSL_SUCCESS && status != GSL_EMAXITER) || !finite)
    throw RunError(fmt::format("{}: the least-squares fit of the {} law did not converge ({})", s.test->source, info.name,
                               gsl_strerror(status)));
  return out;
}

Fit fit_law(const CyclicTest& test, const FitRequest& request) {
  const LawInfo& info = law_info(request.law);
  const std::string& src = test.source;
  const std::size_t n = test.e.size();
  if (test.F.size() != n || (!test.t.empty() && test.t.size() != n))
    throw InputError(fmt::format("{}: the columns differ in length", src));
  Search s;
  s.info = &info;
  s.test = &test;
  s.values.assign(info.parameters.size(), 0.0);
  const std::vector<bool> held = hold_parameters(info, request, s);
  const std::vector<int> derived = link_parameters(info, held, s);
  const DataScales scales = check_test(test, info, s.free.size());
  double exponent = 1;
  for (std::size_t i = 0; i < info.parameters.size(); ++i)
    if (info.parameters[i].role == ParameterRole::rate_exponent)
      exponent = held[i] ? s.values[i] : info.parameters[i].default_value;
  std::vector<double> start(s.free.size());
  for (std::size_t k = 0; k < s.free.size(); ++k) {
    const LawParameter& p = info.parameters[s.free[k]];
    start[k] = starting_value(p, scales, exponent);
    s.scale.push_back(start[k] - p.minimum);
  }
  s.force_scale = scales.force;
  s.rates = rates(test);
  const Solution found = least_squares(s, start);

  Fit fit;
  fit.law = info.name;
  fit.samples = n;
  fit.iterations = found.iterations;
  fit.rcond = found.rcond;
  fit.fitted = law_from(info, found.values);
  fit.force = law_force_history(fit.fitted, test);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = fit.force[i] - test.F[i];
    fit.rms_error += r * r;
    fit.peak_error = std::max(fit.peak_error, std::abs(r));
  }
  fit.rms_error = std::sqrt(fit.rms_error / static_cast<double>(n));
  fit.peak_force = scales.force;
  for (std::size_t i = 0; i < info.parameters.size(); ++i) {
    const LawParameter& lp = info.parameters[i];
    fit.parameters.push_back({lp.key, lp.unit, lp.doc, lp.role, found.values[i], found.errors[i], held[i],
                              derived[i] >= 0 ? info.parameters[static_cast<std::size_t>(derived[i])].key : ""});
  }
  const double e_range = range_of(test.e);
  if (has_role(info, ParameterRole::yield_elongation))
    for (const FittedParameter& fp : fit.parameters)
      if (fp.role == ParameterRole::yield_elongation && !fp.fixed && fp.value > e_range)
        throw InputError(fmt::format("{}: the test never yields (the fitted {} = {:.4g} m exceeds the elongation range "
                                     "{:.4g} m): fit --law elastic, or use a test that goes past yield",
                                     src, fp.key, fp.value, e_range));
  return fit;
}

std::vector<std::pair<std::string, double>> scaled_parameters(const Fit& fit, const PlateScaling& scaling) {
  std::vector<std::pair<std::string, double>> out;
  for (const FittedParameter& p : fit.parameters) out.emplace_back(p.key, p.value);
  if (!scaling.any()) return out;
  auto find = [&](const char* key) {
    auto it = std::find_if(out.begin(), out.end(), [&](const auto& kv) { return kv.first == key; });
    if (it == out.end())
      throw InputError(fmt::format("plate scaling needs a law with k and d_y (bouc-wen), not {}", fit.law));
    return it;
  };
  auto k = find("k");
  auto d_y = find("d_y");
  if (!(scaling.thickness_ratio > 0 && scaling.thickness_ratio <= 100))
    throw InputError(fmt::format("--thickness {:g}: must be a ratio in (0, 100]", scaling.thickness_ratio));
  const double tau = scaling.thickness_ratio;
  k->second *= tau * tau * tau;
  d_y->second /= tau;
  if (scaling.stiffness) k->second = *scaling.stiffness;
  if (scaling.yield_elongation) d_y->second = *scaling.yield_elongation;
  // The scaled values go into a scene: they must be values the law takes.
  const std::vector<LawInfo> laws = device_laws();
  const auto law = std::find_if(laws.begin(), laws.end(), [&](const LawInfo& l) { return l.name == fit.law; });
  for (const auto& [key, value] : out)
    for (const LawParameter& p : law->parameters)
      if (p.key == key && !within(p, value))
        throw InputError(fmt::format("plate scaling gives {} = {:g}: it must be {} (check --thickness, --stiffness "
                                     "and --yield)",
                                     key, value, bounds_text(p)));
  return out;
}

}  // namespace rocking
