// The user's command against the study path's run (issue 34): the chimney
// under El Centro N-S at the default tolerance,
//   in this process: the run as a study makes it (rk45, exact full contact,
//   no energy, no history: what run_bench times) and the same run with the
//   energy balance tracked, best of --repeats;
//   as processes, alternated A B C A B C ...: `rocking --version` (the
//   program's start-up), `rocking simulate --record R --out TMP --history t`
//   (every row, one column) and the command a user types, `rocking simulate
//   --record R --out TMP` (history.csv, summary.json, energy balance);
//   wall time of each, median over --pairs rounds.
// It prints the command's cost per run (its process less start-up) over the
// study run, the history's share of the run (all columns against one), the
// whole process and the start-up.
// Usage: command_bench [RECORDS_DIR] [--pairs N] [--repeats N]
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>
import rocking;

extern char** environ;

using namespace rocking;
using Clock = std::chrono::steady_clock;

namespace {

// Wall seconds of one run of argv, its output thrown away; exits on failure.
double run_process(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const auto start = Clock::now();
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) {
    fmt::print(stderr, "command_bench: cannot start {}\n", args[0]);
    std::exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  posix_spawn_file_actions_destroy(&actions);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print(stderr, "command_bench: {} failed (status {})\n", fmt::join(args, " "), status);
    std::exit(1);
  }
  return wall;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Best wall seconds of `repeats` runs of the chimney under g in this process.
double best_run(const ContactModel& m, const GroundMotion& g, int repeats) {
  double best = 1e300;
  for (int i = 0; i < repeats; ++i) {
    const auto start = Clock::now();
    const RunResult r = simulate(m, g, RunOptions{});
    const double wall = std::chrono::duration<double>(Clock::now() - start).count();
    if (r.outcome != Outcome::completed) {
      fmt::print(stderr, "command_bench: the chimney's run did not complete\n");
      std::exit(1);
    }
    best = std::min(best, wall);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  std::string records = std::getenv("ROCKING_RECORDS") ? std::getenv("ROCKING_RECORDS") : ROCKING_SOURCE_DIR "/../shared/data/records";
  int pairs = 41, repeats = 40;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--pairs" && i + 1 < argc) pairs = std::max(3, std::atoi(argv[++i]));
    else if (a == "--repeats" && i + 1 < argc) repeats = std::max(1, std::atoi(argv[++i]));
    else if (a == "--help") {
      fmt::print("usage: command_bench [RECORDS_DIR] [--pairs N] [--repeats N]\n");
      return 0;
    } else records = a;
  }
  const std::string record = records + "/elcentro_1940_ns.at2";
  if (!std::filesystem::exists(record)) {
    fmt::print(stderr, "command_bench: {} not found (give RECORDS_DIR or set ROCKING_RECORDS)\n", record);
    return 1;
  }
  const GroundMotion g = read_record(record);
  const Scene scene = load_default_scene();
  const double study = best_run(make_contact_model(scene, false), g, repeats);
  const double with_energy = best_run(make_contact_model(scene, true), g, repeats);

  char folder[] = "/tmp/command_bench.XXXXXX";
  if (mkdtemp(folder) == nullptr) {
    fmt::print(stderr, "command_bench: cannot make a temporary folder\n");
    return 1;
  }
  const std::string bin = ROCKING_BIN, out = std::string(folder) + "/out";
  const std::vector<std::string> version{bin, "--version"},
      one_column{bin, "simulate", "--record", record, "--out", out, "--history", "t"},
      command{bin, "simulate", "--record", record, "--out", out};
  std::vector<double> start_up, narrow, full, per_run, history;
  for (const auto* args : {&version, &one_column, &command}) run_process(*args);  // warm-up
  for (int i = 0; i < pairs; ++i) {
    const double v = run_process(version), n = run_process(one_column), c = run_process(command);
    start_up.push_back(v);
    narrow.push_back(n);
    full.push_back(c);
    per_run.push_back(c - v);
    history.push_back(c - n);
  }
  std::filesystem::remove_all(folder);

  const double run = median(per_run);
  fmt::print("the chimney under El Centro N-S, default tolerance; {} alternated rounds of processes, medians\n", pairs);
  fmt::print("  study run in process (rk45 + exact full contact, as run_bench): {:.2f} ms (best of {})\n", 1e3 * study,
             repeats);
  fmt::print("  the same with the energy balance tracked:                       {:.2f} ms ({:.2f}x)\n",
             1e3 * with_energy, with_energy / study);
  fmt::print("  start-up, `rocking --version`:                                   {:.2f} ms\n", 1e3 * median(start_up));
  fmt::print("  the command, `rocking simulate --record R --out DIR`:            {:.2f} ms whole process\n",
             1e3 * median(full));
  fmt::print("    per run (less start-up):                                       {:.2f} ms = {:.2f}x the study run "
             "(target 1.5x)\n",
             1e3 * run, run / study);
  fmt::print("    its history's columns (against `--history t`):                 {:.2f} ms = {:.0f} % of the run "
             "(target 10 %)\n",
             1e3 * median(history), 100 * median(history) / run);
  return 0;
}
