module;
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multimin.h>
#include <gsl/gsl_sf_erf.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <fmt/format.h>
module rocking.fragility;
import rocking.errors;

namespace rocking {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// ln Phi(z) and ln(1 - Phi(z)), accurate far in the tails.
double log_phi_cdf(double z) { return gsl_sf_log_erfc(-z / std::numbers::sqrt2) - std::numbers::ln2; }
double log_phi_upper(double z) { return log_phi_cdf(-z); }

// The minimum of f(ln median, ln beta) from a start, by GSL's simplex; false
// when it did not converge.
bool minimise(const std::function<double(double, double)>& f, double& x0, double& x1) {
  struct Data {
    const std::function<double(double, double)>* f;
  } data{&f};
  gsl_multimin_function fn;
  fn.n = 2;
  fn.params = &data;
  fn.f = [](const gsl_vector* x, void* p) {
    const double v = (*static_cast<Data*>(p)->f)(gsl_vector_get(x, 0), gsl_vector_get(x, 1));
    return std::isfinite(v) ? v : GSL_POSINF;
  };
  gsl_vector* x = gsl_vector_alloc(2);
  gsl_vector* step = gsl_vector_alloc(2);
  gsl_vector_set(x, 0, x0);
  gsl_vector_set(x, 1, x1);
  gsl_vector_set_all(step, 0.2);
  gsl_multimin_fminimizer* s = gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, 2);
  gsl_multimin_fminimizer_set(s, &fn, x, step);
  int status = GSL_CONTINUE;
  for (int i = 0; i < 5000 && status == GSL_CONTINUE; ++i) {
    const double size = gsl_multimin_fminimizer_size(s);
    // No progress is possible once the simplex is at rounding level.
    if (gsl_multimin_fminimizer_iterate(s) != GSL_SUCCESS) {
      status = size < 1e-5 ? GSL_SUCCESS : GSL_FAILURE;
      break;
    }
    status = gsl_multimin_test_size(gsl_multimin_fminimizer_size(s), 1e-6);
  }
  x0 = gsl_vector_get(s->x, 0);
  x1 = gsl_vector_get(s->x, 1);
  gsl_multimin_fminimizer_free(s);
  gsl_vector_free(step);
  gsl_vector_free(x);
  return status == GSL_SUCCESS;
}

// A maximum-likelihood fit: minimise the negative log-likelihood nll(ln
// median, beta), then standard errors from its Hessian.
void fit_by_likelihood(LognormalFit& fit, const std::function<double(double, double)>& nll, double log_median,
                       double beta) {
  double x0 = log_median, x1 = std::log(beta);
  const bool converged = minimise([&](double a, double b) { return nll(a, std::exp(b)); }, x0, x1);
  const double b = std::exp(x1);
  if (b < 1e-3) {
    fit.note = "the data separate perfectly: beta -> 0, no dispersion can be estimated";
    return;
  }
  if (!converged || !std::isfinite(x0)) {
    fit.note = "the likelihood has no maximum the simplex could find";
    return;
  }
  fit.fitted = true;
  fit.median = std::exp(x0);
  fit.beta = b;
  // Hessian in (ln median, beta) by central differences.
  const double h0 = 1e-4, h1 = 1e-4 * b;
  const double f = nll(x0, b);
  const double f00 = (nll(x0 + h0, b) - 2 * f + nll(x0 - h0, b)) / (h0 * h0);
  const double f11 = (nll(x0, b + h1) - 2 * f + nll(x0, b - h1)) / (h1 * h1);
  const double f01 = (nll(x0 + h0, b + h1) - nll(x0 + h0, b - h1) - nll(x0 - h0, b + h1) + nll(x0 - h0, b - h1)) /
                     (4 * h0 * h1);
  const double det = f00 * f11 - f01 * f01;
  if (det > 0 && f00 > 0) {
    fit.log_median_se = std::sqrt(f11 / det);
    fit.beta_se = std::sqrt(f00 / det);
  } else {
    fit.log_median_se = fit.beta_se = inf;
  }
}

}  // namespace

double fractile(std::vector<double> values, double p) {
  if (values.empty()) throw InputError("fractile of no values");
  if (!(p >= 0 && p <= 1)) throw InputError(fmt::format("fractile {}: must lie in [0, 1]", p));
  for (double v : values)
    if (std::isnan(v)) throw InputError("fractile of a NaN value");
  std::sort(values.begin(), values.end());
  const double h = p * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const double w = h - static_cast<double>(lo);
  if (w == 0 || lo + 1 >= values.size()) return values[lo];
  if (std::isinf(values[lo + 1])) return inf;
  return values[lo] + w * (values[lo + 1] - values[lo]);
}

