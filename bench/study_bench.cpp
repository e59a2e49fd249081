// The paper's Fig. 5 study as a benchmark (issue 6): the chimney under the
// Papanui stand-in record, scales 1 to 20, three variants (60 runs), with 1
// and 2 threads. Best of five of each; reports wall time, jobs per second and
// the speed-up, measured in one process so the ratio is fair on a noisy machine.
// Usage: study_bench [RECORDS_DIR]  (default ../shared/data/records or $ROCKING_RECORDS)
#include <rocking/eigen.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <string>
#include <vector>
import rocking;

int main(int argc, char** argv) {
  const char* env = std::getenv("ROCKING_RECORDS");
  const std::string dir = argc > 1 ? argv[1] : env ? env : std::string(ROCKING_SOURCE_DIR) + "/../shared/data/records";
  const std::string record = dir + "/christchurch2011_pphs_s57e.at2";
  using namespace rocking;
  RunOptions options;  // rk45 at the default tolerance (rtol 1e-4, atol 1e-7), as the command line
  const Study study("", {}, {record}, RecordOptions{},
                    {named_variant("damper"), named_variant("no-damper"), named_variant("fixed-base")}, options);
  const std::vector<Job> jobs = study.ladder(parse_number_list("1:20:1"));
  auto wall = [&](int threads) {
    double best = 1e30;
    long failed = 0;
    for (int repeat = 0; repeat < 5; ++repeat) {
      const auto t0 = std::chrono::steady_clock::now();
      failed = 0;
      parallel_ordered<JobResult>(
          jobs.size(), threads, [&](std::size_t i) { return study.run(jobs[i]); },
          [&](std::size_t, const JobResult& r) { failed += !r.error.empty(); });
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    if (failed > 0) fmt::print("warning: {} jobs failed\n", failed);
    return best;
  };
  const double one = wall(1), two = wall(2);
  fmt::print("Fig. 5 study: {} runs (Papanui stand-in, scales 1-20, damper / no-damper / fixed-base), rk45 rtol 1e-4\n",
             jobs.size());
  fmt::print("{:>8} {:>10} {:>10} {:>9}\n", "threads", "wall [s]", "jobs/s", "speed-up");
  fmt::print("{:>8} {:>10.3f} {:>10.1f} {:>9.2f}\n", 1, one, jobs.size() / one, 1.0);
  fmt::print("{:>8} {:>10.3f} {:>10.1f} {:>9.2f}\n", 2, two, jobs.size() / two, one / two);
  fmt::print("targets: 60 runs under 1 s ({}), speed-up at least 1.7 ({})\n", two < 1.0 ? "met" : "NOT met",
             one / two >= 1.7 ? "met" : "NOT met");
  return 0;
}
