// IDA statistics (MODEL.md 13): fractiles with collapses against answers
// worked by hand, and the three lognormal fits recovering known fragilities
// from samples drawn from them (fixed seeds; each estimate within three of
// its own standard errors, which a correct estimator misses with odds of
// about 1 in 370).
#include <doctest/doctest.h>
#include "close.hpp"
#include <gsl/gsl_cdf.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_statistics_double.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>
import rocking.fragility;
import rocking.errors;

using namespace rocking;

namespace {
constexpr double inf = std::numeric_limits<double>::infinity();
}

TEST_CASE("fractile IDA curves: collapses count as infinite EDP, worked by hand") {
  // Five records at one IM level, one collapsed: sorted 0.1 0.2 0.3 0.5 inf.
  const std::vector<double> level1{0.3, 0.1, inf, 0.5, 0.2};
  CHECK(fractile(level1, 0.5) == close_to(0.3, 1e-12));             // position 2
  CHECK(fractile(level1, 0.16) == close_to(0.1 + 0.64 * 0.1, 1e-12));  // position 0.64
  CHECK(fractile(level1, 0.84) == inf);                             // position 3.36: between 0.5 and a collapse
  CHECK(fractile(level1, 0.75) == close_to(0.5, 1e-12));            // position 3 exactly: the last finite value
  // At a higher level three collapse: the median falls on a collapse.
  const std::vector<double> level2{inf, 0.4, inf, 0.9, inf};
  CHECK(fractile(level2, 0.16) == close_to(0.4 + 0.64 * 0.5, 1e-12));
  CHECK(fractile(level2, 0.5) == inf);
  CHECK(fractile(level2, 0.84) == inf);
  // No collapses: the same numbers as GSL's quantile of sorted data.
  std::vector<double> finite{0.7, 0.05, 1.3, 0.2, 0.9, 0.4, 0.33};
  std::vector<double> sorted = finite;
  std::sort(sorted.begin(), sorted.end());
  for (double p : {0.0, 0.16, 0.5, 0.84, 1.0})
    CHECK(fractile(finite, p) == close_to(gsl_stats_quantile_from_sorted_data(sorted.data(), 1, sorted.size(), p), 1e-12));
  CHECK_THROWS_AS(fractile({}, 0.5), InputError);
  CHECK_THROWS_AS(fractile({1.0, std::nan("")}, 0.5), InputError);
  CHECK_THROWS_AS(fractile({1.0}, 1.5), InputError);
}

TEST_CASE("the moment fit recovers a lognormal's median and beta from 10,000 capacities") {
  const double median = 0.62, beta = 0.35;
  std::mt19937_64 rng(20261123);
  std::normal_distribution<double> z;
  std::vector<Capacity> caps;
  for (int i = 0; i < 10000; ++i) caps.push_back({median * std::exp(beta * z(rng)), true});
  const LognormalFit fit = fit_capacities(caps);
  REQUIRE(fit.fitted);
  CHECK(fit.method == "moments");
  CHECK(fit.reached == 10000);
  // se = beta_hat / sqrt(N): as uncertain as beta_hat, 1 / sqrt(2 N) = 0.7 %; three of those.
  CHECK(fit.log_median_se == close_to(beta / 100, 0.021));
  CHECK(std::abs(std::log(fit.median / median)) < 3 * fit.log_median_se);
  CHECK(std::abs(fit.beta - beta) < 3 * fit.beta_se);
}

TEST_CASE("capacities that never reached the limit are censored, and the fit still recovers the lognormal") {
  const double median = 1.1, beta = 0.5, cut = 1.6;  // about a fifth never reach it below the cut
  std::mt19937_64 rng(7);
  std::normal_distribution<double> z;
  std::vector<Capacity> caps;
  for (int i = 0; i < 4000; ++i) {
    const double c = median * std::exp(beta * z(rng));
    caps.push_back(c <= cut ? Capacity{c, true} : Capacity{cut, false});
  }
  const LognormalFit fit = fit_capacities(caps);
  REQUIRE(fit.fitted);
  CHECK(fit.method == "censored-mle");
  CHECK(fit.reached < fit.records);
  CHECK(std::abs(std::log(fit.median / median)) < 3 * fit.log_median_se);
  CHECK(std::abs(fit.beta - beta) < 3 * fit.beta_se);
  // Dropping the censored records instead biases both: the fit must differ.
  std::vector<Capacity> reached;
  for (const Capacity& c : caps)
    if (c.reached) reached.push_back(c);
  CHECK(fit_capacities(reached).median < 0.9 * fit.median);
}