double lognormal_cdf(double im, double median, double beta) {
  if (!(im > 0)) return 0;
  return gsl_cdf_ugaussian_P(std::log(im / median) / beta);
}

LognormalFit fit_capacities(const std::vector<Capacity>& capacities) {
  LognormalFit fit;
  fit.records = capacities.size();
  double sum = 0, sum2 = 0;
  for (const Capacity& c : capacities) {
    if (!(c.im > 0) || !std::isfinite(c.im))
      throw InputError(fmt::format("capacity {}: an IM must be positive and finite", c.im));
    if (!c.reached) continue;
    ++fit.reached;
    sum += std::log(c.im);
  }
  if (fit.reached < 2) {
    fit.method = "moments";
    fit.note = fmt::format("{} of {} records reached the limit: a fit needs at least two", fit.reached, fit.records);
    return fit;
  }
  const double n = static_cast<double>(fit.reached);
  const double mean = sum / n;
  for (const Capacity& c : capacities)
    if (c.reached) sum2 += (std::log(c.im) - mean) * (std::log(c.im) - mean);
  const double beta = std::sqrt(sum2 / (n - 1));
  if (fit.reached == fit.records) {
    fit.method = "moments";
    if (!(beta > 0)) {
      fit.note = "every capacity is the same: no dispersion can be estimated";
      return fit;
    }
    fit.fitted = true;
    fit.median = std::exp(mean);
    fit.beta = beta;
    fit.log_median_se = beta / std::sqrt(n);
    fit.beta_se = beta / std::sqrt(2 * (n - 1));
    return fit;
  }
  fit.method = "censored-mle";
  const std::size_t censored = fit.records - fit.reached;
  auto nll = [&](double log_median, double b) {
    if (!(b > 0)) return inf;
    double s = 0;
    for (const Capacity& c : capacities) {
      const double z = (std::log(c.im) - log_median) / b;
      s -= c.reached ? -0.5 * z * z - std::log(b) : log_phi_upper(z);
    }
    return s;
  };
  fit_by_likelihood(fit, nll, mean, beta > 0 ? beta : 0.3);
  if (fit.fitted)
    fit.note = fmt::format("{} of {} records did not reach the limit: censored at the highest IM they were run to",
                           censored, fit.records);
  return fit;
}

LognormalFit fit_stripes(const std::vector<Stripe>& stripes) {
  LognormalFit fit;
  fit.method = "stripes-mle";
  for (const Stripe& s : stripes) {
    if (!(s.im > 0) || !std::isfinite(s.im))
      throw InputError(fmt::format("stripe at IM {}: an IM must be positive and finite", s.im));
    if (s.reached > s.runs) throw InputError(fmt::format("stripe at IM {}: {} of {} runs", s.im, s.reached, s.runs));
    fit.records += s.runs;
    fit.reached += s.reached;
  }
  if (fit.reached == 0 || fit.reached == fit.records) {
    fit.note = fit.reached == 0 ? "no run reached the limit at any stripe" : "every run reached the limit at every stripe";
    return fit;
  }
  // Every stripe all or nothing, the nothings below the alls: the likelihood
  // grows without bound as beta -> 0.
  double highest_none = 0, lowest_all = inf;
  bool mixed = false;
  for (const Stripe& s : stripes) {
    if (s.runs == 0) continue;
    mixed = mixed || (s.reached > 0 && s.reached < s.runs);
    if (s.reached == 0) highest_none = std::max(highest_none, s.im);
    if (s.reached == s.runs) lowest_all = std::min(lowest_all, s.im);
  }
  if (!mixed && highest_none < lowest_all) {
    fit.note = fmt::format("the stripes separate perfectly (none reached the limit up to {:g}, all from {:g}): beta "
                           "-> 0, no dispersion can be estimated",
                           highest_none, lowest_all);
    return fit;
  }
  // Start at the IM where the fraction first reaches one half.
  double start = stripes.front().im;
  for (const Stripe& s : stripes)
    if (2 * s.reached >= s.runs && s.runs > 0) {
      start = s.im;
      break;
    }
  auto nll = [&](double log_median, double b) {
    if (!(b > 0)) return inf;
    double sum = 0;
    for (const Stripe& s : stripes) {
      if (s.runs == 0) continue;
      const double z = (std::log(s.im) - log_median) / b;
      if (s.reached > 0) sum -= static_cast<double>(s.reached) * log_phi_cdf(z);
      if (s.runs > s.reached) sum -= static_cast<double>(s.runs - s.reached) * log_phi_upper(z);
    }
    return sum;
  };
  fit_by_likelihood(fit, nll, std::log(start), 0.4);
  return fit;
}

}  // namespace rocking
