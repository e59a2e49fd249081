// make_cyclic_test: a synthetic cyclic test of a device, made by the
// project's own law (rocking.fitting's law_force_history) along a sine
// protocol of growing amplitudes, with Gaussian noise on the force. It makes
// the tests in data/tests (scripts/make_cyclic_tests.sh says with what).
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <cmath>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
import rocking.errors;
import rocking.devices;
import rocking.fitting;

int main(int argc, char** argv) {
  CLI::App app{"Writes a synthetic cyclic test (time [s], displacement [mm], force [kN]) made by a device law"};
  std::string law = "bouc-wen", out;
  std::vector<std::string> params;
  std::vector<double> amplitudes;
  double frequency = 0.5, noise = 0.01;
  int cycles = 2, samples = 100;
  unsigned long seed = 1;
  app.add_option("--law", law, "Device law");
  app.add_option("--param", params, "KEY=VALUE, SI units (repeatable)");
  app.add_option("--amplitudes", amplitudes, "Displacement amplitudes [m], in order")->required()->delimiter(',');
  app.add_option("--frequency", frequency, "Cycles per second");
  app.add_option("--cycles", cycles, "Cycles per amplitude");
  app.add_option("--samples", samples, "Samples per cycle");
  app.add_option("--noise", noise, "Standard deviation of the force noise, as a fraction of the peak force");
  app.add_option("--seed", seed, "Seed of the noise (GSL mt19937)");
  app.add_option("--out", out, "CSV file to write")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    const rocking::DeviceLaw device = rocking::make_law(law, [&](std::string_view key) -> std::optional<double> {
      for (const std::string& p : params)
        if (p.starts_with(std::string(key) + "=")) return std::stod(p.substr(key.size() + 1));
      return std::nullopt;
    });
    rocking::CyclicTest test;
    const double dt = 1.0 / (frequency * samples);
    for (double a : amplitudes)
      for (int i = 0; i < cycles * samples; ++i) {
        test.t.push_back(static_cast<double>(test.t.size()) * dt);
        test.e.push_back(a * std::sin(2 * std::numbers::pi * i / samples));
      }
    test.t.push_back(static_cast<double>(test.t.size()) * dt);
    test.e.push_back(0.0);
    std::vector<double> F = rocking::law_force_history(device, test);
    double peak = 0;
    for (double f : F) peak = std::max(peak, std::abs(f));
    gsl_rng* rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, seed);
    for (double& f : F) f += gsl_ran_gaussian(rng, noise * peak);
    gsl_rng_free(rng);
    std::ofstream csv(out);
    csv << fmt::format("# made by make_cyclic_test --law {}", law);
    for (const std::string& p : params) csv << " --param " << p;
    csv << fmt::format(" (noise {} of the peak force {:.6g} N, seed {})\n", noise, peak, seed);
    csv << "time [s],displacement [mm],force [kN]\n";
    for (std::size_t i = 0; i < F.size(); ++i)
      csv << fmt::format("{:.6f},{:.9g},{:.9g}\n", test.t[i], test.e[i] * 1000, F[i] / 1000);
    if (!csv) throw rocking::InputError(out + ": cannot write");
  } catch (const std::exception& e) {
    fmt::print(stderr, "make_cyclic_test: error: {}\n", e.what());
    return 2;
  }
  return 0;
}
