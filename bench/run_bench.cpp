// One El Centro chimney run per backend at the default tolerance (issue 7):
// wall time (best of 20), rhs evaluations and ns per evaluation; and the peak
// memory of a run over a 1-minute and a 10-minute record with only peaks
// requested (each in a child process: the process's peak, ru_maxrss from
// wait4, and what the run itself adds, VmHWM after it less VmRSS before it).
// And the rocking phase's right-hand side alone (ns per evaluation).
// Usage: run_bench [RECORDS_DIR] [--backend NAME] [--contact exact|integrated] [--repeats N] [--rhs]
//   RECORDS_DIR: default ../shared/data/records or $ROCKING_RECORDS.
//   --backend, --contact: time only this backend or full-contact treatment
//   (e.g. under perf); --repeats: runs per case, best kept (default 20);
//   --rhs: time only the rocking right-hand side.
#include <rocking/eigen.hpp>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
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

// Kilobytes of a "VmHWM:" / "VmRSS:" line of /proc/self/status.
long status_kb(const char* key) {
  FILE* f = std::fopen("/proc/self/status", "r");
  char line[256];
  long kb = -1;
  while (f && std::fgets(line, sizeof line, f))
    if (std::strncmp(line, key, std::strlen(key)) == 0) kb = std::atol(line + std::strlen(key));
  if (f) std::fclose(f);
  return kb;
}

struct Memory {
  double peak_mb = 0;   // the process's peak resident memory
  double run_mb = 0;    // what the run added to the resident memory it started with
  double record_mb = 0; // the record's samples (8 bytes each)
};

// In a child: build the record, reset the peak-memory mark (Linux clear_refs 5),
// run with peaks only, and report through a pipe.
Memory peak_memory(double seconds, const ContactModel& m) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    const GroundMotion g = synthetic(seconds);
    if (FILE* c = std::fopen("/proc/self/clear_refs", "w")) { std::fputs("5", c); std::fclose(c); }
    const long before = status_kb("VmRSS:");
    const RunResult r = simulate(m, g, RunOptions{});
    const long after = status_kb("VmHWM:");
    const long out[2] = {before, after};
    [[maybe_unused]] const auto n = write(fds[1], out, sizeof out);
    std::_Exit(r.outcome == Outcome::failed ? 1 : 0);
  }
  close(fds[1]);
  long got[2] = {0, 0};
  [[maybe_unused]] const auto n = read(fds[0], got, sizeof got);
  close(fds[0]);
  int status = 0;
  rusage usage{};
  wait4(pid, &status, 0, &usage);
  Memory mem;
  mem.peak_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;
  mem.run_mb = static_cast<double>(got[1] - got[0]) / 1024.0;
  mem.record_mb = 8.0 * (std::lround(seconds / 0.01) + 1) / (1024.0 * 1024.0);
  return mem;
}

// Nanoseconds per evaluation of the rocking phase's right-hand side alone
// (about right, with the damper active), best of 20 batches of 100,000, as the
// integrator calls it (through ode::Rhs, with a_g from the record).
double rocking_rhs_ns(const ContactModel& m, const GroundMotion& ground) {
  Discrete d;
  Eigen::VectorXd y = Eigen::VectorXd::Constant(m.layout.size, 1e-3), dydt(m.layout.size);
  begin_rocking(m, d, Pivot::right, y);
  y[m.layout.theta.start] = 0.01;
  y[m.layout.theta_dot.start] = 0.02;
  const ode::Rhs rhs = [&](double t, Eigen::Ref<const Eigen::VectorXd> x, Eigen::Ref<Eigen::VectorXd> f) {
    phase_rhs(m, d, ground.acceleration(t), x, f);
  };
  constexpr int batch = 100000;
  double best = 1e9, sink = 0;
  for (int r = 0; r < 20; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < batch; ++i) {
      rhs(1.0 + 1e-6 * i, y, dydt);
      sink += dydt[m.layout.theta_dot.start];
    }
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / batch);
  }
  if (!std::isfinite(sink)) fmt::print(stderr, "run_bench: non-finite rhs\n");
  return 1e9 * best;
}

}  // namespace