TEST_CASE("the multiple-stripe MLE recovers a known fragility from simulated binomial stripes") {
  const double median = 0.5, beta = 0.4;
  std::mt19937_64 rng(42);
  std::vector<Stripe> stripes;
  for (double im = 0.1; im < 1.25; im += 0.1) {
    std::binomial_distribution<std::size_t> count(300, lognormal_cdf(im, median, beta));
    stripes.push_back({im, 300, count(rng)});
  }
  const LognormalFit fit = fit_stripes(stripes);
  REQUIRE(fit.fitted);
  CHECK(fit.method == "stripes-mle");
  CHECK(fit.log_median_se > 0);
  CHECK(fit.log_median_se < 0.05);
  CHECK(fit.beta_se < 0.05);
  CHECK(std::abs(std::log(fit.median / median)) < 3 * fit.log_median_se);
  CHECK(std::abs(fit.beta - beta) < 3 * fit.beta_se);
}

TEST_CASE("two stripes: the MLE passes through both fractions, with the Fisher information's standard errors") {
  // Two parameters and two stripes: the fit reproduces both fractions, so
  // z_i = Phi^-1(r_i / n_i) = (ln im_i - ln median) / beta, and there the
  // observed information equals the expected one, sum n phi(z)^2 / (p (1 - p))
  // a a' with a = dz/d(ln median, beta) = (-1 / beta, -z / beta).
  const std::vector<Stripe> stripes{{0.3, 40, 10}, {0.8, 50, 35}};
  double z[2], p[2];
  for (int i = 0; i < 2; ++i) {
    p[i] = static_cast<double>(stripes[i].reached) / static_cast<double>(stripes[i].runs);
    z[i] = gsl_cdf_ugaussian_Pinv(p[i]);
  }
  const double beta = std::log(0.8 / 0.3) / (z[1] - z[0]), log_median = std::log(0.3) - beta * z[0];
  double info[3] = {0, 0, 0};  // (mu mu, mu beta, beta beta)
  for (int i = 0; i < 2; ++i) {
    const double w = static_cast<double>(stripes[i].runs) * std::pow(gsl_ran_ugaussian_pdf(z[i]), 2) / (p[i] * (1 - p[i]));
    const double a0 = -1 / beta, a1 = -z[i] / beta;
    info[0] += w * a0 * a0;
    info[1] += w * a0 * a1;
    info[2] += w * a1 * a1;
  }
  const double det = info[0] * info[2] - info[1] * info[1];
  const LognormalFit fit = fit_stripes(stripes);
  REQUIRE(fit.fitted);
  CHECK(std::log(fit.median) == close_to(log_median, 1e-9));
  CHECK(fit.beta == close_to(beta, 1e-9));
  CHECK(fit.log_median_se == close_to(std::sqrt(info[2] / det), 1e-9));
  CHECK(fit.beta_se == close_to(std::sqrt(info[0] / det), 1e-9));
  // From a start far away (a resample's fit as the warm start), the same answer.
  LognormalFit far;
  far.fitted = true;
  far.median = 3.0;
  far.beta = 0.05;
  const LognormalFit again = fit_stripes(stripes, &far);
  REQUIRE(again.fitted);
  CHECK(again.median == close_to(fit.median, 1e-9));
  CHECK(again.beta == close_to(fit.beta, 1e-9));
}

TEST_CASE("fits that the data cannot support say why instead of returning numbers") {
  CHECK_FALSE(fit_stripes({{0.2, 10, 0}, {0.4, 10, 0}}).fitted);
  CHECK_FALSE(fit_stripes({{0.2, 10, 10}, {0.4, 10, 10}}).fitted);
  const LognormalFit separated = fit_stripes({{0.2, 10, 0}, {0.3, 10, 0}, {0.4, 10, 10}, {0.5, 10, 10}});
  CHECK_FALSE(separated.fitted);
  CHECK(separated.note.find("separate") != std::string::npos);
  CHECK_FALSE(fit_capacities({{0.3, true}, {0.5, false}}).fitted);
  CHECK_FALSE(fit_capacities({{0.3, true}, {0.3, true}}).fitted);
  CHECK_THROWS_AS(fit_capacities({{-1, true}}), InputError);
  CHECK_THROWS_AS(fit_stripes({{0.3, 2, 3}}), InputError);
  CHECK(lognormal_cdf(0.5, 0.5, 0.4) == close_to(0.5, 1e-12));
}

