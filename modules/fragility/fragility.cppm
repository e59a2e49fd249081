// rocking.fragility: the statistics of incremental dynamic analysis over a
// suite of records (MODEL.md 13). Pure numbers: it knows neither records nor
// runs.
// - Fractile IDA curves (Vamvatsikos & Cornell 2002): at one IM level, the
//   p-fractile of the EDP over the records, a collapse counted as +inf. The
//   fractile is Hyndman & Fan's type 7 (GSL's gsl_stats_quantile_from_sorted_data:
//   position p (n - 1) in the sorted values, linear between neighbours); it is
//   +inf (collapse) when that position touches a collapse with a non-zero
//   weight.
// - Lognormal fragility P(IM_c <= im) = Phi(ln(im / median) / beta):
//   * from the capacity of each record (the lowest IM at which it reaches the
//     limit): ln(median) = mean ln IM_c, beta = sample standard deviation of
//     ln IM_c (n - 1), when every record reached it; when some did not, they
//     are right-censored at the highest IM they were run to and median and
//     beta maximise the censored likelihood;
//   * from stripes (multiple-stripe analysis, Baker 2015, Earthquake Spectra
//     31(1)): median and beta maximise the binomial likelihood of the counts
//     of runs that reached the limit at each IM.
//   Likelihoods are maximised over (ln median, ln beta) by Newton's method on
//   their exact gradient and Hessian (the probit terms through the inverse
//   Mills ratio phi / Phi), with GSL's Nelder-Mead simplex where Newton does
//   not converge; standard errors come from the inverse of the negative
//   log-likelihood's exact Hessian in (ln median, beta) at the optimum, or,
//   for the moment fit, from se(ln median) = beta / sqrt(n), se(beta) =
//   beta / sqrt(2 (n - 1)).
// - Their uncertainty by a bootstrap over records (Efron & Tibshirani 1993,
//   BCa intervals, 14.3): the records are resampled with replacement, each
//   resample is fitted as the records were, and the interval is the fractiles
//   of the fitted medians and betas that the bias correction and the
//   jackknife's acceleration select. The resamples are drawn by
//   GSL's MT19937 from a stated seed, so the intervals are the same on every
//   machine.
// - The total dispersion with modelling uncertainty, FEMA P-695 (2009) 7.3:
//   beta_total = sqrt(beta^2 + beta_modelling^2), the median unchanged.
module;
#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>
export module rocking.fragility;

export namespace rocking {

// The p-fractile (p in [0, 1]) of values, +inf standing for a collapse;
// +inf when the fractile falls on collapses. InputError for no values, a NaN,
// or p outside [0, 1].
double fractile(std::vector<double> values, double p);

struct LognormalFit {
  bool fitted = false;
  std::string method;        // "moments", "censored-mle", "stripes-mle"
  std::string note;          // why there is no fit, or what the fit assumed
  double median = 0, beta = 0;
  double log_median_se = 0;  // standard error of ln(median)
  double beta_se = 0;
  std::size_t records = 0;   // capacities: samples; stripes: runs in all
  std::size_t reached = 0;   // how many reached the limit
};

// P(capacity <= im) of the fit.
double lognormal_cdf(double im, double median, double beta);

// One record's capacity: the IM at which it first reached the limit, or (not
// reached) the highest IM it was run to without reaching it.
struct Capacity {
  double im = 0;
  bool reached = false;
};
// near: a fit of similar data (the whole sample's, for a resample) to start
// the likelihood's search from.
LognormalFit fit_capacities(const std::vector<Capacity>& capacities, const LognormalFit* near = nullptr);

// One stripe: `runs` records run at IM `im`, `reached` of them at the limit.
struct Stripe {
  double im = 0;
  std::size_t runs = 0, reached = 0;
};
LognormalFit fit_stripes(const std::vector<Stripe>& stripes, const LognormalFit* near = nullptr);

// sqrt(beta^2 + modelling^2) (FEMA P-695); InputError naming
// --beta-modelling unless modelling is finite and >= 0.
double total_beta(double beta, double modelling);

struct BootstrapOptions {
  std::size_t draws = 1000;
  unsigned long seed = 20020101;
  double level = 0.9;  // of the central intervals
};
// InputError naming the option unless draws is in [0, 1e6] (0: no bootstrap)
// and level in (0, 1).
void check_bootstrap_options(const BootstrapOptions& o);
struct FitBootstrap {
  std::size_t draws = 0;   // resamples drawn
  std::size_t fitted = 0;  // of which the fit gave numbers (others say why in their notes)
  double level = 0.9;
  unsigned long seed = 0;
  static constexpr double none = std::numeric_limits<double>::quiet_NaN();
  std::array<double, 2> median{none, none}, beta{none, none};  // low, high; NaN when fewer than two fitted
  std::vector<std::array<double, 2>> fits;                      // (median, beta) of each fitted resample
  bool computed() const { return fitted >= 2; }
};
// Draws o.draws resamples of the indices 0..n-1 with replacement and fits
// each with fit(sample).
FitBootstrap bootstrap_fit(std::size_t n, const std::function<LognormalFit(const std::vector<std::size_t>&)>& fit,
                           const BootstrapOptions& o);
// The central interval (at the bootstrap's level) of P(capacity <= im) over
// the resamples' fits, optionally with modelling dispersion added to each:
// the band drawn around a fragility curve. NaN when not computed.
std::array<double, 2> cdf_band(const FitBootstrap& b, double im, double beta_modelling = 0);

}  // namespace rocking