int main(int argc, char** argv) {
  const char* env = std::getenv("ROCKING_RECORDS");
  std::string dir = env ? env : std::string(ROCKING_SOURCE_DIR) + "/../shared/data/records";
  std::vector<ode::Backend> backends{ode::Backend::rk45, ode::Backend::arkode, ode::Backend::cvode};
  std::vector<bool> contacts{false, true};  // exact full contact?
  int repeats = 20;
  bool rhs_only = false;
  const char* usage = "usage: run_bench [RECORDS_DIR] [--backend NAME] [--contact exact|integrated] [--repeats N] [--rhs]";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      fmt::print("{}\n", usage);
      return 0;
    }
    if (a == "--backend" && i + 1 < argc) backends = {ode::parse_backend(argv[++i])};
    else if (a == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (a == "--rhs") rhs_only = true;
    else if (a == "--contact" && i + 1 < argc && (argv[i + 1] == std::string("exact") ||
                                                   argv[i + 1] == std::string("integrated")))
      contacts = {argv[++i] == std::string("exact")};
    else if (!a.starts_with("--")) dir = a;
    else {
      fmt::print(stderr, "run_bench: bad option '{}' ({})\n", a, usage);
      return 2;
    }
  }
  const GroundMotion elcentro = read_record(dir + "/elcentro_1940_ns.at2");
  const ContactModel model = make_contact_model(load_default_scene(), false);
  if (rhs_only) {
    fmt::print("the rocking right-hand side alone (chimney, 4 nodes, damper): {:.1f} ns per evaluation\n",
               rocking_rhs_ns(model, elcentro));
    return 0;
  }
  fmt::print("El Centro N-S, chimney with dampers, default tolerance (rtol 1e-4, atol 1e-7), best of {}\n", repeats);
  fmt::print("full contact: 'integrated' by the backend, or 'exact' steps (the default under a record);\n"
             "ns / rhs: wall time over the backend's rhs evaluations (all work included)\n");
  fmt::print("{:<8} {:<11} {:>10} {:>9} {:>8} {:>9} {:>10} {:>12}\n", "backend", "contact", "wall [ms]", "rhs", "steps",
             "rejected", "ns / rhs", "top [mm]");
  for (ode::Backend b : backends) {
    for (bool exact : contacts) {
      RunOptions o;
      o.backend = b;
      o.exact_full_contact = exact;
      RunResult best = simulate(model, elcentro, o);
      for (int k = 1; k < repeats; ++k) {
        RunResult r = simulate(model, elcentro, o);
        if (r.wall_s < best.wall_s) best = r;
      }
      fmt::print("{:<8} {:<11} {:>10.2f} {:>9} {:>8} {:>9} {:>10.0f} {:>12.2f}\n", ode::backend_name(b),
                 exact ? "exact" : "integrated", 1e3 * best.wall_s, best.stats.rhs, best.stats.steps,
                 best.stats.rejected,
                 1e9 * best.wall_s / static_cast<double>(best.stats.rhs), best.top_total_mm);
    }
  }
  if (backends.size() == 1 || contacts.size() == 1) return 0;  // a profiling run
  fmt::print("the rocking right-hand side alone (chimney, 4 nodes, damper): {:.0f} ns per evaluation\n",
             rocking_rhs_ns(model, elcentro));
  fmt::print("memory with peaks only (record at 0.01 s): process peak, the record's samples, what the run adds\n");
  for (double seconds : {60.0, 600.0}) {
    const Memory mem = peak_memory(seconds, model);
    fmt::print("  {:>3.0f}-minute record: peak {:.2f} MB, record {:.2f} MB, run {:.2f} MB\n", seconds / 60,
               mem.peak_mb, mem.record_mb, mem.run_mb);
  }
  fmt::print("target: one El Centro run under 2 ms at the default tolerance (rk45, exact contact)\n");
  return 0;
}
