// The suite IDA of issue 17 as a benchmark: the chimney under every
// horizontal record of ../shared/data/records (--suite horizontal, 24), 30
// PGA levels, with and without dampers (1440 runs), with its fractiles,
// fragilities and CSVs (no figures), run as a user runs it: the `rocking`
// program in a child process. Three paired rounds of 1 and 2 threads (the
// ratio is measured in one round, fair on a noisy machine), then the same
// study at 60 levels (2880 runs) for memory: peak resident memory should not
// grow with the number of jobs (rows are streamed, not kept).
// Usage: suite_bench  ($ROCKING_RECORDS, else ../shared/data/records)
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

struct Child {
  double wall_s = 0;
  long max_rss_kb = 0;
  int status = 0;
};

// Runs the program with its arguments (no shell), its output discarded.
Child run(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    ::execv(argv[0], argv.data());
    std::_Exit(127);
  }
  Child c;
  rusage usage{};
  ::wait4(pid, &c.status, 0, &usage);
  c.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  c.max_rss_kb = usage.ru_maxrss;
  return c;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main() {
  const std::string out = (std::filesystem::temp_directory_path() / "rocking_suite_bench").string();
  auto study = [&](const std::string& levels, int threads) {
    return std::vector<std::string>{ROCKING_BIN, "-q", "ida", "--suite", "horizontal", "--im", "pga", "--levels",
                                    levels, "--variants", "damper,no-damper", "--no-plot", "--threads",
                                    std::to_string(threads), "--out", out};
  };
  std::vector<double> one, two, ratio;
  long rss = 0;
  for (int round = 0; round < 3; ++round) {
    const Child a = run(study("0.1:3:0.1", 1)), b = run(study("0.1:3:0.1", 2));
    if (a.status != 0 || b.status != 0) {
      fmt::print(stderr, "suite_bench: the study failed (exit {} / {}): is --suite horizontal's folder there?\n",
                 WEXITSTATUS(a.status), WEXITSTATUS(b.status));
      return 1;
    }
    one.push_back(a.wall_s);
    two.push_back(b.wall_s);
    ratio.push_back(a.wall_s / b.wall_s);
    rss = std::max(rss, b.max_rss_kb);
  }
  const Child twice = run(study("0.05:3:0.05", 2));
  const int jobs = 24 * 30 * 2;
  fmt::print("suite IDA: 24 records x 30 PGA levels x 2 variants = {} runs, with fractiles and fragility, no figures\n",
             jobs);
  fmt::print("command: {} -q ida --suite horizontal --im pga --levels 0.1:3:0.1 --variants damper,no-damper "
             "--no-plot --threads N\n",
             ROCKING_BIN);
  fmt::print("  1 thread : median {:.2f} s wall (min {:.2f}, max {:.2f})\n", median(one),
             *std::min_element(one.begin(), one.end()), *std::max_element(one.begin(), one.end()));
  fmt::print("  2 threads: median {:.2f} s wall (min {:.2f}, max {:.2f}); {:.0f} jobs/s   [target: under 3 s (issue 17), under 2 s (issue 35)]\n",
             median(two), *std::min_element(two.begin(), two.end()), *std::max_element(two.begin(), two.end()),
             jobs / median(two));
  fmt::print("  speed-up 1 -> 2 threads: median {:.2f} over 3 paired rounds   [target: at least 1.8]\n", median(ratio));
  fmt::print("  peak memory: {:.1f} MB for {} runs, {:.1f} MB for {} runs (60 levels)   [target: flat]\n",
             rss / 1024.0, jobs, twice.max_rss_kb / 1024.0, 2 * jobs);
  std::filesystem::remove_all(out);
  return 0;
}
