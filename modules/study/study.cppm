// rocking.study: many runs of a scene at once, for incremental dynamic
// analysis (IDA, Vamvatsikos & Cornell 2002) and parametric studies (the
// paper's Figs. 5-8). A study is a list of jobs (record x scale x variant);
// jobs are independent and deterministic, so they run on a pool of threads and
// their results are handed back in job order: the output of a study does not
// depend on the number of threads (or of processes: the app splits the same
// list across MPI ranks). The collapse hunt steps the scale up until the
// structure overturns, then bisects (the hunt-and-fill idea of IDA tools).
module;
#include <rocking/eigen.hpp>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>
export module rocking.study;
export import rocking.simulation;
export import rocking.scene;

export namespace rocking {

// Calls work(i) for i in [0, n) on `threads` threads and emit(i, result) on the
// calling thread in the order 0, 1, 2, ... as results become available.
// progress(done, n) is called from the calling thread after each emit. When
// stop() turns true (polled; a signal handler may set what it reads), no new
// work starts, the work in flight finishes, and the results are emitted up to
// the first that was never started. Returns how many were emitted.
template <class T>
std::size_t parallel_ordered(std::size_t n, int threads, const std::function<T(std::size_t)>& work,
                             const std::function<void(std::size_t, const T&)>& emit,
                             const std::function<void(std::size_t, std::size_t)>& progress = {},
                             const std::function<bool()>& stop = {}) {
  std::vector<std::optional<T>> results(n);
  std::mutex m;
  std::condition_variable ready;
  std::atomic<std::size_t> next{0};
  auto stopped = [&] { return stop && stop(); };
  auto worker = [&] {
    for (std::size_t i; !stopped() && (i = next.fetch_add(1)) < n;) {
      T r = work(i);
      {
        std::lock_guard lock(m);
        results[i] = std::move(r);
      }
      ready.notify_one();
    }
  };
  std::vector<std::jthread> pool;
  for (int k = 0; k < std::max(1, threads); ++k) pool.emplace_back(worker);
  std::size_t i = 0;
  for (; i < n; ++i) {
    std::unique_lock lock(m);
    // Index i is computed by whoever took it; none took it if next <= i.
    while (!results[i].has_value()) {
      if (stopped() && next.load() <= i) break;
      ready.wait_for(lock, std::chrono::milliseconds(20));
    }
    if (!results[i].has_value()) break;
    T r = std::move(*results[i]);
    results[i].reset();
    lock.unlock();
    emit(i, r);
    if (progress) progress(i + 1, n);
  }
  pool.clear();  // joins
  return i;
}

// One variant of the scene: a name and the --set overrides that make it.
struct Variant {
  std::string name;
  std::vector<std::string> overrides;
};
// "damper", "no-damper", "fixed-base", "scene" (as given); InputError otherwise.
Variant named_variant(const std::string& name);

struct Job {
  std::size_t record = 0;   // index into the study's records
  double scale = 1;
  std::size_t variant = 0;  // index into the study's variants
};

// What a study keeps of a run.
struct JobResult {
  RunResult run;
  std::string error;  // non-empty: the job could not run (bad record, bad variant)
};

// A study: records (paths; a bad one gives error rows, never a stop), the
// variants, and how each run is integrated.
class Study {
 public:
  Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
        std::vector<std::string> records, RecordOptions record_options, std::vector<Variant> variants,
        RunOptions run_options);
  const std::vector<std::string>& records() const { return records_; }
  const std::vector<Variant>& variants() const { return variants_; }
  std::vector<Job> ladder(const std::vector<double>& scales) const;  // record-major, then scale, then variant
  JobResult run(const Job& job) const;
  bool can_overturn(std::size_t variant) const;  // false for a fixed base
  bool has_damper(std::size_t variant) const;
  // The record as read (unscaled), or null when it could not be read.
  const GroundMotion* motion(std::size_t record) const {
    return motions_[record] ? &*motions_[record] : nullptr;
  }

 private:
  std::vector<std::string> records_;
  std::vector<Variant> variants_;
  std::vector<std::optional<GroundMotion>> motions_;
  std::vector<std::string> record_errors_;
  std::vector<std::optional<ContactModel>> models_;
  std::vector<std::string> variant_errors_;
  RunOptions options_;
};

// "1:20:1" (first:last:step) or "0.5,1,2" -> numbers; otherwise an InputError
// quoting the text (the caller names the option it came from).
std::vector<double> parse_number_list(const std::string& text);

// The collapse hunt for one record and variant: scales first, first + step, ...
// up to max_scale until a run overturns, then bisection to `precision`.
struct HuntResult {
  bool collapsed = false;
  bool fixed_base = false;     // a fixed base cannot overturn: nothing was run
  double collapse_scale = 0;   // lowest scale found that overturns
  double survived_scale = 0;   // highest scale below it that did not
  int runs = 0;
  std::string error;
};
HuntResult hunt_collapse(const Study& study, std::size_t record, std::size_t variant, double first, double step,
                         double max_scale, double precision);

// The overturning spectrum of a rigid block under pulses (Housner 1963;
// Makris & Roussos 2000; Zhang & Makris 2001), the classic teaching figure:
// on a grid of pulse frequency over p and amplitude over g tan(alpha), does
// the block lift, and does it overturn? p^2 = g H'M1 / J_p is the block's
// frequency parameter. The block's lengths are scaled by `size` (the same
// slenderness, p ~ 1/sqrt(size)): by similarity, outcomes in the normalised
// axes do not depend on size, while in seconds the larger block survives more.
struct SpectrumPoint {
  double frequency_ratio = 0, amplitude_ratio = 0;  // omega_p / p, a_p / (g tan alpha)
  double period_s = 0, amplitude_g = 0;             // T = 2 pi / omega_p, a_p / g
  bool uplift = false, overturned = false;
};
struct BlockSpectrum {
  double size = 1, p = 0, alpha = 0;
  std::vector<SpectrumPoint> points;  // frequency-major
};
// rigid_block must be a rigid scene. Runs on `threads` threads; progress(done, total).
BlockSpectrum overturning_spectrum(const Scene& rigid_block, double size, PulseShape pulse,
                                   const std::vector<double>& frequency_ratios,
                                   const std::vector<double>& amplitude_ratios, int threads,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {});

}  // namespace rocking
