// rocking.fitting: the law driven along a measured history against closed
// forms, parameter recovery from tests made by the project's own laws (exact
// without noise; within two standard errors with 1 % noise, on the committed
// synthetic tests of data/tests), and the tests that cannot be fitted.
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
#include <fstream>
#include <map>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <numbers>
#include <optional>
#include <string_view>
#include <string>
#include <vector>
import rocking.fitting;
import rocking.errors;

using namespace rocking;

namespace {

DeviceLaw law_of(const std::string& name, const std::vector<std::pair<std::string, double>>& values) {
  return make_law(name, [&](std::string_view key) -> std::optional<double> {
    for (const auto& [k, v] : values)
      if (k == key) return v;
    return std::nullopt;
  });
}

// The protocol of scripts/make_cyclic_tests.sh: two sine cycles at each amplitude.
CyclicTest protocol(const std::vector<double>& amplitudes, double frequency = 0.5, int samples = 100) {
  CyclicTest t;
  t.source = "protocol";
  const double dt = 1.0 / (frequency * samples);
  for (double a : amplitudes)
    for (int i = 0; i < 2 * samples; ++i) {
      t.t.push_back(static_cast<double>(t.t.size()) * dt);
      t.e.push_back(a * std::sin(2 * std::numbers::pi * i / samples));
    }
  return t;
}

void check_recovered(const Fit& fit, const std::vector<std::pair<std::string, double>>& truth, double rtol) {
  for (const auto& [key, value] : truth) {
    INFO(key << " = " << fit.value(key) << ", true " << value);
    CHECK(fit.value(key) == close_to(value, rtol));
  }
}

// Every free parameter within `bands` of its standard errors of the truth.
void check_within_errors(const Fit& fit, const std::vector<std::pair<std::string, double>>& truth, double bands) {
  for (const FittedParameter& p : fit.parameters) {
    if (p.fixed || !p.one_minus.empty()) continue;  // held, or following a checked one
    double value = 0;
    for (const auto& [k, v] : truth)
      if (k == p.key) value = v;
    INFO(p.key << " = " << p.value << " +- " << p.standard_error << ", true " << value);
    CHECK(p.standard_error > 0);
    CHECK(std::abs(p.value - value) <= bands * p.standard_error);
  }
}

std::string tests_dir() { return std::string(ROCKING_SOURCE_DIR) + "/data/tests/"; }

// The parameters scripts/make_cyclic_tests.sh states.
const std::vector<std::pair<std::string, double>> bouc_wen_truth{{"k", 2.0e7}, {"eps", 0.05}, {"d_y", 0.004},
                                                                  {"alpha", 0.7}, {"beta", 0.3}, {"n", 1.5}};
const std::vector<std::pair<std::string, double>> elastic_truth{{"P0", 5.0e4}, {"k", 3.0e6}};
const std::vector<std::pair<std::string, double>> viscous_truth{{"c", 2.0e5}, {"a", 0.4}};

}  // namespace

TEST_CASE("the law driven along a history: Bouc-Wen loading from rest follows its closed form") {
  // n = 1, e' > 0, z > 0: d_y dz/de = 1 - (alpha + beta) z, so
  // z = (1 - exp(-(alpha + beta) e / d_y)) / (alpha + beta).
  const double k = 1e7, eps = 0.1, d_y = 0.01, alpha = 0.6, beta = 0.2;
  const DeviceLaw law = law_of("bouc-wen", {{"k", k}, {"eps", eps}, {"d_y", d_y}, {"alpha", alpha}, {"beta", beta}, {"n", 1}});
  CyclicTest t;
  for (int i = 0; i <= 200; ++i) t.e.push_back(0.06 * i / 200.0);
  t.F.assign(t.e.size(), 0.0);
  const std::vector<double> F = law_force_history(law, t);
  for (std::size_t i = 0; i < t.e.size(); ++i) {
    const double z = (1 - std::exp(-(alpha + beta) * t.e[i] / d_y)) / (alpha + beta);
    CHECK(F[i] == close_to(k * eps * t.e[i] + k * (1 - eps) * d_y * z, 1e-9));
  }
}