TEST_CASE("the stripes MLE fits stripes whose fractions do not rise monotonically (resurrections)") {
  // Overturning counts of 24 records at 30 PGA levels (the chimney without
  // damper, `rocking ida --suite horizontal --im pga --levels 0.1:3:0.1`).
  const std::size_t counts[] = {0, 0, 0, 0, 0, 0, 1, 1, 2, 3, 3, 3, 3, 3, 4, 4, 5, 5, 5, 6, 8, 6, 7, 7, 10, 12, 11, 12, 13, 12};
  std::vector<Stripe> stripes;
  for (std::size_t k = 0; k < std::size(counts); ++k) stripes.push_back({0.1 * static_cast<double>(k + 1), 24, counts[k]});
  const LognormalFit fit = fit_stripes(stripes);
  INFO(fit.note);
  REQUIRE(fit.fitted);
  // Half of the runs overturn near the top of the range.
  CHECK(fit.median > 2.0);
  CHECK(fit.median < 4.0);
}

TEST_CASE("the bootstrap over records: the same seed gives the same intervals, and they cover the truth as often as stated") {
  const double median = 0.8, beta = 0.4;
  std::mt19937_64 rng(20261126);
  std::normal_distribution<double> z;
  auto draw = [&](std::size_t n) {
    std::vector<Capacity> caps;
    for (std::size_t i = 0; i < n; ++i) caps.push_back({median * std::exp(beta * z(rng)), true});
    return caps;
  };
  auto fit_of = [](const std::vector<Capacity>& caps) {
    return [&caps](const std::vector<std::size_t>& sample) {
      std::vector<Capacity> s;
      for (std::size_t i : sample) s.push_back(caps[i]);
      return fit_capacities(s);
    };
  };
  const std::vector<Capacity> caps = draw(20);
  const FitBootstrap a = bootstrap_fit(caps.size(), fit_of(caps), {1000, 7, 0.9});
  const FitBootstrap b = bootstrap_fit(caps.size(), fit_of(caps), {1000, 7, 0.9});
  const FitBootstrap c = bootstrap_fit(caps.size(), fit_of(caps), {1000, 8, 0.9});
  REQUIRE(a.computed());
  CHECK(a.draws == 1000);
  CHECK(a.fitted == 1000);
  CHECK((a.median == b.median));
  CHECK((a.beta == b.beta));
  CHECK((a.median != c.median));
  const LognormalFit full = fit_capacities(caps);
  CHECK((a.median[0] < full.median && full.median < a.median[1]));
  CHECK((a.beta[0] < full.beta && full.beta < a.beta[1]));
  // The percentile interval of ln(median) is about +-1.645 of its standard
  // error: within 15 %, a bootstrap of 20 capacities (its intervals follow the
  // sample's skew, not the normal's).
  CHECK(std::log(a.median[1] / a.median[0]) / 2 == close_to(1.645 * full.log_median_se, 0.15));
  // The pointwise band of the CDF holds the fitted CDF, and modelling
  // dispersion widens the curve (FEMA P-695: the median unchanged).
  const auto band = cdf_band(a, 1.2);
  CHECK((band[0] < lognormal_cdf(1.2, full.median, full.beta) && lognormal_cdf(1.2, full.median, full.beta) < band[1]));
  CHECK(total_beta(0.3, 0.4) == close_to(0.5, 1e-12));
  CHECK(total_beta(0.3, 0) == 0.3);
  CHECK_THROWS_AS(total_beta(0.3, -0.1), InputError);
  CHECK_THROWS_AS(bootstrap_fit(3, fit_of(caps), {10, 1, 1.5}), InputError);

  // Coverage over 400 repeated suites of 100 records, each bootstrapped 1000
  // times. A 90 % interval covers the truth in 360 of 400 on average,
  // standard deviation 6: the check is +-4 standard deviations (0.84-0.96).
  // Smaller suites undercover somewhat, as bootstrap intervals do.
  int cover_median = 0, cover_beta = 0;
  const int suites = 400;
  for (int k = 0; k < suites; ++k) {
    const std::vector<Capacity> suite = draw(100);
    const FitBootstrap f = bootstrap_fit(suite.size(), fit_of(suite), {1000, static_cast<unsigned long>(k + 1), 0.9});
    REQUIRE(f.computed());
    cover_median += f.median[0] <= median && median <= f.median[1];
    cover_beta += f.beta[0] <= beta && beta <= f.beta[1];
  }
  MESSAGE("coverage of the 90 % intervals over ", suites, " suites: median ", cover_median, ", beta ", cover_beta);
  CHECK(cover_median >= 336);
  CHECK(cover_median <= 384);
  CHECK(cover_beta >= 336);
  CHECK(cover_beta <= 384);
}
