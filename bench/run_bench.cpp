// One El Centro chimney run per backend at the default tolerance (issue 7):
// wall time (best of 20), rhs evaluations and ns per evaluation; and the peak
// memory of a run over a 1-minute and a 10-minute record with only peaks
// requested (each in a child process, ru_maxrss from wait4).
// Usage: run_bench [RECORDS_DIR] [--backend NAME] [--repeats N]
//   RECORDS_DIR: default ../shared/data/records or $ROCKING_RECORDS.
//   --backend: time only this backend (e.g. under perf); --repeats: runs per
//   backend, best kept (default 20).
#include <rocking/eigen.hpp>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>
import rocking;

using namespace rocking;

namespace {

GroundMotion synthetic(double seconds) {
  std::vector<double> t, a;
  for (long i = 0; i <= std::lround(seconds / 0.01); ++i) {
    const double ti = 0.01 * static_cast<double>(i);
    t.push_back(ti);
    a.push_back(2.0 * std::sin(2 * M_PI * 1.3 * ti) + std::sin(2 * M_PI * 3.1 * ti));
  }
  return GroundMotion::from_samples("synthetic", t, a);
}

// Peak resident memory [MB] of a child that builds the record and runs it.
double peak_memory_mb(double seconds, const ContactModel& m) {
  const pid_t pid = fork();
  if (pid == 0) {
    const GroundMotion g = synthetic(seconds);
    const RunResult r = simulate(m, g, RunOptions{});
    std::_Exit(r.outcome == Outcome::failed ? 1 : 0);
  }
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("ROCKING_RECORDS");
  std::string dir = env ? env : std::string(ROCKING_SOURCE_DIR) + "/../shared/data/records";
  std::vector<ode::Backend> backends{ode::Backend::rk45, ode::Backend::arkode, ode::Backend::cvode};
  int repeats = 20;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--backend" && i + 1 < argc) backends = {ode::parse_backend(argv[++i])};
    else if (a == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (!a.starts_with("--")) dir = a;
    else {
      fmt::print(stderr, "run_bench: unknown option '{}' (usage: run_bench [RECORDS_DIR] [--backend NAME] [--repeats N])\n", a);
      return 2;
    }
  }
  const GroundMotion elcentro = read_record(dir + "/elcentro_1940_ns.at2");
  const ContactModel model = make_contact_model(load_default_scene(), false);
  fmt::print("El Centro N-S, chimney with dampers, default tolerance (rtol 1e-4, atol 1e-7), best of {}\n", repeats);
  fmt::print("{:<8} {:>10} {:>9} {:>8} {:>10} {:>12}\n", "backend", "wall [ms]", "rhs", "steps", "ns / rhs", "top [mm]");
  for (ode::Backend b : backends) {
    RunOptions o;
    o.backend = b;
    RunResult best = simulate(model, elcentro, o);
    for (int k = 1; k < repeats; ++k) {
      RunResult r = simulate(model, elcentro, o);
      if (r.wall_s < best.wall_s) best = r;
    }
    fmt::print("{:<8} {:>10.2f} {:>9} {:>8} {:>10.0f} {:>12.2f}\n", ode::backend_name(b), 1e3 * best.wall_s,
               best.stats.rhs, best.stats.steps, 1e9 * best.wall_s / static_cast<double>(best.stats.rhs),
               best.top_total_mm);
  }
  if (backends.size() == 1) return 0;  // a profiling run
  const double one = peak_memory_mb(60, model), ten = peak_memory_mb(600, model);
  fmt::print("peak memory, peaks only: 1-minute record {:.1f} MB, 10-minute record {:.1f} MB\n", one, ten);
  fmt::print("target: one El Centro run under 2 ms with rk45 at the default tolerance\n");
  return 0;
}