TEST_CASE("the law driven along a history: viscous force from the central-difference rate") {
  // e = t^2: the central difference is exact, e' = 2 t, at interior samples.
  const DeviceLaw law = law_of("viscous", {{"c", 3e4}, {"a", 0.5}});
  CyclicTest t;
  for (int i = 0; i <= 50; ++i) {
    t.t.push_back(0.02 * i);
    t.e.push_back(t.t.back() * t.t.back());
  }
  const std::vector<double> F = law_force_history(law, t);
  for (std::size_t i = 1; i + 1 < t.e.size(); ++i) CHECK(F[i] == close_to(3e4 * std::sqrt(2 * t.t[i]), 1e-12));
}

TEST_CASE("fitting noise-free tests recovers the parameters to 1e-6") {
  SUBCASE("bouc-wen, every parameter free") {
    CyclicTest t = protocol({0.002, 0.004, 0.008, 0.016, 0.024});
    t.F = law_force_history(law_of("bouc-wen", bouc_wen_truth), t);
    check_recovered(fit_law(t, {"bouc-wen", {}}), bouc_wen_truth, 1e-6);
  }
  SUBCASE("bouc-wen, beta and n fixed as the paper did") {
    const std::vector<std::pair<std::string, double>> paper{{"k", 1e7}, {"eps", 0.06}, {"d_y", 0.0185},
                                                            {"alpha", 1.0}, {"beta", 0.0}, {"n", 1.0}};
    CyclicTest t = protocol({0.01, 0.02, 0.04, 0.07});
    t.F = law_force_history(law_of("bouc-wen", paper), t);
    const Fit fit = fit_law(t, {"bouc-wen", {{"beta", 0.0}, {"n", 1.0}}});
    check_recovered(fit, paper, 1e-6);
    CHECK(fit.parameters[4].fixed);
    CHECK(fit.parameters[4].standard_error == 0);
  }
}

TEST_CASE("every registered law is fitted back from a noise-free test of its example device, every parameter free") {
  // The laws come from the registry (device_laws): a new law is covered
  // here by its registration alone. One protocol for all: two sine cycles at
  // each of 2 to 24 mm, at 1 Hz.
  for (const LawInfo& law : device_laws()) {
    CAPTURE(law.name);
    std::vector<std::pair<std::string, double>> truth;
    for (const LawParameter& p : law.parameters) truth.emplace_back(p.key, p.example);
    CyclicTest t = protocol({0.002, 0.004, 0.008, 0.016, 0.024}, 1.0);
    t.F = law_force_history(law_of(law.name, truth), t);
    check_recovered(fit_law(t, {law.name, {}}), truth, 1e-6);
  }
}

