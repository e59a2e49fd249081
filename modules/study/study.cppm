// rocking.study: many runs of a scene at once, for incremental dynamic
// analysis (IDA, Vamvatsikos & Cornell 2002) and parametric studies (the
// paper's Figs. 5-8). A study is a list of jobs (record x IM level x variant);
// each record is scaled so that its intensity measure equals the level
// exactly (SF = level / IM(record), MODEL.md 12). Jobs are independent and
// deterministic, so they run on a pool of threads and their results are
// handed back in job order: the output of a study does not depend on the
// number of threads (or of processes: the app splits the same list across
// MPI ranks). The collapse hunt is the hunt-and-fill of Vamvatsikos & Cornell
// (2004): trace up with a growing step to the first overturning, bisect to a
// stated precision, then fill the levels below at a finer step to catch
// earlier collapse windows. The summary (summary.cpp) gathers what a suite
// study reports (MODEL.md 13): fractile IDA curves, capacities and stripes
// for each limit state, and their lognormal fragilities (rocking.fragility).
module;
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <array>
#include <limits>
#include <map>
#include <memory>
#include <string_view>
#include <optional>
#include <string_view>
#include <string>
#include <thread>
#include <vector>
export module rocking.study;
export import rocking.simulation;
export import rocking.scene;
export import rocking.intensity;
export import rocking.fragility;

