module;
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_multimin.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_sf_erf.h>
#include <memory>
#include <algorithm>
#include <array>
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
// libm's erfc where it does not underflow (z > -30: erfc > 1e-200), GSL's
// log_erfc in the far tail.
double log_phi_cdf(double z) {
  return z > -30 ? std::log(0.5 * std::erfc(-z / std::numbers::sqrt2))
                 : gsl_sf_log_erfc(-z / std::numbers::sqrt2) - std::numbers::ln2;
}
double log_phi_upper(double z) { return log_phi_cdf(-z); }

// The minimum of f(ln median, ln beta) from a start, by GSL's simplex; false
// when it did not converge.
bool minimise(const std::function<double(double, double)>& f, double& x0, double& x1, double first_step) {
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
  gsl_vector_set_all(step, first_step);
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

// A negative log-likelihood at (mu, s) = (ln median, ln beta) with its
// gradient and Hessian there (g: d/dmu, d/ds; h: mu mu, mu s, s s).
struct Nll {
  double value = 0;
  std::array<double, 2> g{};
  std::array<double, 3> h{};
};
using NllFunction = std::function<Nll(double mu, double s)>;

// Adds f(z) with z = (x - mu) / beta, beta = e^s, given f, f' and f'' in z:
// dz/dmu = -1/beta, dz/ds = -z, d2z/dmu ds = 1/beta, d2z/dmu2 = 0, d2z/ds2 = z.
void add_term(Nll& n, double z, double inv_beta, double f, double f1, double f2) {
  const double zm = -inv_beta, zs = -z;
  n.value += f;
  n.g[0] += f1 * zm;
  n.g[1] += f1 * zs;
  n.h[0] += f2 * zm * zm;
  n.h[1] += f2 * zm * zs + f1 * inv_beta;
  n.h[2] += f2 * zs * zs + f1 * z;
}

// The inverse Mills ratio lambda(z) = phi(z) / Phi(z): from libm's erfc
// where Phi(z) does not underflow (z > -30), else from the asymptotic series
// Phi(-u) = phi(u) / u (1 - 1/u^2 + 3/u^4 - 15/u^6 + 105/u^8 ...), whose
// next term is below 2e-12 there.
double mills(double z) {
  if (z > -30) return std::exp(-0.5 * z * z) / (std::sqrt(2 * std::numbers::pi) * 0.5 * std::erfc(-z / std::numbers::sqrt2));
  const double u = -z, v = 1 / (u * u);
  return u / (1 - v * (1 - 3 * v * (1 - 5 * v * (1 - 7 * v))));
}

// -w ln Phi(z) and -w ln Phi(-z) with their derivatives in z:
// d ln Phi(z)/dz = lambda(z), d2 ln Phi(z)/dz2 = -lambda(z) (z + lambda(z)).
void add_below(Nll& n, double w, double z, double inv_beta) {  // -w ln Phi(z)
  const double lambda = mills(z);
  add_term(n, z, inv_beta, -w * log_phi_cdf(z), -w * lambda, w * lambda * (z + lambda));
}
void add_above(Nll& n, double w, double z, double inv_beta) {  // -w ln Phi(-z)
  const double lambda = mills(-z);
  add_term(n, z, inv_beta, -w * log_phi_upper(z), w * lambda, w * lambda * (lambda - z));
}

// The minimum of a smooth negative log-likelihood from (mu, s), by Newton's
// method on its exact gradient and Hessian (Levenberg-damped where the
// Hessian is not positive definite, steps halved until the value does not
// rise beyond round-off); converged when a step is below 1e-10 in ln median
// and ln beta (quadratic convergence: the next would be at round-off). False
// when it does not converge within 50 iterations or stalls.
bool newton(const NllFunction& f, double& mu, double& s) {
  Nll at = f(mu, s);
  if (!std::isfinite(at.value)) return false;
  double damping = 0;
  for (int i = 0; i < 50; ++i) {
    double step_mu = 0, step_s = 0;
    for (int tries = 0;; ++tries) {
      const double a = at.h[0] + damping, b = at.h[1], c = at.h[2] + damping, det = a * c - b * b;
      if (a > 0 && det > 0) {
        step_mu = -(c * at.g[0] - b * at.g[1]) / det;
        step_s = -(a * at.g[1] - b * at.g[0]) / det;
        break;
      }
      if (tries == 60) return false;
      damping = std::max(4 * damping, 1e-6 * (std::abs(at.h[0]) + std::abs(at.h[2]) + 1));
    }
    const double size = std::max(std::abs(step_mu), std::abs(step_s));
    if (size <= 1e-10) return true;
    const double slack = 1e-13 * (1 + std::abs(at.value));
    double t = 1;
    Nll next;
    for (int halvings = 0;; ++halvings) {
      next = f(mu + t * step_mu, s + t * step_s);
      if (std::isfinite(next.value) && next.value <= at.value + slack) break;
      if (halvings == 30) return size <= 1e-7;  // stalled: converged only if already close
      t *= 0.5;
    }
    mu += t * step_mu;
    s += t * step_s;
    at = next;
    damping *= 0.25;
  }
  return false;
}

// A maximum-likelihood fit: minimise the negative log-likelihood in (ln
// median, ln beta) by Newton's method (GSL's simplex where that fails), then
// standard errors of ln median and beta from its exact Hessian.
void fit_by_likelihood(LognormalFit& fit, const NllFunction& nll, double log_median, double beta,
                       const LognormalFit* near) {
  const bool warm = near && near->fitted;  // from a fit of similar data (a resample's)
  const double start0 = warm ? std::log(near->median) : log_median, start1 = std::log(warm ? near->beta : beta);
  double x0 = start0, x1 = start1;
  bool converged = newton(nll, x0, x1) && std::exp(x1) >= 1e-3;
  if (!converged) {  // the simplex needs no derivatives, and tells where beta runs to 0
    x0 = start0;
    x1 = start1;
    converged = minimise([&](double a, double b) { return nll(a, b).value; }, x0, x1, warm ? 0.05 : 0.2);
  }
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
  // The Hessian in (ln median, beta): d/dbeta = (1/beta) d/ds, so
  // H_mu,beta = H_mu,s / beta and H_beta,beta = (H_ss - g_s) / beta^2.
  const Nll at = nll(x0, x1);
  const double f00 = at.h[0], f01 = at.h[1] / b, f11 = (at.h[2] - at.g[1]) / (b * b);
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

LognormalFit fit_capacities(const std::vector<Capacity>& capacities, const LognormalFit* near) {
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
  std::vector<double> log_im;
  for (const Capacity& c : capacities) log_im.push_back(std::log(c.im));
  // Each reached capacity's density of ln C, less constants: 0.5 z^2 + ln beta;
  // each censored one's survival: -ln Phi(-z).
  auto nll = [&](double log_median, double log_b) {
    Nll n;
    const double inv_b = std::exp(-log_b);
    for (std::size_t i = 0; i < capacities.size(); ++i) {
      const double z = (log_im[i] - log_median) * inv_b;
      if (capacities[i].reached) {
        add_term(n, z, inv_b, 0.5 * z * z, z, 1.0);
        n.value += log_b;
        n.g[1] += 1;
      } else {
        add_above(n, 1.0, z, inv_b);
      }
    }
    return n;
  };
  fit_by_likelihood(fit, nll, mean, beta > 0 ? beta : 0.3, near);
  if (fit.fitted)
    fit.note = fmt::format("{} of {} records did not reach the limit: censored at the highest IM they were run to",
                           censored, fit.records);
  return fit;
}

LognormalFit fit_stripes(const std::vector<Stripe>& stripes, const LognormalFit* near) {
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
  std::vector<double> log_im;
  for (const Stripe& s : stripes) log_im.push_back(std::log(s.im));
  auto nll = [&](double log_median, double log_b) {
    Nll n;
    const double inv_b = std::exp(-log_b);
    for (std::size_t i = 0; i < stripes.size(); ++i) {
      const Stripe& s = stripes[i];
      if (s.runs == 0) continue;
      const double z = (log_im[i] - log_median) * inv_b;
      if (s.reached > 0) add_below(n, static_cast<double>(s.reached), z, inv_b);
      if (s.runs > s.reached) add_above(n, static_cast<double>(s.runs - s.reached), z, inv_b);
    }
    return n;
  };
  fit_by_likelihood(fit, nll, std::log(start), 0.4, near);
  return fit;
}

double total_beta(double beta, double modelling) {
  if (!(modelling >= 0) || !std::isfinite(modelling))
    throw InputError(fmt::format("--beta-modelling {}: must be a finite number >= 0", modelling));
  return std::hypot(beta, modelling);
}

void check_bootstrap_options(const BootstrapOptions& o) {
  if (o.draws > 1000000) throw InputError(fmt::format("--bootstrap {}: at most 1000000 resamples", o.draws));
  if (!(o.level > 0 && o.level < 1)) throw InputError(fmt::format("bootstrap level {}: must lie in (0, 1)", o.level));
}

namespace {

// The central interval at `level` of finite values.
std::array<double, 2> central(const std::vector<double>& values, double level) {
  return {fractile(values, (1 - level) / 2), fractile(values, (1 + level) / 2)};
}

// The bias-corrected and accelerated (BCa) interval at `level` (Efron &
// Tibshirani 1993, 14.3) of an estimate `full` from its values over the
// resamples and over the leave-one-out samples (the jackknife, which gives
// the acceleration; none: no acceleration).
std::array<double, 2> bca(const std::vector<double>& values, double full, const std::vector<double>& jackknife,
                          double level) {
  const double b = static_cast<double>(values.size());
  double below = 0;
  for (double v : values) below += v < full ? 1 : v == full ? 0.5 : 0;
  const double z0 = gsl_cdf_ugaussian_Pinv(std::clamp(below / b, 0.5 / b, 1 - 0.5 / b));
  double a = 0;
  if (jackknife.size() >= 2) {
    double mean = 0;
    for (double v : jackknife) mean += v / static_cast<double>(jackknife.size());
    double s2 = 0, s3 = 0;
    for (double v : jackknife) {
      s2 += (mean - v) * (mean - v);
      s3 += (mean - v) * (mean - v) * (mean - v);
    }
    if (s2 > 0) a = s3 / (6 * std::pow(s2, 1.5));
  }
  auto adjusted = [&](double alpha) {
    const double z = z0 + gsl_cdf_ugaussian_Pinv(alpha);
    return std::clamp(gsl_cdf_ugaussian_P(z0 + z / (1 - a * z)), 0.0, 1.0);
  };
  return {fractile(values, adjusted((1 - level) / 2)), fractile(values, adjusted((1 + level) / 2))};
}

}  // namespace

FitBootstrap bootstrap_fit(std::size_t n, const std::function<LognormalFit(const std::vector<std::size_t>&)>& fit,
                           const BootstrapOptions& o) {
  check_bootstrap_options(o);
  FitBootstrap out;
  out.level = o.level;
  out.seed = o.seed;
  if (n == 0 || o.draws == 0) return out;
  std::vector<std::size_t> sample(n);
  for (std::size_t i = 0; i < n; ++i) sample[i] = i;
  const LognormalFit whole = fit(sample);
  if (!whole.fitted) return out;
  // The jackknife: every sample that leaves one record out.
  std::vector<double> jack_median, jack_beta;
  for (std::size_t left = 0; left < n && n >= 3; ++left) {
    std::vector<std::size_t> rest;
    for (std::size_t i = 0; i < n; ++i)
      if (i != left) rest.push_back(i);
    const LognormalFit f = fit(rest);
    if (!f.fitted) {
      jack_median.clear();
      jack_beta.clear();
      break;
    }
    jack_median.push_back(std::log(f.median));
    jack_beta.push_back(f.beta);
  }
  const std::unique_ptr<gsl_rng, decltype(&gsl_rng_free)> rng(gsl_rng_alloc(gsl_rng_mt19937), gsl_rng_free);
  gsl_rng_set(rng.get(), o.seed);
  std::vector<double> medians, betas;
  for (std::size_t d = 0; d < o.draws; ++d) {
    for (std::size_t& i : sample) i = gsl_rng_uniform_int(rng.get(), n);
    ++out.draws;
    const LognormalFit f = fit(sample);
    if (!f.fitted) continue;
    out.fits.push_back({f.median, f.beta});
    medians.push_back(std::log(f.median));
    betas.push_back(f.beta);
  }
  out.fitted = out.fits.size();
  if (out.computed()) {
    const auto m = bca(medians, std::log(whole.median), jack_median, o.level);
    out.median = {std::exp(m[0]), std::exp(m[1])};
    out.beta = bca(betas, whole.beta, jack_beta, o.level);
  }
  return out;
}

std::array<double, 2> cdf_band(const FitBootstrap& b, double im, double beta_modelling) {
  if (!b.computed()) return {FitBootstrap::none, FitBootstrap::none};
  std::vector<double> p;
  p.reserve(b.fits.size());
  for (const auto& [median, beta] : b.fits) p.push_back(lognormal_cdf(im, median, total_beta(beta, beta_modelling)));
  return central(p, b.level);
}

}  // namespace rocking