TEST_CASE("standard errors are calibrated: two of them cover the truth in about 95 % of noisy draws") {
  // 40 draws (GSL mt19937 seeds 1-40) of 1 % Gaussian force noise on each
  // test of scripts/make_cyclic_tests.sh. For calibrated errors the z-scores
  // (fit - truth) / SE have spread 1 and |z| <= 2 in 95 % of draws; asserted:
  // spread 0.7-1.4 and at least 85 % covered (34 of 40), per parameter.
  struct Case {
    std::string law;
    std::vector<std::pair<std::string, double>> truth;
    std::vector<double> amplitudes;
    double frequency;
  };
  for (const Case& c : {Case{"bouc-wen", bouc_wen_truth, {0.002, 0.004, 0.008, 0.016, 0.024}, 0.5},
                        Case{"elastic", elastic_truth, {0.005, 0.01}, 0.5},
                        Case{"viscous", viscous_truth, {0.005, 0.01, 0.02}, 2.0}}) {
    CyclicTest t = protocol(c.amplitudes, c.frequency);
    t.t.push_back(static_cast<double>(t.t.size()) * t.t[1]);
    t.e.push_back(0.0);
    const std::vector<double> clean = law_force_history(law_of(c.law, c.truth), t);
    double peak = 0;
    for (double f : clean) peak = std::max(peak, std::abs(f));
    std::map<std::string, std::vector<double>> z;
    gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
    for (unsigned long seed = 1; seed <= 40; ++seed) {
      gsl_rng_set(rng, seed);
      t.F = clean;
      for (double& f : t.F) f += gsl_ran_gaussian(rng, 0.01 * peak);
      const Fit fit = fit_law(t, {c.law, {}});
      for (const FittedParameter& p : fit.parameters)
        if (p.one_minus.empty()) {
          double truth = 0;
          for (const auto& [k, v] : c.truth)
            if (k == p.key) truth = v;
          z[p.key].push_back((p.value - truth) / p.standard_error);
        }
    }
    gsl_rng_free(rng);
    for (const auto& [key, scores] : z) {
      double sum2 = 0;
      int covered = 0;
      for (double v : scores) {
        sum2 += v * v;
        covered += std::abs(v) <= 2;
      }
      const double spread = std::sqrt(sum2 / static_cast<double>(scores.size()));
      INFO(c.law << " " << key << ": spread " << spread << ", covered " << covered << " of 40");
      CHECK(spread >= 0.7);
      CHECK(spread <= 1.4);
      CHECK(covered >= 34);
    }
  }
}

TEST_CASE("fitting the committed synthetic tests (1 % noise, seed 1) recovers the parameters") {
  // Within two standard errors except where seed 1's draw is among the 5 %
  // outside (bouc-wen n at 2.05 SE, viscous a at 2.5 SE); the calibration
  // of the errors is what the test above asserts over 40 draws.
  SUBCASE("bouc-wen, every parameter free") {
    const Fit fit = fit_law(read_cyclic_test(tests_dir() + "bouc_wen_cyclic.csv"), {"bouc-wen", {}});
    check_within_errors(fit, bouc_wen_truth, 3);
    // The noise is 1 % of the nominal peak force 1e5 N (the file's header):
    // the fit's RMS error is that noise's, 1000 N, less the fitted share
    // sqrt((N - 6) / N); the RMS of N = 1000 draws is itself uncertain by
    // 1 / sqrt(2N) = 2.2 %: three of those.
    CHECK(fit.rms_error == close_to(1000.0 * std::sqrt(994.0 / 1000.0), 0.067));
  }
  SUBCASE("bouc-wen, beta and n fixed") {
    const Fit fit = fit_law(read_cyclic_test(tests_dir() + "bouc_wen_cyclic.csv"), {"bouc-wen", {{"beta", 0.3}, {"n", 1.5}}});
    check_within_errors(fit, bouc_wen_truth, 2);
  }
  SUBCASE("elastic") {
    check_within_errors(fit_law(read_cyclic_test(tests_dir() + "elastic_cyclic.csv"), {"elastic", {}}), elastic_truth, 2);
  }
  SUBCASE("viscous") {
    check_within_errors(fit_law(read_cyclic_test(tests_dir() + "viscous_cyclic.csv"), {"viscous", {}}), viscous_truth, 3);
  }
}

