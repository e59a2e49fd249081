// rocking.study_run: a suite study run once for every front end (MODEL.md
// 12-13): the ladder (every record scaled to each IM level, for each
// variant) with its limit states and its summary, and the collapse hunts
// (rocking.study's hunt_collapse), each job on a pool of threads with its
// results handed back in job order (parallel_ordered). The front ends are
// sinks of the same runner: `rocking ida` and `rocking sweep` write each
// result as a row of their files as it comes (rocking.study_files), Python's
// ida keeps it as a dict; progress and cancellation are callbacks. No physics
// here: rocking.study runs each job.
module;
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>
export module rocking.study_run;
export import rocking.study;
export import rocking.study_files;

export namespace rocking {

// How a running study talks to its caller, always on the calling thread.
struct StudyCallbacks {
  std::function<void(std::size_t done, std::size_t total)> progress;  // after each result; empty: none
  // Polled: true starts no new run and ends those in flight within a step
  // (their results are not emitted: a stopped run is not a result). Empty: never.
  std::function<bool()> stop;
};

// A ladder as run: its levels (in the order given), its limit states
// (overturning, then each of `limits`, checked against the study's devices
// and joints), its jobs (Study::ladder) and the columns of its rows.
// InputError for a limit the study cannot reach. A level that scales a record beyond what a
// record can be is the caller's to refuse (Study::check_level) or to run as
// an error row.
struct Ladder {
  std::vector<double> levels;
  std::vector<Limit> limits;
  std::vector<Job> jobs;
  StudyColumns columns;
};
Ladder plan_ladder(const Study& study, std::vector<double> levels, std::span<const Limit> limits);

// Runs the jobs ladder.jobs[which[k]] (which ascending) on `threads` threads
// and hands each result to emit(job index, result) in order; with a summary,
// adds each to it as the study's rows write it (written_row), so that a summary
// of rows read back is the same. A run a stop cut short ends the emission:
// it and every job after it are left to run again (--resume). Returns how
// many were emitted: which[0 .. n) ran.
std::size_t run_ladder(const Study& study, const Ladder& ladder, std::span<const std::size_t> which, int threads,
                       StudySummary* summary, const std::function<void(std::size_t, const JobResult&)>& emit,
                       const StudyCallbacks& callbacks);

// The collapse hunts of the pairs (record, variant) from pair `first` on, in
// record-major order (pair k: record k / variants, variant k % variants), on
// `threads` threads, each result handed to emit(pair, result) in order; a
// hunt a stop cut short ends the emission as run_ladder's. Returns how many
// were emitted.
std::size_t run_hunts(const Study& study, const HuntOptions& options, std::size_t first, int threads,
                      const std::function<void(std::size_t, const HuntResult&)>& emit,
                      const StudyCallbacks& callbacks);

}  // namespace rocking
