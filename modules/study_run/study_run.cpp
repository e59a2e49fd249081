module;
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <map>
#include <mutex>
#include <thread>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
module rocking.study_run;

namespace rocking {

namespace {

bool stopped(const StudyCallbacks& c) { return c.stop && c.stop(); }

}  // namespace

Ladder plan_ladder(const Study& study, std::vector<double> levels, std::span<const Limit> limits) {
  Ladder out;
  out.limits.push_back(overturning_limit());
  for (const Limit& l : limits) {
    check_limit(study, l);
    out.limits.push_back(l);
  }
  out.jobs = study.ladder(levels);
  out.levels = std::move(levels);
  out.columns = study_columns(study);
  return out;
}

std::size_t run_ladder(const Study& study, const Ladder& ladder, std::span<const std::size_t> which, int threads,
                       StudySummary* summary, const std::function<void(std::size_t, const JobResult&)>& emit,
                       const StudyCallbacks& callbacks) {
  std::size_t emitted = 0;
  bool halted = false;
  parallel_ordered<JobResult>(
      which.size(), threads, [&](std::size_t k) { return study.run(ladder.jobs[which[k]]); },
      [&](std::size_t k, const JobResult& r) {
        // An error while stopping is the stop's: that run and those after it are left.
        if (halted || (stopped(callbacks) && !r.error.empty())) {
          halted = true;
          return;
        }
        ++emitted;
        const Job& job = ladder.jobs[which[k]];
        if (summary != nullptr) summary->add(job, written_row(ladder.columns, job, r));
        emit(which[k], r);
      },
      [&](std::size_t done, std::size_t total) {
        if (callbacks.progress) callbacks.progress(done, total);
      },
      [&] { return stopped(callbacks); });
  return emitted;
}

std::size_t run_hunts(const Study& study, const HuntOptions& options, std::size_t first, int threads,
                      const std::function<void(std::size_t, const HuntResult&)>& emit,
                      const StudyCallbacks& callbacks) {
  const std::size_t nv = study.variants().size(), pairs = study.records().size() * nv;
  if (first >= pairs) return 0;
  std::size_t emitted = 0;
  bool halted = false;
  parallel_ordered<HuntResult>(
      pairs - first, threads,
      [&](std::size_t k) { return hunt_collapse(study, (first + k) / nv, (first + k) % nv, options); },
      [&](std::size_t k, const HuntResult& h) {
        if (halted || (stopped(callbacks) && !h.error.empty())) {
          halted = true;
          return;
        }
        ++emitted;
        emit(first + k, h);
      },
      [&](std::size_t done, std::size_t total) {
        if (callbacks.progress) callbacks.progress(done, total);
      },
      [&] { return stopped(callbacks); });
  return emitted;
}

}  // namespace rocking