TEST_CASE("tests that cannot be fitted get a one-line error, not a diverged fit") {
  auto message = [](const CyclicTest& t, const FitRequest& r) {
    try {
      fit_law(t, r);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  CyclicTest few = protocol({0.01});
  few.t.resize(8);
  few.e.resize(8);
  few.F = law_force_history(law_of("bouc-wen", bouc_wen_truth), few);
  CHECK(message(few, {"bouc-wen", {}}).find("too few") != std::string::npos);

  CyclicTest still = protocol({0.01});
  std::fill(still.e.begin(), still.e.end(), 0.003);
  still.F.assign(still.e.size(), 1000.0);
  CHECK(message(still, {"bouc-wen", {}}).find("never moves") != std::string::npos);

  CyclicTest elastic = protocol({0.005, 0.01});
  elastic.F = law_force_history(law_of("elastic", elastic_truth), elastic);
  CHECK(message(elastic, {"bouc-wen", {}}).find("never yields") != std::string::npos);

  CyclicTest timeless = protocol({0.005, 0.01});
  timeless.F = law_force_history(law_of("viscous", viscous_truth), timeless);
  timeless.t.clear();
  CHECK(message(timeless, {"viscous", {}}).find("needs a time column") != std::string::npos);

  CHECK(message(elastic, {"elastic", {{"q", 1.0}}}).find("no such parameter") != std::string::npos);
  CHECK(message(elastic, {"spring", {}}).find("unknown") != std::string::npos);
}

TEST_CASE("plate scaling: thickness x tau gives stiffness x tau^3 and yield elongation x 1/tau") {
  CyclicTest t = protocol({0.01, 0.02, 0.04, 0.07});
  t.F = law_force_history(law_of("bouc-wen", {{"k", 1e7}, {"eps", 0.06}, {"d_y", 0.0185}, {"alpha", 1}, {"beta", 0}, {"n", 1}}), t);
  const Fit fit = fit_law(t, {"bouc-wen", {{"beta", 0.0}, {"n", 1.0}}});
  const auto scaled = scaled_parameters(fit, {2.0, {}, {}});
  CHECK(scaled[0].second == close_to(8 * fit.value("k"), 1e-12));
  CHECK(scaled[2].second == close_to(fit.value("d_y") / 2, 1e-12));
  CHECK(scaled[1].second == fit.value("eps"));
  const auto given = scaled_parameters(fit, {1.0, 3e7, 0.01});
  CHECK(given[0].second == 3e7);
  CHECK(given[2].second == 0.01);
  CyclicTest e = protocol({0.005, 0.01});
  e.F = law_force_history(law_of("elastic", elastic_truth), e);
  CHECK_THROWS_AS(scaled_parameters(fit_law(e, {"elastic", {}}), {2.0, {}, {}}), InputError);
}

TEST_CASE("reading a cyclic test: units from the header, errors naming file and line") {
  const std::string path = std::string(std::tmpnam(nullptr)) + ".csv";
  auto write = [&](const std::string& text) {
    std::ofstream(path) << text;
  };
  write("# a comment\ntime [s], displacement [mm], force [kN]\n0, 0, 0\n0.1, 2.5, 10\n");
  CyclicTest t = read_cyclic_test(path);
  REQUIRE(t.e.size() == 2);
  CHECK(t.t[1] == 0.1);
  CHECK(t.e[1] == close_to(0.0025, 1e-12));
  CHECK(t.F[1] == close_to(1e4, 1e-12));
  write("stroke (in)  load (kip)\n0 0\n1 2\n");
  t = read_cyclic_test(path);
  CHECK(t.t.empty());
  CHECK(t.e[1] == close_to(0.0254, 1e-12));
  CHECK(t.F[1] == close_to(2 * 4448.2216152605, 1e-12));
  write("d, F [kN]\n0, 0\n");
  CHECK_THROWS_WITH_AS(read_cyclic_test(path), doctest::Contains(":1: column 'd' (elongation) states no unit"), InputError);
  write("d [mm], F [kN]\n0, 0\n1, x\n");
  CHECK_THROWS_WITH_AS(read_cyclic_test(path), doctest::Contains(":3: 'x' in column 'f' is not a number"), InputError);
  write("d [mm], F [furlong]\n0, 0\n");
  CHECK_THROWS_WITH_AS(read_cyclic_test(path), doctest::Contains("unit 'furlong' is not a force unit"), InputError);
  write("a [mm], b [kN]\n0, 0\n1, 2\n");
  CHECK_THROWS_WITH_AS(read_cyclic_test(path), doctest::Contains("names no elongation column"), InputError);
  t = read_cyclic_test(path, {"", "a", "2"});
  CHECK(t.e.size() == 2);
  std::remove(path.c_str());
}
