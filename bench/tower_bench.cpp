// The cost of a run against the number of nodes N (issue 20): the towers of
// data/scenes/towers (scripts/make_towers.py: the chimney's height, mass and
// mean stiffness over N masses) under El Centro N-S at the default tolerance,
// one run each, in two set-ups: as `rocking simulate` runs (energy balance
// tracked) and as a study runs (no energy accumulators); in both, full
// contact is stepped exactly under rk45 and integrated by an automatic rosw. A run past its
// budget is stopped (RunOptions::stop) and reported with the time it reached.
// Each integrator named is timed on every tower (auto: the default choice,
// rk45 for 8 nodes and rosw from 16; rk45 for the explicit method).
// The exponent between consecutive N is log(cost ratio) / log(N ratio).
// --peaks then measures the default run's accuracy: its peaks of delta_t,
// delta_e, theta and base moment against rk45 at rtol 1e-8 (N <= 32, where it
// is affordable) and against rosw at rtol 1e-8 for every N (convergence).
// Usage: tower_bench [RECORDS_DIR] [--n 8,16,32,64,128] [--integrators auto,rk45] [--budget S] [--peaks]
#include <rocking/eigen.hpp>
#include <fmt/format.h>
#include <array>
#include <chrono>
#include <utility>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>
import rocking;

using namespace rocking;

namespace {

constexpr std::array checked{Quantity::delta_t, Quantity::delta_e, Quantity::theta, Quantity::base_moment};

// The largest relative difference of the checked peaks of a and b.
double peak_difference(const RunResult& a, const RunResult& b) {
  double worst = 0;
  for (Quantity q : checked) worst = std::max(worst, std::abs(a.peak(q) / b.peak(q) - 1));
  return worst;
}

void peak_accuracy(const GroundMotion& record, const std::vector<double>& counts, double budget) {
  fmt::print("\npeaks of the default run (auto, rtol 1e-4, energy tracked) against references at rtol 1e-8\n"
             "(largest relative difference of delta_t, delta_e, theta, base moment; target 1e-3 against rk45)\n");
  fmt::print("{:>5} {:>12} {:>12} {:>10} {:>12} {:>10}\n", "N", "default", "vs rk45", "rk45 [s]", "vs rosw", "rosw [s]");
  for (double n : counts) {
    const Scene scene =
        load_scene(fmt::format("{}/data/scenes/towers/tower_{}.toml", ROCKING_SOURCE_DIR, static_cast<int>(n)));
    const RunResult run = simulate(make_contact_model(scene, true), record, RunOptions{});
    const ContactModel model = make_contact_model(scene, false);
    const auto reference = [&](ode::Backend b) {
      RunOptions o;
      o.backend = b;
      o.tolerances.rtol = 1e-8;
      o.tolerances.atol = 1e-11;
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
      o.stop = [deadline] { return std::chrono::steady_clock::now() > deadline; };
      return simulate(model, record, o);
    };
    const auto cell = [&](const RunResult& r) {
      return r.outcome == Outcome::failed ? std::pair{std::string("over budget"), std::string("-")}
                                          : std::pair{fmt::format("{:.1e}", peak_difference(run, r)),
                                                      fmt::format("{:.3g}", r.wall_s)};
    };
    const auto [rk45_diff, rk45_wall] =
        n <= 32 ? cell(reference(ode::Backend::rk45)) : std::pair{std::string("-"), std::string("-")};
    const auto [rosw_diff, rosw_wall] = cell(reference(ode::Backend::rosw));
    fmt::print("{:>5} {:>12} {:>12} {:>10} {:>12} {:>10}\n", n, run.integrator, rk45_diff, rk45_wall, rosw_diff,
               rosw_wall);
  }
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("ROCKING_RECORDS");
  std::string dir = env ? env : std::string(ROCKING_SOURCE_DIR) + "/../shared/data/records";
  std::vector<double> counts{8, 16, 32, 64, 128};
  std::vector<std::string> integrators{"auto", "rk45"};
  double budget = 20;
  bool peaks = false;
  const char* usage =
      "usage: tower_bench [RECORDS_DIR] [--n 8,16,32,64,128] [--integrators auto,rk45] [--budget S] [--peaks]";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      fmt::print("{}\n", usage);
      return 0;
    }
    if (a == "--n" && i + 1 < argc) counts = parse_number_list(argv[++i]);
    else if (a == "--budget" && i + 1 < argc) budget = std::atof(argv[++i]);
    else if (a == "--peaks") peaks = true;
    else if (a == "--integrators" && i + 1 < argc) {
      integrators.clear();
      for (std::string list = argv[++i]; !list.empty();) {
        const std::size_t comma = list.find(',');
        integrators.push_back(list.substr(0, comma));
        list = comma == std::string::npos ? "" : list.substr(comma + 1);
      }
    }
    else if (!a.starts_with("--")) dir = a;
    else {
      fmt::print(stderr, "tower_bench: bad option '{}' ({})\n", a, usage);
      return 2;
    }
  }
  const GroundMotion elcentro = read_record(dir + "/elcentro_1940_ns.at2");
  fmt::print("towers of N nodes (data/scenes/towers) under El Centro N-S ({:.1f} s) at the default tolerance\n"
             "(rtol 1e-4), one run each, stopped after {:g} s\n", elcentro.duration(), budget);
  fmt::print("{:>5} {:<8} {:<22} {:>10} {:>12} {:>10} {:>9} {:>10} {:>12}\n", "N", "method", "set-up", "wall [s]", "rhs",
             "steps", "exponent", "reached", "delta_t");
  for (const std::string& name : integrators) {
    const ode::Backend backend = ode::parse_backend(name);
    for (bool energy : {true, false}) {
      double previous_wall = 0, previous_n = 0;
      for (double n : counts) {
        const Scene scene =
            load_scene(fmt::format("{}/data/scenes/towers/tower_{}.toml", ROCKING_SOURCE_DIR, static_cast<int>(n)));
        const ContactModel model = make_contact_model(scene, energy);
        RunOptions o;
        o.backend = backend;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
        o.stop = [deadline] { return std::chrono::steady_clock::now() > deadline; };
        const RunResult r = simulate(model, elcentro, o);
        const bool finished = r.outcome != Outcome::failed;
        const std::string exponent =
            previous_wall > 0 && finished
                ? fmt::format("{:.2f}", std::log(r.wall_s / previous_wall) / std::log(n / previous_n))
                : std::string("-");
        fmt::print("{:>5} {:<8} {:<22} {:>10.4g} {:>12} {:>10} {:>9} {:>9.1f}s {:>12.6g}\n", n,
                   name == "auto" ? "auto:" + r.integrator : r.integrator,
                   energy ? "simulate (energy)" : (r.exact_full_contact ? "study (exact contact)" : "study"),
                   r.wall_s, r.stats.rhs, r.stats.steps,
                   exponent, r.t_end, finished ? r.peak(Quantity::delta_t) : std::nan(""));
        previous_wall = finished ? r.wall_s : 0;
        previous_n = n;
        if (!finished) break;  // a larger tower would not finish either
      }
    }
  }
  fmt::print("target (issue 20): cost at most ~N^2 from N = 16 to 128, N = 64 under 50 ms\n");
  if (peaks) peak_accuracy(elcentro, counts, budget);
  return 0;
}