export namespace rocking {

// The threads a study runs on: `requested` (0: every core), at most four
// per core (beyond that they only wait for each other: `capped` says so).
// InputError naming `option` when negative.
struct WorkerThreads {
  int threads = 1, cores = 1;
  bool capped = false;
};
WorkerThreads worker_threads(int requested, std::string_view option);

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
  // Results done but not yet emitted: memory follows the work in flight, not n.
  std::map<std::size_t, T> results;
  std::mutex m;
  std::condition_variable ready;
  std::atomic<std::size_t> next{0};
  auto stopped = [&] { return stop && stop(); };
  auto worker = [&] {
    for (std::size_t i; !stopped() && (i = next.fetch_add(1)) < n;) {
      T r = work(i);
      {
        std::lock_guard lock(m);
        results.emplace(i, std::move(r));
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
    auto done = results.find(i);
    while (done == results.end()) {
      if (stopped() && next.load() <= i) break;
      ready.wait_for(lock, std::chrono::milliseconds(20));
      done = results.find(i);
    }
    if (done == results.end()) break;
    T r = std::move(done->second);
    results.erase(done);
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
// "scene" (as given), "fixed-base", "without:NAME" (without the device the
// scene names NAME, its [damper] included: DeviceGroup), "no-devices", and
// the paper's "damper" and "no-damper" (the [damper] on and off); InputError
// otherwise.
Variant named_variant(const std::string& name);
// The variants a study of the scene runs unless told: as built ("scene"),
// without each of its energy-dissipating devices ("without:NAME", by the
// laws' traits), and on a fixed base when it is flexible and rocks on its
// own base (not at joints, not on columns). None needs a key the scene lacks.
std::vector<Variant> default_variants(const Scene& scene);

struct Job {
  std::size_t record = 0;   // index into the study's records
  double scale = 1;         // the factor applied to the record
  std::size_t variant = 0;  // index into the study's variants
  double level = 1;         // the IM level the scale brings the record to (the scale itself for "sf")
};

// What a study keeps of a run.
struct JobResult {
  RunResult run;
  std::string error;  // non-empty: the job could not run (bad record, bad variant)
};

// A record of a study: a file to read, or a motion already in memory under a name.
struct StudyRecord {
  std::string name;                            // the path read, or the given motion's name
  std::shared_ptr<const GroundMotion> motion;  // null: read the file `name`
};

// A study: records (paths or motions; a bad one gives error rows, never a
// stop), the variants, and how each run is integrated.
class Study {
 public:
  // im: what the levels measure (the scale factor unless given).
  Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
        std::vector<std::string> records, RecordOptions record_options, std::vector<Variant> variants,
        RunOptions run_options, IntensityMeasure im = {});
  Study(const std::string& scene_path, const std::vector<std::string>& common_overrides,
        const std::vector<StudyRecord>& records, RecordOptions record_options, std::vector<Variant> variants,
        RunOptions run_options, IntensityMeasure im = {});
  const std::vector<std::string>& records() const { return records_; }
  const std::vector<Variant>& variants() const { return variants_; }
  const IntensityMeasure& intensity_measure() const { return im_; }
  // The record's own IM (unscaled); NaN when it could not be read.
  double record_intensity(std::size_t record) const { return record_im_[record]; }
  // Empty, or why the record's jobs cannot run.
  const std::string& record_error(std::size_t record) const { return record_errors_[record]; }
  // The job that runs the record scaled to an IM level.
  Job at_level(std::size_t record, std::size_t variant, double level) const;
  std::vector<Job> ladder(const std::vector<double>& levels) const;  // record-major, then level, then variant
  JobResult run(const Job& job) const;
  // InputError naming `option`, the level and the record when scaling a
  // readable record to the level takes it beyond max_acceleration_g.
  void check_level(double level, std::string_view option) const;
  bool can_overturn(std::size_t variant) const;  // false for a fixed base
  // Whether the variant's model reports the quantity (a fixed base has no
  // theta, a variant without a device none of its quantities).
  bool reports(std::size_t variant, const QuantityName& q) const;
  // The names of the variant's devices (none when its scene failed to load).
  std::vector<std::string> device_names(std::size_t variant) const;
  // How many joints the variant's structure has above its base (MODEL.md 15; 0: none, or its scene failed to load).
  int joints(std::size_t variant) const;
  // The record as read (unscaled), or null when it could not be read.
  const GroundMotion* motion(std::size_t record) const {
    return motions_[record] ? &*motions_[record] : nullptr;
  }

 private:
  std::vector<std::string> records_;
  std::vector<Variant> variants_;
  std::vector<std::optional<GroundMotion>> motions_;
  std::vector<std::string> record_errors_;
  IntensityMeasure im_;
  std::vector<double> record_im_;
  std::vector<std::optional<ContactModel>> models_;
  std::vector<std::string> variant_errors_;
  RunOptions options_;
};

// "1:20:1" (first:last:step) or "0.5,1,2" -> numbers; otherwise an InputError
// quoting the text (the caller names the option it came from).
std::vector<double> parse_number_list(const std::string& text);

// The collapse hunt for one record and variant, in IM levels (Vamvatsikos &
// Cornell 2004): trace up from `first` by a step that grows by `growth` each
// run, up to `max`, until a run overturns; bisect between the last survivor
// and that collapse to `precision`; then fill every level below it at
// `fill_step` (first + k fill_step) and, if an earlier collapse turns up,
// bisect below the lowest one too. A collapse window narrower than
// `fill_step` below the answer can be missed: the answer is the lowest
// collapse level found, bracketed to `precision`.
struct HuntOptions {
  double first = 1, step = 1, growth = 1.5, max = 50, precision = 0.05, fill_step = 0.1;
};
// InputError unless every option is positive and finite, growth >= 1 and
// first <= max, or when the hunt could take more than 1e5 runs.
void check_hunt_options(const HuntOptions& o);
// The options from the first level and those given (none: the default):
// step the first level, precision step / 20, fill_step step / 10, max 50 x
// the first level; checked.
HuntOptions hunt_options(double first, std::optional<double> step, double growth, std::optional<double> max,
                         std::optional<double> precision, std::optional<double> fill_step);
struct HuntPoint {
  double level = 0;
  bool overturned = false;
  // Why it was run: the trace up (to --hunt-max itself), a bisection of a
  // bracket, or the fill at --fill-step below the collapse (below --hunt-max
  // when the trace met none).
  enum class Why { trace, bisect, fill } why = Why::trace;
};
std::string_view hunt_reason(HuntPoint::Why why);
struct HuntResult {
  bool collapsed = false;
  bool fixed_base = false;     // a fixed base cannot overturn: nothing was run
  double collapse_level = 0;   // the lowest level found that overturns
  double survived_level = 0;   // the highest level below it that did not (the highest run if none overturned)
  double traced_level = 0;     // the first overturning the trace up met (before the fill)
  double record_im = 0;        // the record's own IM: scale = level / record_im
  std::vector<HuntPoint> points;  // every run, in level order
  // Levels above the collapse at which the structure survived, as ranges
  // [first, last] of consecutive surviving runs ("resurrections").
  std::vector<std::pair<double, double>> resurrections;
  int runs = 0;
  std::string error;
};
HuntResult hunt_collapse(const Study& study, std::size_t record, std::size_t variant, const HuntOptions& options);

// A hunt's overturning capacity: the collapse level, or (none found) the
// highest level it survived, censored.
Capacity hunt_capacity(const HuntResult& h);
// The (record, capacity) of a variant's hunts, from hunts of every (record,
// variant) in record-major order; records whose hunt ran nothing or failed are
// left out.
std::vector<std::pair<std::size_t, Capacity>> hunt_capacities(const std::vector<HuntResult>& hunts,
                                                              std::size_t variants, std::size_t variant);

// A limit state for fragility (MODEL.md 13): overturning, or a peak quantity
// at or above a value. An overturned run has reached every limit.
struct Limit {
  std::string name;                      // "overturning", "theta_over_alpha>=0.5", "plates.elongation>=0.07"
  std::optional<QuantityName> quantity;  // none: overturning
  double value = 0;
};
Limit overturning_limit();
// "theta_over_alpha=0.5", "damper_d=0.07", "plates.elongation=0.07" (in the
// quantity's unit of rocking.quantities: m, N, drifts as fractions, forces
// over V_ref and M_ref); InputError naming the text and the quantities
// otherwise. A device's quantity is checked against the study's devices by
// check_limit.
Limit parse_limit(const std::string& text);
// InputError when a limit names a device or a joint that no variant of the study has.
void check_limit(const Study& study, const Limit& limit);
// A study quantity by name (a scalar one of Role::study, or a device's);
// InputError naming the text and the choices otherwise.
QuantityName parse_study_quantity(std::string_view text);
// "delta_t, delta_e, ..., jointK.theta, jointK.theta_over_alpha, ..., or DEVICE.elongation, DEVICE.force"
std::string study_quantity_names();

// The columns of a study's results (CSV, figure data, Python rows): the
// schema's study quantities that some variant reports, then each joint's
// above the base (jointK.NAME, K = 1 .. the most joints of any variant),
// then each device's quantities, the devices taken over every variant in
// order of first appearance.
struct StudyColumns {
  std::vector<Quantity> quantities;
  std::vector<JointQuantityName> joints;
  std::vector<std::string> devices;
  std::vector<QuantityName> all() const;
  std::vector<std::string> names() const;
  std::size_t size() const { return quantities.size() + joints.size() + devices.size() * device_study_count; }
  // Where a quantity is among the columns (all()'s order); none when it is not one of them.
  std::optional<std::size_t> index(const QuantityName& q) const;
  // A run's peaks in the columns' order: NaN where its model does not report one.
  std::vector<double> values(const RunResult& run) const;
};
StudyColumns study_columns(const Study& study);

// A finished job as a study carries it from its run to the writers that
// format it (rocking.study_files: the study's CSV, the per-record figures'
// data, Python's rows) and to the summary: its level, its peaks in the order
// of the study's columns, and how it ended. A job that could not run (an
// error row) has no peaks.
struct StudyRow {
  double level = 0;
  std::vector<double> values;  // StudyColumns order: NaN where the run's model does not report one
  Outcome outcome = Outcome::completed;
  bool ran = false;  // false: the job could not run (JobResult::error), or no job's row yet
  // Past every limit (overturned, or a joint separated): a study's collapse.
  bool collapsed() const { return ran && past_every_limit(outcome); }
  // The peak of a quantity by name: NaN when it is not one of the columns or the run has none.
  double value(const StudyColumns& columns, const QuantityName& q) const;
};
// The job's row: its level, the run's peaks (none for an error), its outcome.
StudyRow study_row(const StudyColumns& columns, const Job& job, const JobResult& result);

// How a record that survives a level above its first overturning (a
// "resurrection") counts there. first, the convention of Vamvatsikos &
// Cornell (2002) and the default: a record's IDA curve is collapsed from its
// first overturning on (its capacity), and a limit state once reached stays
// reached at every higher level. keep: each level counts as it ran.
enum class Resurrection { first, keep };
// "first" or "keep"; InputError naming --resurrection otherwise.
Resurrection parse_resurrection(std::string_view text);

// How fragilities are fitted beyond the data: the bootstrap over records
// (draws 0: none) and the modelling dispersion added to beta (FEMA P-695).
struct FragilityOptions {
  BootstrapOptions bootstrap;
  double beta_modelling = 0;
};
// InputError naming --bootstrap or --beta-modelling.
void check_fragility_options(const FragilityOptions& o);

// A limit state's fragility over a suite: each record's capacity, the stripes,
// both lognormal fits and their bootstrap over records (rocking.fragility).
struct LimitFragility {
  Limit limit;
  std::vector<std::pair<std::size_t, Capacity>> capacities;  // (record, capacity) of each record that ran
  std::vector<Stripe> stripes;
  LognormalFit capacity_fit, stripes_fit;
  FitBootstrap capacity_bootstrap, stripes_bootstrap;
  double beta_modelling = 0;
};
// The fragility of capacities alone (a hunt's): the capacity fit and its
// bootstrap; no stripes.
LimitFragility capacity_fragility(const Limit& limit, std::vector<std::pair<std::size_t, Capacity>> capacities,
                                  const FragilityOptions& options);
// A fit as JSON (summary.json's capacity_fit and stripes_fit, Python's
// dicts): method, fitted, records, reached, note; when fitted, median, beta,
// log_median_se, beta_se, beta_modelling and beta_total = sqrt(beta^2 +
// beta_modelling^2); when bootstrapped, median_interval, beta_interval and
// beta_total_interval ([low, high]) and bootstrap {draws, fitted, level, seed}.
nlohmann::json fit_json(const LognormalFit& fit, const FitBootstrap& bootstrap, double beta_modelling);
// limit, capacity_fit, stripes_fit, capacities ({record: ids[r], level,
// reached}) and stripes ({level, runs, reached}); no stripes_fit and stripes
// for capacities alone.
nlohmann::json fragility_json(const LimitFragility& f, const std::vector<std::string>& ids);

// What a suite study reports (MODEL.md 13), gathered job by job: a few
// numbers per job are kept, never a run's history. Failed jobs are left out.
class StudySummary {
 public:
  StudySummary(const Study& study, std::vector<double> levels, std::vector<Limit> limits,
               Resurrection resurrection = Resurrection::first);
  void add(const Job& job, const JobResult& result);
  // A row as a study carries it (a job's, or one read back from its CSV); an error row is left out.
  void add(const Job& job, const StudyRow& row);
  const std::vector<double>& levels() const { return levels_; }  // ascending
  const std::vector<Limit>& limits() const { return limits_; }
  Resurrection resurrection() const { return resurrection_; }
  // At each level, the 16/50/84 % fractiles of a peak over the records that
  // ran there, an overturned run counted as +inf (a +inf fractile is a
  // collapse); under Resurrection::first a record that overturned at a lower
  // level counts as overturned.
  struct FractileRow {
    double level = 0;
    std::size_t runs = 0, collapsed = 0;
    std::array<double, 3> edp{};  // 16, 50, 84 %
  };
  std::vector<FractileRow> fractiles(std::size_t variant, const QuantityName& q) const;
  // A record's IDA curve: (level, peak) up to its first overturning, and the
  // level of that overturning (NaN if none).
  struct Curve {
    std::vector<std::pair<double, double>> points;
    double collapse_level = std::numeric_limits<double>::quiet_NaN();
  };
  Curve curve(std::size_t record, std::size_t variant, const QuantityName& q) const;
  // Per record that ran: the lowest level at which it reached the limit, or
  // the highest level it ran to without, censored.
  std::vector<std::pair<std::size_t, Capacity>> capacities(std::size_t variant, std::size_t limit) const;
  // Per level: how many records ran, how many reached the limit (as the
  // convention counts them).
  std::vector<Stripe> stripes(std::size_t variant, std::size_t limit) const;
  // Capacities, stripes, their fits and (bootstrap.draws > 0) their
  // bootstrap over the records that ran.
  LimitFragility fragility(std::size_t variant, std::size_t limit, const FragilityOptions& options) const;
  // The records that overturned and then survived a higher level: each with
  // its first overturning and the levels above it that it survived.
  struct Resurrections {
    std::size_t record = 0;
    double first_overturning = 0;
    std::vector<double> survived;
  };
  std::vector<Resurrections> resurrections(std::size_t variant) const;

 private:
  struct Cell {
    StudyRow row;
    bool ran = false;
  };
  double value(const Cell& c, const QuantityName& q) const { return c.row.value(columns_, q); }
  const Cell& cell(std::size_t record, std::size_t variant, std::size_t level) const {
    return cells_[(record * variants_ + variant) * levels_.size() + level];
  }
  bool reached(const Cell& c, const Limit& l) const;
  // [record][level]: -1 not run, 1 at the limit (by the convention), 0 not.
  std::vector<std::vector<signed char>> limit_table(std::size_t variant, const Limit& limit) const;
  // The stripes over these records (repeats counted).
  std::vector<Stripe> stripes_of(const std::vector<std::vector<signed char>>& table,
                                 const std::vector<std::size_t>& records) const;
  std::size_t records_ = 0, variants_ = 0;
  std::vector<double> levels_;
  std::vector<Limit> limits_;
  Resurrection resurrection_ = Resurrection::first;
  StudyColumns columns_;
  std::vector<Cell> cells_;  // [record][variant][level]
};

// The overturning spectrum of a rigid block under pulses (Housner 1963;
// Makris & Roussos 2000; Zhang & Makris 2001), the classic teaching figure:
// on a grid of pulse frequency over p and amplitude over g tan(alpha), does
// the block lift, and does it overturn? p^2 = m g R / J_p is the block's
// frequency parameter (Housner 1963; R from the pivot to the centre of
// gravity). The block's lengths are scaled by `size` (the same
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
  std::size_t complete = 0;           // points [0, complete) are computed (all, unless stopped)
};
// The normalised axes' scale of a rigid scene whose lengths are scaled by
// `size` (the same slenderness): Housner's p and the block's alpha; on
// [columns] (MODEL.md 16), the rigid frame's p-hat, p^2 (1 + 2 gamma) /
// (1 + 3 gamma), and its columns' alpha, which make the frame's equation of
// motion the single block's.
struct SpectrumScale {
  double p = 0, alpha = 0;
};
SpectrumScale spectrum_scale(const Scene& rigid_block, double size);
// rigid_block must be a rigid scene, on its base or on [columns]. Runs on
// `threads` threads; progress(done, total).
// `done`: the outcomes (uplift, overturned) of the first points from an
// earlier, stopped computation, taken as they are. When stop() turns true no
// new point starts; `complete` says how far the points go.
BlockSpectrum overturning_spectrum(const Scene& rigid_block, double size, PulseShape pulse,
                                   const std::vector<double>& frequency_ratios,
                                   const std::vector<double>& amplitude_ratios, int threads,
                                   const std::function<void(std::size_t, std::size_t)>& progress = {},
                                   const std::vector<std::pair<bool, bool>>& done = {},
                                   const std::function<bool()>& stop = {});

}  // namespace rocking
