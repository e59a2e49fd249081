// `rocking ida` and `rocking sweep`: many runs at once (the paper's Figs. 5-8),
// over a suite of records scaled to an intensity measure. Jobs run on a
// thread pool (and across MPI ranks under mpirun); rows are written in job
// order, so the CSV does not depend on how the work was split. Wall times go
// to a separate timing.csv for that reason. The suite's summaries and figures
// are study_report.cpp's.
#include "commands.hpp"
#include "study_folder.hpp"
#include "study_report.hpp"
#include "mpi_jobs.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <limits>
#include <csignal>
#include <sstream>
#include <fstream>
#include <memory>
#include <map>
#include <optional>
#include <tuple>
import rocking.study;
import rocking.errors;
import rocking.study_run;
import rocking.plot;
import rocking.records;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct StudyArgs {
  SceneOptions scene;
  std::vector<std::string> records;
  std::string suite;
  RecordFileOptions file;
  std::string vertical;  // the vertical component of each record's file
  std::string azimuths;  // the plane's azimuths [degrees]: each record projected at each
  bool pairs = false;    // the records are pairs of files, a record's two horizontal components
  std::string im = "sf";
  double damping = 0.05;
  std::string levels, scales;
  std::vector<std::string> variants;
  std::vector<std::string> limits;
  std::vector<Limit> limit_states;  // --limit as parsed, before any record is read (check_study_args)
  std::string resurrection = "first";
  long bootstrap = 1000;
  unsigned long seed = 20020101;
  double beta_modelling = 0;
  int threads = 0;
  std::string out;
  SolverOptions solver;
  bool hunt = false;
  // NaN: derived from the first level (see --help).
  double hunt_step = std::nan(""), hunt_max = std::nan(""), precision = std::nan(""), fill_step = std::nan("");
  double hunt_growth = 1.5;
  std::string formats = "png,pdf,svg";
  std::string log_axes = "auto";
  bool no_plot = false;
  bool per_record = false;
  bool resume = false;
  double max_runs = 1e5;  // a ladder beyond it (minutes to hours of runs) needs the option raised
  std::string scene_text;  // the scene after the overrides every run shares (make_study)
};

FragilityOptions fragility_options(const StudyArgs& a) {
  if (a.bootstrap < 0) throw InputError(fmt::format("--bootstrap {}: must be 0 (none) or a number of resamples", a.bootstrap));
  FragilityOptions o;
  o.bootstrap.draws = static_cast<std::size_t>(a.bootstrap);
  o.bootstrap.seed = a.seed;
  o.beta_modelling = a.beta_modelling;
  check_fragility_options(o);
  return o;
}

// The inputs that make a study what it is (study_folder.hpp).
std::string inputs_of(const StudyArgs& a, const Study& st, const std::string& kind) {
  std::string variants;
  for (const Variant& v : st.variants()) variants += (variants.empty() ? "" : ",") + v.name;
  const SolverOptions& s = a.solver;
  return study_inputs(kind, a.scene_text, st.records(),
                      {{"record options", fmt::format("format {}, component {}, units {}, dt {}{}{}{}", a.file.format,
                                                      a.file.component, a.file.units, a.file.dt,
                                                      a.vertical.empty() ? "" : ", vertical " + a.vertical,
                                                      a.azimuths.empty() ? "" : ", azimuths " + a.azimuths + (a.pairs ? ", pairs" : ""),
                                                      a.file.process.empty() ? "" : ", process " + a.file.process)},
                       {"im", fmt::format("{} (damping {})", a.im, a.damping)},
                       {"levels", a.scales.empty() ? a.levels : "scales " + a.scales},
                       {"variants", variants},
                       {"integrator", fmt::format("{}, rtol {}, atol {}, duration {}, max-events {}, max-steps {}{}",
                                                  s.integrator, s.rtol, s.atol, s.duration.value_or(0.0),
                                                  s.max_events, s.max_steps, s.integrate_contact ? ", integrate-contact" : "")},
                       {"hunt", a.hunt ? fmt::format("step {}, growth {}, max {}, precision {}, fill {}", a.hunt_step,
                                                     a.hunt_growth, a.hunt_max, a.precision, a.fill_step)
                                       : std::string("no")}});
}

// The levels: --levels, or --scales for the scale factor; 1:20:1 by default
// for the scale factor, required for any other IM.
std::vector<double> study_levels(const StudyArgs& a, const IntensityMeasure& im) {
  if (!a.scales.empty() && !a.levels.empty()) throw InputError("--scales and --levels: give one (--scales is --levels of the scale factor)");
  if (!a.scales.empty() && im.kind != IntensityMeasure::Kind::scale_factor)
    throw InputError(fmt::format("--scales with --im {}: give the levels of the IM as --levels", im.name()));
  const std::string flag = a.scales.empty() ? "--levels" : "--scales";
  std::string text = a.scales.empty() ? a.levels : a.scales;
  if (text.empty()) {
    if (im.kind != IntensityMeasure::Kind::scale_factor)
      throw InputError(fmt::format("--im {}: give the levels to scale to as --levels (e.g. --levels 0.05:1.5:0.05, in {})",
                                   im.name(), im.unit()));
    text = "1:20:1";
  }
  const std::vector<double> levels = number_list(flag, text);
  for (double l : levels)
    if (!(l > 0)) throw InputError(fmt::format("{} {}: every level must be positive (got {:g})", flag, text, l));
  return levels;
}

// A row of a per-record figure's data: the level, the study's columns (empty
// where the run has none), the collapse code (plot::Collapse).
std::string figure_data_row(const StudyRow& row, plot::Collapse code) {
  std::string out = fmt::format("{:.9g}", row.level);
  for (double v : row.values) out += "," + peak_field(v);
  return out + fmt::format(",{}\n", static_cast<unsigned>(code));
}

// One data file per (record, variant) and one figure per record: peaks
// against the scale, with each variant's first overturning drawn as collapse.
// rows: every job's, as written (the runs that could not run are left out).
void study_figures(const StudyArgs& a, const Study& st, const StudyColumns& columns,
                   const std::vector<std::string>& ids, const std::vector<Job>& jobs,
                   const std::vector<StudyRow>& rows, const std::string& kind, const std::string& scene_name) {
  const fs::path dir(a.out);
  // One panel per scalar study quantity that some variant reports; the
  // devices' peaks are in the data files and the CSV.
  std::vector<std::size_t> shown;  // indices into columns.quantities
  for (std::size_t k = 0; k < columns.quantities.size(); ++k)
    for (std::size_t v = 0; v < st.variants().size(); ++v)
      if (st.reports(v, columns.quantities[k])) {
        shown.push_back(k);
        break;
      }
  std::vector<plot::Panel> panels;
  std::vector<bool> force_like;  // forces, moments, accelerations: the panels --log may make logarithmic
  for (std::size_t k : shown) {
    const QuantityName q(columns.quantities[k]);
    panels.push_back({"peak " + axis_label(q), plot::column("level"),
                      fmt::format("{}*{:.9g}", plot::column(q.name()), figure_factor(q)), true, ""});
    const std::string_view unit = q.unit();
    force_like.push_back(unit == "V_ref" || unit == "M_ref" || unit == "N" || unit == "N m" || unit == "m/s2");
  }
  const std::string header = fmt::format("level,{},collapse\n", fmt::join(columns.names(), ","));
  for (std::size_t r = 0; r < st.records().size(); ++r) {
    std::string stem = ids[r];
    for (char& c : stem)
      if (c == '/' || c == '#' || static_cast<unsigned char>(c) < 0x20) c = '_';
    stem = fs::path(stem).replace_extension().string();
    const std::string name = kind + "_" + stem;
    make_output_dir(dir / (name + ".data"));
    std::vector<plot::Series> series;
    for (std::size_t v = 0; v < st.variants().size(); ++v) {
      const std::string file = (fs::path(name + ".data") / (fmt::format("{}.csv", v))).string();
      std::ofstream out(dir / file);
      out << header;
      int written = 0;
      bool fallen = false;
      unsigned codes = 0;
      std::vector<double> levels;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (jobs[i].record != r || jobs[i].variant != v || !rows[i].ran) continue;
        const bool down = rows[i].collapsed();
        const plot::Collapse code = plot::collapse_of(down, fallen);
        fallen = fallen || down;
        codes |= code != plot::Collapse::standing ? plot::collapse_bit(code) : 0u;
        levels.push_back(jobs[i].level);
        out << figure_data_row(rows[i], code);
        ++written;
      }
      if (written == 0) continue;
      plot::Series s{variant_label(st.variants()[v].name), file, {}, fallen ? "collapse" : ""};
      s.collapse_codes = codes;
      // The variants' collapse markers side by side: a fifth of the levels' spacing apart.
      std::ranges::sort(levels);
      double spacing = 0;
      for (std::size_t i = 1; i < levels.size(); ++i)
        if (const double d = levels[i] - levels[i - 1]; d > 0 && (spacing == 0 || d < spacing)) spacing = d;
      s.dodge = 0.2 * spacing * (static_cast<double>(v) - 0.5 * static_cast<double>(st.variants().size() - 1));
      for (std::size_t p = 0; p < shown.size(); ++p)  // what the variant does not have (a fixed base's rocking)
        if (!st.reports(v, columns.quantities[shown[p]])) s.absent.push_back(p);
      series.push_back(std::move(s));
    }
    if (series.empty()) continue;
    // --log auto: a force-like panel whose positive peaks over every variant
    // of this record span more than a decade.
    std::vector<plot::Panel> record_panels = panels;
    for (std::size_t p = 0; p < shown.size(); ++p) {
      if (!force_like[p] || a.log_axes == "off") continue;
      const QuantityName q(columns.quantities[shown[p]]);
      double low = std::numeric_limits<double>::infinity(), high = 0;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (jobs[i].record != r || !rows[i].ran) continue;
        const double v = std::abs(rows[i].value(columns, q));  // NaN where the run has none
        if (v > 0 && std::isfinite(v)) {
          low = std::min(low, v);
          high = std::max(high, v);
        }
      }
      record_panels[p].log_y = a.log_axes == "on" ? high > 0 : high > 10 * low;
    }
    plot::Figure fig;
    fig.dir = dir;
    fig.name = name;
    fig.formats = plot::parse_formats(a.formats);
    const int rows = static_cast<int>((panels.size() + 1) / 2);
    fig.width = 1100;
    fig.height = 325 * rows;
    const GroundMotion* motion = st.motion(r);
    fig.title = fmt::format("{}: {}\n{}", scene_name,
                            kind == "ida" ? "incremental dynamic analysis" : "parametric study",
                            motion != nullptr ? motion_title(*motion) : ids[r]);
    for (const fs::path& f : plot::render_panels(fig, rows, 2, im_axis_label(st.intensity_measure()), record_panels, series))
      fmt::print("wrote {}\n", f.string());
  }
}

// What an earlier, interrupted run of the same study left in DIR: its rows are
// the first jobs in order (rows are written in job order), each checked
// against the job it must be; rows: their text, kept as it is; results: each
// read back.
struct Resumed {
  std::vector<std::string> rows, timings;
  std::vector<StudyRow> results;
};
Resumed read_resumed(const fs::path& csv_file, const fs::path& timing_file, const std::vector<Job>& jobs,
                     const std::vector<std::string>& ids, const Study& st, const StudyColumns& columns) {
  Resumed r;
  // A study ended by a second signal (or killed) left its rows in the .partial
  // files: whole rows, and at most one cut line at the end.
  const fs::path rows_file = resume_source(csv_file);
  std::ifstream in(rows_file);
  if (!in) throw InputError(fmt::format("--resume: {} not found: nothing to resume", csv_file.string()));
  ResumedRows kept = read_resumed_rows(in, rows_file.string(), jobs, ids, st, columns);
  if (!kept.rerun.empty()) log::warn("{}", kept.rerun);
  r.rows = std::move(kept.rows);
  r.results = std::move(kept.results);
  std::string line;
  std::ifstream timing(resume_source(timing_file));
  if (timing && std::getline(timing, line))
    while (r.timings.size() < r.rows.size() && std::getline(timing, line)) r.timings.push_back(line + "\n");
  return r;
}

// " (records that could not be read: a.at2, b.txt)", or nothing.
std::string unreadable(const Study& st, const std::vector<std::string>& ids) {
  std::string out;
  for (std::size_t r = 0; r < ids.size(); ++r)
    if (!st.record_error(r).empty()) out += (out.empty() ? "" : ", ") + ids[r];
  return out.empty() ? out : " (records that could not be read: " + out + ")";
}

void write_azimuth_summary(const fs::path& study_csv, const fs::path& out);

// A ladder as it will run, everything it is refused for checked before any
// run: its levels (the largest checked against the study), the fragility's
// options, the resurrection rule, its jobs (at most --max-runs), the figures'
// formats, and --resume under mpirun.
struct LadderPlan {
  FragilityOptions fragility;
  Resurrection resurrection = Resurrection::first;
  Ladder ladder;
  std::vector<std::string> ids;  // the records' ids, as rows name them
  int threads = 1;
};

LadderPlan plan_study_ladder(const StudyArgs& a, const Study& st, const MpiWorld& world) {
  const std::vector<double> levels = study_levels(a, st.intensity_measure());
  LadderPlan plan;
  plan.fragility = fragility_options(a);
  plan.resurrection = parse_resurrection(a.resurrection);
  plan.ladder = plan_ladder(st, levels, a.limit_states);
  st.check_level(*std::max_element(levels.begin(), levels.end()), a.scales.empty() ? "--levels" : "--scales");
  const std::size_t jobs = plan.ladder.jobs.size();
  if (static_cast<double>(jobs) > a.max_runs)
    throw InputError(fmt::format("{} runs ({} records x {} levels x {} variants): more than --max-runs {:g}; raise it "
                                 "to run them all",
                                 jobs, st.records().size(), levels.size(), st.variants().size(), a.max_runs));
  plan.ids = record_ids(st.records());
  plan.threads = thread_count(a.threads);
  if (!a.no_plot) plot::parse_formats(a.formats);
  if (a.resume && world.size > 1) throw InputError("--resume: run it as one process (not under mpirun)");
  return plan;
}

// The study's folder, claimed by rank 0: made, locked against a second study
// writing into it, its files checked free (or those of the study resumed),
// and the inputs that make the study what it is recorded. The lock is held
// while the answer lives.
std::unique_ptr<FolderLock> claim_study_folder(const StudyArgs& a, const Study& st, const std::string& kind,
                                               const MpiWorld& world) {
  if (world.rank != 0) return nullptr;
  const fs::path dir(a.out);
  make_output_dir(dir);
  auto lock = std::make_unique<FolderLock>(dir);
  check_outputs_free(dir, {kind + ".csv", kind + ".csv.partial", "timing.csv", "timing.csv.partial", "records.csv",
                           "summary.csv", "fragility.csv", "fragility_points.csv", "summary.json", "inputs.txt"});
  record_inputs(dir, inputs_of(a, st, kind), a.resume);
  return lock;
}

// The jobs this process runs, from the first not done before: under mpirun
// rank r runs the jobs i with i % size == r.
std::vector<std::size_t> jobs_of_this_rank(std::size_t first, std::size_t count, const MpiWorld& world) {
  std::vector<std::size_t> mine;
  for (std::size_t i = first; i < count; ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(world.size)) == world.rank) mine.push_back(i);
  return mine;
}

// Where a ladder's rows go as they come. A single process streams its rows
// and timings (a long study shows them as they come) into temporary files,
// renamed when the study ends or stops, and keeps of each job only its cell of
// the summary (and its row when it draws one figure per record): memory does
// not grow with the number of jobs. Under mpirun each rank keeps its rows'
// text; rank 0 gathers them, writes them in job order and reads them back.
class LadderSink {
 public:
  LadderSink(const Study& st, const LadderPlan& plan, const fs::path& csv_file, const fs::path& timing_file,
             bool one_figure_per_record, const MpiWorld& world)
      : summary(st, plan.ladder.levels, plan.ladder.limits, plan.resurrection),
        per_record_figures(one_figure_per_record),
        figure_rows(one_figure_per_record ? plan.ladder.jobs.size() : 0),
        st_(st), plan_(plan), world_(world), csv_file_(csv_file), timing_file_(timing_file),
        partial_(csv_file.string() + ".partial"), timing_partial_(timing_file.string() + ".partial") {}

  StudySummary summary;
  const bool per_record_figures;
  std::vector<StudyRow> figure_rows;  // every job's row when one figure per record is drawn
  std::size_t failed = 0;             // runs that could not run

  // The rows an interrupted study left, counted as if they had just run; a
  // single process opens its files with them (rank 0 under mpirun opens its
  // after the gather).
  void start(const Resumed& resumed) {
    const std::size_t first = resumed.rows.size();
    for (std::size_t i = 0; i < first; ++i) count(i, resumed.results[i]);
    if (world_.size != 1) return;
    open();
    if (!csv_ || !timing_) throw InputError(fmt::format("{}: cannot write", (!csv_ ? partial_ : timing_partial_).string()));
    for (const std::string& r : resumed.rows) csv_ << r;
    csv_ << std::flush;
    for (std::size_t i = 0; i < first; ++i) timing_ << (i < resumed.timings.size() ? resumed.timings[i] : std::string());
  }

  // What a single process's run adds to the summary as it emits (none under
  // mpirun: rank 0 adds the rows it reads back).
  StudySummary* summary_of_runs() { return world_.size == 1 ? &summary : nullptr; }

  // Job i's result, as the ladder emits it in job order.
  void emit(std::size_t i, const JobResult& r) {
    const Job& job = plan_.ladder.jobs[i];
    const std::string text = study_csv_row(st_, plan_.ladder.columns, plan_.ids, job, r);
    const std::string time = fmt::format("{},{:.6f}\n", job_fields(st_, plan_.ids, job), r.run.wall_s);
    if (world_.size == 1) {
      csv_ << text << std::flush;
      timing_ << time;
      failed += r.error.empty() ? 0 : 1;
      if (per_record_figures) figure_rows[i] = written_row(plan_.ladder.columns, job, r);
    } else {
      rows_.emplace_back(static_cast<long>(i), text);
      timings_.emplace_back(static_cast<long>(i), time);
    }
  }

  // Under mpirun, every rank's rows to rank 0, written there in job order.
  void gather() {
    if (world_.size == 1) return;
    gathered_ = gather_rows(world_, rows_);
    MpiRows all_timings = gather_rows(world_, timings_);
    std::sort(gathered_.begin(), gathered_.end());
    std::sort(all_timings.begin(), all_timings.end());
    if (world_.rank != 0) return;
    open();
    for (const auto& [i, text] : gathered_) csv_ << text;
    for (const auto& [i, text] : all_timings) timing_ << text;
  }

  // The temporary files closed and renamed into place (rank 0).
  void close() {
    csv_.close();
    timing_.close();
    if (!csv_ || !timing_) throw RunError(fmt::format("{}: cannot write", (!csv_ ? partial_ : timing_partial_).string()));
    fs::rename(partial_, csv_file_);
    fs::rename(timing_partial_, timing_file_);
  }

  // Under mpirun, rank 0 reads back the rows the ranks wrote into the summary.
  void read_back_gathered() {
    for (const auto& [i, text] : gathered_) count(static_cast<std::size_t>(i), read_study_row(plan_.ladder.columns, text));
  }

 private:
  static constexpr const char* timing_header = "record,scale,variant,im,level,record_im,wall_s\n";

  // The temporary files, with their headers; a file that cannot be written
  // shows when they are closed.
  void open() {
    csv_.open(partial_);
    timing_.open(timing_partial_);
    csv_ << study_csv_header(plan_.ladder.columns);
    timing_ << timing_header;
  }

  // A row read back (resumed, or gathered) into the summary and the counts.
  void count(std::size_t i, const StudyRow& row) {
    summary.add(plan_.ladder.jobs[i], row);
    failed += row.ran ? 0 : 1;
    if (per_record_figures) figure_rows[i] = row;
  }

  const Study& st_;
  const LadderPlan& plan_;
  const MpiWorld& world_;
  fs::path csv_file_, timing_file_, partial_, timing_partial_;
  std::ofstream csv_, timing_;
  MpiRows rows_, timings_, gathered_;
};

// A study stopped by a signal before its last job: what holds the runs done,
// how to go on, and the signal's exit code.
int report_stopped(std::size_t done, std::size_t jobs, const fs::path& csv_file) {
  const int signal = stop_signal();
  fmt::print(stderr, "rocking: stopped by {} after {} of {} runs; {} holds them; continue with the same command and "
                     "--resume\n",
             stop_signal_name(signal), done, jobs, csv_file.string());
  return stop_exit_code(signal);
}

// A finished ladder's report (summary.csv, the fragility fits, summary.json)
// and figures: one per record for a few records (the paper's Figs. 5-8); the
// suite's (every record, fractiles, fragility) for two or more. The exit
// code: 4 when some runs failed.
int report_ladder(const StudyArgs& a, const Study& st, const LadderPlan& plan, const LadderSink& sink,
                  const std::string& kind, const std::string& scene_name, const fs::path& csv_file) {
  const fs::path dir(a.out);
  const std::vector<Job>& jobs = plan.ladder.jobs;
  fmt::print("wrote {} ({} runs)\n", csv_file.string(), jobs.size());
  const SuiteFragility fragility = suite_fragility(st, sink.summary, plan.fragility, plan.threads);
  const StudyReport report = ladder_report(st, sink.summary, fragility, plan.ids);
  for (const std::string& note : report.notes) fmt::print("{}\n", note);
  write_report(dir, report);
  fmt::print("wrote {} (16/50/84 % fractiles), {}, {}, {}\n", (dir / "summary.csv").string(),
             (dir / "fragility.csv").string(), (dir / "fragility_points.csv").string(), (dir / "summary.json").string());
  if (!a.no_plot) {
    if (sink.per_record_figures)
      study_figures(a, st, plan.ladder.columns, plan.ids, jobs, sink.figure_rows, kind, scene_name);
    if (st.records().size() >= 2)
      for (const fs::path& f : draw_ladder_report(dir, st, sink.summary, fragility, kind, scene_name, plot::parse_formats(a.formats)))
        fmt::print("wrote {}\n", f.string());
  }
  if (sink.failed > 0) {
    fmt::print(stderr, "rocking: {} of {} runs failed{}: see the error column of {}\n", sink.failed, jobs.size(),
               unreadable(st, plan.ids), csv_file.string());
    return exit_jobs_failed;
  }
  return 0;
}

// A ladder of runs (ida, sweep): planned and refused before any run, the
// folder claimed, an interrupted study's rows taken up (--resume), the jobs
// run with their rows streamed in job order (and gathered under mpirun), the
// files renamed into place, and, unless a signal stopped it, the report.
int run_ladder(const StudyArgs& a, const Study& st, const std::string& kind, const std::string& scene_name,
               const MpiWorld& world) {
  const LadderPlan plan = plan_study_ladder(a, st, world);
  const std::vector<Job>& jobs = plan.ladder.jobs;
  const fs::path dir(a.out), csv_file = dir / (kind + ".csv"), timing_file = dir / "timing.csv";
  const std::unique_ptr<FolderLock> lock = claim_study_folder(a, st, kind, world);
  const Resumed resumed = a.resume ? read_resumed(csv_file, timing_file, jobs, plan.ids, st, plan.ladder.columns)
                                   : Resumed{};
  const std::size_t first = resumed.rows.size();
  if (world.size == 1) catch_stop_signals();
  const std::vector<std::size_t> mine = jobs_of_this_rank(first, jobs.size(), world);
  if (world.rank == 0)
    log::info("{}: {} jobs on {} thread(s){}{}", kind, jobs.size() - first, plan.threads,
                 world.size > 1 ? fmt::format(" x {} processes", world.size) : "",
                 first > 0 ? fmt::format(" ({} done before, resumed)", first) : "");
  const bool per_record_figures = !a.no_plot && (st.records().size() <= 3 || a.per_record);
  LadderSink sink(st, plan, csv_file, timing_file, per_record_figures, world);
  sink.start(resumed);
  Progress progress(world.rank == 0 && log::shows(log::Level::info));
  // Rows in job order up to the first run a stop cut short: that one and any
  // after it are left for --resume (rocking.study_run).
  const std::size_t emitted = rocking::run_ladder(
      st, plan.ladder, mine, plan.threads, sink.summary_of_runs(),
      [&](std::size_t i, const JobResult& r) { sink.emit(i, r); },
      {.progress = [&](std::size_t done, std::size_t total) { progress(done, total); },
       .stop = [] { return stop_signal() != 0; }});
  sink.gather();
  if (world.rank != 0) return 0;
  sink.close();
  if (!a.azimuths.empty()) write_azimuth_summary(csv_file, dir / "azimuths.csv");
  // What each record id is, as its file says (rows name records by id).
  write_text(dir / "records.csv", records_csv(st, plan.ids));
  // Stopped by a signal (one process: mine is every job left).
  if (emitted < mine.size()) return report_stopped(first + emitted, jobs.size(), csv_file);
  sink.read_back_gathered();
  return report_ladder(a, st, plan, sink, kind, scene_name, csv_file);
}

// A hunt's options: the first level starts it; the others default to
// multiples of it (step = first, precision = first / 20, fill = first / 10,
// max = 50 x first).
HuntOptions hunt_options(const StudyArgs& a, const Study& st) {
  auto given = [](double v) { return std::isnan(v) ? std::nullopt : std::optional<double>(v); };
  return rocking::hunt_options(study_levels(a, st.intensity_measure()).front(), given(a.hunt_step), a.hunt_growth,
                               given(a.hunt_max), given(a.precision), given(a.fill_step));
}

// The hunts an interrupted hunt finished (hunt.csv, or the .partial file a
// killed one left), in order, each checked against the pair it must be; what
// the report needs of each read back from its row.
std::vector<std::pair<std::string, HuntResult>> read_resumed_hunts(
    const fs::path& file, const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
    const std::vector<std::string>& ids, const Study& st) {
  const fs::path rows_file = resume_source(file);
  std::ifstream in(rows_file);
  if (!in) throw InputError(fmt::format("--resume: {} not found: nothing to resume", file.string()));
  std::string line;
  if (!std::getline(in, line) || line + "\n" != hunt_csv_header)
    throw InputError(fmt::format("--resume: {}:1: not a hunt CSV of this version (header differs)", rows_file.string()));
  // The fields after a row's hunt_fields (record, variant, im, which may be
  // quoted), by the header's names.
  const std::vector<std::string> names = csv_fields(hunt_csv_header.substr(0, hunt_csv_header.size() - 1));
  const auto header_index = [&](std::string_view name) {
    return static_cast<std::size_t>(std::ranges::find(names, name) - names.begin());
  };
  const auto at = [&](std::string_view name) { return header_index(name) - (header_index("im") + 1); };
  const std::size_t collapse = at("collapse_level"), survived = at("survived_level"), run_count = at("runs"),
                    error = at("error");
  std::vector<std::pair<std::string, HuntResult>> out;
  for (int n = 2; std::getline(in, line); ++n) {
    if (in.eof()) break;  // a last line without its newline was cut: hunt it again
    const std::size_t k = out.size();
    const std::string prefix = k < pairs.size() ? hunt_fields(ids[pairs[k].first], st.variants()[pairs[k].second].name,
                                                              st.intensity_measure())
                                                : std::string();
    const std::string rest = k < pairs.size() && line.starts_with(prefix) ? line.substr(prefix.size()) : std::string();
    const std::vector<std::string> f = csv_fields(rest);
    if (f.size() <= error)
      throw InputError(fmt::format("--resume: {}:{}: this row is not hunt {} of this study", rows_file.string(), n, k + 1));
    // Its levels and count are finite numbers: a row holding anything else
    // (nan, inf, text) is hunted again, with every one after it.
    auto number = [&](const std::string& text, double& v) {
      char* end = nullptr;
      v = std::strtod(text.c_str(), &end);
      return !text.empty() && end == text.c_str() + text.size() && std::isfinite(v);
    };
    HuntResult h;
    double runs = 0;
    h.collapsed = !f[collapse].empty();
    if ((h.collapsed && !number(f[collapse], h.collapse_level)) ||
        (!f[survived].empty() && !number(f[survived], h.survived_level)) || !number(f[run_count], runs) || runs < 0 ||
        runs > 1e9) {
      log::warn("--resume: {}:{}: not a whole hunt row (collapse '{}', survived '{}', runs '{}'): hunt {} runs "
                   "again, with the {} after it", rows_file.string(), n, f[collapse], f[survived], f[run_count], k + 1,
                   pairs.size() - k - 1);
      break;
    }
    h.runs = static_cast<int>(runs);
    std::size_t from = 0;  // the error, last, may hold commas (quoted): the rest of the row after its field's comma
    for (std::size_t comma = 0; comma < error; ++comma) from = rest.find(',', from) + 1;
    h.fixed_base = !st.can_overturn(pairs[k].second);
    if (!h.fixed_base) h.error = rest.substr(from);  // a fixed base's row says why it was not run
    out.emplace_back(line + "\n", std::move(h));
  }
  return out;
}

int run_hunt(const StudyArgs& a, const Study& st) {
  const fs::path dir(a.out), file = dir / "hunt.csv", partial = file.string() + ".partial";
  const HuntOptions o = hunt_options(a, st);
  const FragilityOptions fragility_opts = fragility_options(a);
  st.check_level(o.max, "--hunt-max");
  make_output_dir(dir);
  const FolderLock lock(dir);
  check_outputs_free(dir, {"hunt.csv", "hunt.csv.partial", "hunt_points.csv", "hunt_points.csv.partial", "records.csv",
                           "fragility.csv", "fragility_points.csv", "summary.json", "inputs.txt"});
  record_inputs(dir, inputs_of(a, st, "ida --hunt"), a.resume);
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t r = 0; r < st.records().size(); ++r)
    for (std::size_t v = 0; v < st.variants().size(); ++v) pairs.emplace_back(r, v);
  const std::vector<std::string> ids = record_ids(st.records());
  const IntensityMeasure& im = st.intensity_measure();
  const std::string unit = im.unit().empty() ? "" : " " + im.unit();
  const auto resumed = a.resume ? read_resumed_hunts(file, pairs, ids, st)
                                : std::vector<std::pair<std::string, HuntResult>>{};
  const std::size_t first = resumed.size();
  // Rows stream into the .partial files, renamed when the hunt ends or stops;
  // hunt_points.csv has every level each hunt ran and why.
  const fs::path points_file = dir / "hunt_points.csv", points_partial = points_file.string() + ".partial";
  std::string resumed_points;
  if (a.resume) {
    std::ifstream old(resume_source(points_file));
    std::string line;
    std::getline(old, line);  // the header
    while (std::getline(old, line) && !old.eof())
      for (std::size_t k = 0; k < first; ++k)
        if (line.starts_with(hunt_fields(ids[pairs[k].first], st.variants()[pairs[k].second].name, im))) {
          resumed_points += line + "\n";
          break;
        }
  }
  std::ofstream csv(partial), points(points_partial);
  if (!csv || !points) throw RunError(fmt::format("{}: cannot write", (!csv ? partial : points_partial).string()));
  csv << hunt_csv_header;
  points << hunt_points_header << resumed_points;
  std::vector<HuntResult> hunts;
  int failed = 0;
  for (const auto& [row, h] : resumed) {
    csv << row;
    hunts.push_back(h);
    failed += h.error.empty() ? 0 : 1;
  }
  csv << std::flush;
  log::info("hunt: {} from {:g}{} by a step of {:g} growing x{:g} to {:g}; bracket {:g}; fill below at {:g}{}",
               im.name(), o.first, unit, o.step, o.growth, o.max, o.precision, o.fill_step,
               first > 0 ? fmt::format(" ({} hunts done before, resumed)", first) : "");
  catch_stop_signals();
  Progress progress(log::shows(log::Level::info));
  // Hunts in order up to the first one a stop cut short (its runs stop
  // within a step): that one and any after it are left for --resume
  // (rocking.study_run).
  const std::size_t emitted = run_hunts(
      st, o, first, thread_count(a.threads),
      [&](std::size_t k, const HuntResult& h) {
        const std::string& record = ids[pairs[k].first];
        const std::string variant = st.variants()[pairs[k].second].name;
        failed += h.error.empty() ? 0 : 1;
        csv << hunt_csv_row(h, record, variant, im, o) << std::flush;
        points << hunt_points_rows(h, record, variant, im) << std::flush;
        std::string what;
        if (!h.error.empty()) what = "error: " + h.error;
        else if (h.fixed_base) what = "a fixed base cannot overturn (not run)";
        else if (!h.collapsed)
          what = fmt::format("no overturning up to {} {:.4g}{} ({} runs)", im.name(), h.survived_level, unit, h.runs);
        else  // with joints, a joint separating ends a run as overturning does
          what = fmt::format("{} at {} {:.4g}{} (survives {:.4g}; {} runs){}",
                             st.joints(pairs[k].second) > 0 ? "overturns or separates" : "overturns", im.name(),
                             h.collapse_level, unit,
                             h.survived_level, h.runs,
                             h.resurrections.empty() ? "" : "; survives again above it at " + ranges_text(h.resurrections));
        fmt::print("{} / {}: {}\n", record, variant, what);
        hunts.push_back(h);
      },
      {.progress = [&](std::size_t done, std::size_t total) { progress(done, total); },
       .stop = [] { return stop_signal() != 0; }});
  csv.close();
  points.close();
  if (!csv || !points) throw RunError(fmt::format("{}: cannot write", (!csv ? partial : points_partial).string()));
  fs::rename(partial, file);
  fs::rename(points_partial, points_file);
  write_text(dir / "records.csv", records_csv(st, ids));
  if (first + emitted < pairs.size()) {  // stopped by a signal
    const int signal = stop_signal();
    fmt::print(stderr, "rocking: stopped by {} after {} of {} hunts; {} holds them; continue with the same command and "
                       "--resume\n",
               stop_signal_name(signal), first + emitted, pairs.size(), file.string());
    return stop_exit_code(signal);
  }
  fmt::print("the lowest overturning found, bracketed to {:g}{}; a window narrower than the fill step {:g}{} below it "
             "can be missed\n",
             o.precision, unit, o.fill_step, unit);
  const StudyReport report = hunt_report(st, hunts, ids, fragility_opts);
  for (const std::string& note : report.notes) fmt::print("{}\n", note);
  write_report(dir, report);
  fmt::print("wrote {}, {}\n", file.string(), (dir / "fragility.csv").string());
  if (failed > 0) {
    fmt::print(stderr, "rocking: {} of {} hunts failed{}: see the error column of {}\n", failed, hunts.size(),
               unreadable(st, ids), file.string());
    return exit_jobs_failed;
  }
  return 0;
}

// The records of a study: each --record argument (a file, a folder, a list
// file) and the --suite's list.
// --log's value, refused before any run.
// What can be refused before the scene and the records are read: --log, and
// --limit, parsed here once.
void check_study_args(StudyArgs& a) {
  if (a.log_axes != "auto" && a.log_axes != "on" && a.log_axes != "off")
    throw InputError(fmt::format("--log {}: give auto, on or off", a.log_axes));
  a.limit_states.clear();
  for (const std::string& text : a.limits) a.limit_states.push_back(parse_limit(text));
}

std::vector<std::string> study_records(const StudyArgs& a) {
  std::vector<std::string> out;
  for (const std::string& r : a.records) {
    std::vector<std::string> skipped;
    for (std::string& p : record_paths(r, &skipped)) out.push_back(std::move(p));
    for (const std::string& s : skipped) log::info("{}: skipped (not a record format this program reads)", s);
  }
  if (!a.suite.empty()) {
    const fs::path list = fs::path(ROCKING_SUITES_DIR) / (a.suite + ".txt");
    if (!fs::is_regular_file(list)) {
      std::string names;
      for (const auto& e : fs::directory_iterator(ROCKING_SUITES_DIR))
        if (e.path().extension() == ".txt") names += (names.empty() ? "" : ", ") + e.path().stem().string();
      throw InputError(fmt::format("--suite {}: no such suite (suites: {})", a.suite, names));
    }
    const char* env = std::getenv("ROCKING_RECORDS");
    const fs::path records = env != nullptr && *env != 0 ? fs::path(env) : fs::path(ROCKING_RECORDS_DIR);
    if (!fs::is_directory(records))
      throw InputError(fmt::format("--suite {}: the records folder {} is missing (set ROCKING_RECORDS to where the "
                                   "records are)",
                                   a.suite, records.string()));
    for (std::string& p : read_record_list(list.string(), records.string())) out.push_back(std::move(p));
  }
  if (out.empty()) throw InputError("--record or --suite: give at least one ground-motion file");
  return out;
}

std::unique_ptr<Study> make_study(StudyArgs& a, const std::vector<std::string>& overrides,
                                  std::vector<Variant> variants, std::string& scene_name) {
  const std::vector<std::string> records = study_records(a);
  const Scene scene = load_scene(SceneOptions{a.scene.path, overrides});
  scene_name = scene.name;
  a.scene_text = scene_toml(a.scene.path, overrides);
  const double t1 = scene.structure.rigid ? 0.0 : 1.0 / modal_analysis(scene.structure, scene_devices(scene)).fixed_base_hz[0];
  if (!(a.damping >= 0 && a.damping < 1)) throw InputError(fmt::format("--damping {}: must be in [0, 1)", a.damping));
  const IntensityMeasure im = parse_intensity_measure(a.im, a.damping, t1);
  if (a.im.find("T1") != std::string::npos)
    log::info("--im {}: T1 = {:.4f} s, the fixed-base first period of {}", a.im, t1, scene.name);
  RecordOptions ro = record_options(a.file);
  ro.vertical_component = a.vertical;
  ro.other_horizontal = im.needs_pair();  // RotD: each record with its file's other horizontal component
  RunOptions run = run_options(scene, a.solver, false);
  // Ctrl-C or SIGTERM ends the runs in flight within a step; their rows are
  // not written (a stopped run is not a result), and --resume runs them again.
  run.stop = [] { return stop_signal() != 0; };
  // --pairs: each record the first file of two, with the second as its other horizontal component.
  std::vector<StudyRecord> given;
  if (a.pairs) {
    if (records.size() % 2 != 0)
      throw InputError(fmt::format("--pairs: an odd number of record files ({}); each record is two, its horizontal "
                                   "components one after the other", records.size()));
    RecordOptions second = ro;
    second.component.clear();
    second.other_horizontal = false;
    for (std::size_t i = 0; i < records.size(); i += 2) {
      RecordOptions first = ro;
      first.other_horizontal = false;
      const GroundMotion g = read_record(records[i], first).with_other_horizontal(read_record(records[i + 1], second));
      given.push_back({records[i], std::make_shared<const GroundMotion>(g)});
    }
  }
  if (a.azimuths.empty())
    return a.pairs ? std::make_unique<Study>(a.scene.path, overrides, given, ro, std::move(variants), run, im)
                   : std::make_unique<Study>(a.scene.path, overrides, records, ro, std::move(variants), run, im);
  // --azimuths: each record projected on the plane at each azimuth, a record
  // of its own ("FILE@30"), from its component toward its file's other horizontal one.
  const std::vector<double> angles = number_list("--azimuths", a.azimuths);
  for (double phi : angles)
    if (!(std::abs(phi) <= 360))
      throw InputError(fmt::format("--azimuths {}: {:g} is not an angle in degrees, -360 to 360", a.azimuths, phi));
  RecordOptions pair = ro;
  pair.other_horizontal = true;
  std::vector<StudyRecord> projected;
  for (std::size_t i = 0; i < (a.pairs ? given.size() : records.size()); ++i) {
    const std::string& path = a.pairs ? given[i].name : records[i];
    const GroundMotion g = a.pairs ? *given[i].motion : read_record(path, pair);
    for (double phi : angles)
      projected.push_back({fmt::format("{}@{:g}", path, phi),
                           std::make_shared<const GroundMotion>(project(g, *g.other_horizontal(), phi))});
  }
  return std::make_unique<Study>(a.scene.path, overrides, projected, ro, std::move(variants), run, im);
}

// azimuths.csv of a study over azimuths: for each record file, variant and
// level, the largest and the median (the mean of the middle two when even)
// over the azimuths of each quantity the study CSV holds (the columns from
// record_im to outcome), and how many azimuths overturned.
void write_azimuth_summary(const fs::path& study_csv, const fs::path& out) {
  std::ifstream in(study_csv);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = csv_fields(line);
  const auto at = [&](std::string_view name) {
    return static_cast<std::size_t>(std::ranges::find(header, name) - header.begin());
  };
  const std::size_t record = at("record"), variant = at("variant"), level = at("level"), first = at("record_im") + 1,
                    outcome = at("outcome");
  std::map<std::tuple<std::string, std::string, std::string>, std::vector<std::vector<std::string>>> groups;
  std::vector<std::tuple<std::string, std::string, std::string>> order;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> f = csv_fields(line);
    if (f.size() < header.size()) continue;
    const std::string file = f[record].substr(0, f[record].rfind('@'));
    const auto key = std::make_tuple(file, f[variant], f[level]);
    if (!groups.contains(key)) order.push_back(key);
    groups[key].push_back(std::move(f));
  }
  // overturned: the runs past every limit (overturned, or a joint separated or slid).
  std::string text = "record,variant,level,azimuths,overturned";
  for (std::size_t c = first; c < outcome; ++c) text += fmt::format(",{0}_max,{0}_median", header[c]);
  text += "\n";
  for (const auto& key : order) {
    const auto& rows = groups[key];
    const long overturned = std::ranges::count_if(rows, [&](const auto& f) {
      const std::optional<Outcome> o = outcome_named(f[outcome]);
      return o && past_every_limit(*o);
    });
    text += fmt::format("{},{},{},{},{}", csv_field(std::get<0>(key)), csv_field(std::get<1>(key)), std::get<2>(key),
                        rows.size(), overturned);
    for (std::size_t c = first; c < outcome; ++c) {
      std::vector<double> v;
      for (const auto& f : rows)
        if (!f[c].empty()) v.push_back(std::stod(f[c]));
      std::ranges::sort(v);
      if (v.empty()) {
        text += ",,";
        continue;
      }
      const std::size_t n = v.size();
      const double median = n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
      text += fmt::format(",{:.9g},{:.9g}", v.back(), median);
    }
    text += "\n";
  }
  write_text(out, text);
}

void add_study_options(CLI::App& cmd, StudyArgs& a, const std::string& default_out) {
  a.out = default_out;
  add_scene_options(cmd, a.scene);
  cmd.add_option("--record", a.records,
                 "Ground-motion files in any format --format lists, folders (every file\n"
                 "in it a reader recognises, by name) or list files (one record path a\n"
                 "line, relative to the list; # comments); repeat or list several")
      ->type_name("PATH...");
  cmd.add_option("--suite", a.suite,
                 "A record suite kept in the project (data/suites/NAME.txt, paths in\n"
                 "$ROCKING_RECORDS or ../shared/data/records): 'horizontal' is every\n"
                 "horizontal record there, 24 of them")
      ->type_name("NAME");
  add_record_file_options(cmd, a.file);
  cmd.add_option("--vertical", a.vertical,
                 "The vertical component of each record's file, run with its horizontal one\n"
                 "and scaled with it (GeoNet: --component N28W --vertical Up; MODEL.md 14).\n"
                 "The IM is the horizontal component's")
      ->type_name("C");
  cmd.add_flag("--pairs", a.pairs,
               "The records are pairs of files, each record's two horizontal components\n"
               "one after the other (a PEER pair: X_n89w.at2 X_s01w.at2): the first is\n"
               "run, the second is its other horizontal component for --azimuths and\n"
               "--im rotd50:T");
  cmd.add_option("--azimuths", a.azimuths,
                 "Run each record at these azimuths of the structure's plane [degrees]\n"
                 "(FIRST:LAST:STEP or a list: 0:165:15), projected from its component\n"
                 "toward its file's other horizontal one (MODEL.md 14), each azimuth a\n"
                 "record of its own (FILE@30); DIR/azimuths.csv gives the largest and the\n"
                 "median over the azimuths of every quantity at each level")
      ->type_name("SPEC");
  cmd.add_option("--im", a.im,
                 "What the levels measure: sf (the scale factor itself, default), pga [g],\n"
                 "pgv [m/s], sa:T (5 %-damped PSA at T seconds [g]; sa:T1 at the scene's\n"
                 "fixed-base first period), saavg:T1:T2 (geometric mean of PSA at 10\n"
                 "periods from T1 to T2; 0.2T1:3T1 in multiples of T1), rotd50:T and\n"
                 "rotd100:T (of each record and its file's other horizontal component;\n"
                 "MODEL.md 14). Each record is\n"
                 "scaled by level / IM(record), so that its IM equals the level exactly")
      ->type_name("IM");
  cmd.add_option("--levels", a.levels,
                 "IM levels: FIRST:LAST:STEP or a list (default 1:20:1 for sf; required\n"
                 "for any other --im)")
      ->type_name("SPEC");
  cmd.add_option("--scales", a.scales, "Scale factors: the --levels of --im sf")->type_name("SPEC");
  cmd.add_option("--damping", a.damping, "Damping ratio of sa and saavg (default 0.05)")->type_name("ZETA");
  cmd.add_option("--limit", a.limits,
                 "A limit state for a fragility besides overturning: QUANTITY=VALUE, the\n"
                 "peak at or above VALUE in the quantity's unit (theta_over_alpha=0.5,\n"
                 "damper_d=0.07 [m], delta_t=0.01, or a device by its scene name:\n"
                 "tendon.force=4e6 [N], dampers_left.elongation=0.05 [m]); repeat for\n"
                 "several. `rocking simulate --list-quantities` lists them with units.\n"
                 "An overturned run has reached every limit")
      ->type_name("Q=V");
  cmd.add_option("--resurrection", a.resurrection,
                 "How a record that survives a level above its first overturning counts\n"
                 "there: first (default; Vamvatsikos & Cornell 2002: its IDA curve is\n"
                 "collapsed from its first overturning on, and a limit once reached stays\n"
                 "reached, in the fractiles and the stripes) or keep (each level counts as\n"
                 "it ran). Capacities are each record's first level at the limit either way;\n"
                 "the summary lists the records that stand again")
      ->type_name("first|keep");
  cmd.add_option("--bootstrap", a.bootstrap,
                 "Resamples of the records for the 90 % intervals of each fragility's median\n"
                 "and beta (BCa bootstrap, Efron & Tibshirani 1993; default 1000, 0: none)")
      ->type_name("N");
  cmd.add_option("--seed", a.seed, "Seed of the bootstrap's resampling (default 20020101): the same seed, the\n"
                                   "same intervals on every machine")
      ->type_name("N");
  cmd.add_option("--beta-modelling", a.beta_modelling,
                 "Modelling dispersion added to every fitted beta as sqrt(beta^2 + X^2)\n"
                 "(FEMA P-695; e.g. 0.2-0.5): fragility.csv's beta_total, the figures'\n"
                 "capacity fits (default 0)")
      ->type_name("X");
  cmd.add_option("--threads", a.threads, "Worker threads (default: every core)")->type_name("N");
  cmd.add_option("--max-runs", a.max_runs,
                 "Refuse a ladder of more runs than this before starting (default 1e5:\n"
                 "minutes on two cores); raise it for a larger study")
      ->type_name("N");
  cmd.add_option("--out", a.out, fmt::format("Output folder (default {})", default_out))->type_name("DIR");
  cmd.add_option("--formats", a.formats, "Figure formats: png,pdf,svg (default all)")->type_name("LIST");
  cmd.add_flag("--no-plot", a.no_plot, "Write the CSVs and JSON only");
  cmd.add_option("--log", a.log_axes,
                 "Logarithmic axes for the peaks of forces, moments and accelerations in the\n"
                 "per-record figures: auto (default: where the variants' peaks span more than\n"
                 "a decade, as a fixed base's beside rocking ones), on, off")
      ->type_name("auto|on|off");
  cmd.add_flag("--per-record", a.per_record,
               "Draw one figure per record also for more than three records");
  cmd.add_flag("--resume", a.resume,
               "Continue a study stopped by Ctrl-C or SIGTERM: the rows already in\n"
               "DIR/ida.csv (DIR/sweep.csv) are kept, the other jobs run; the CSV ends as\n"
               "an uninterrupted run writes it. Give the same arguments as the first run.");
  add_solver_options(cmd, a.solver);
}

}  // namespace

Command add_ida_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "ida",
      "Incremental dynamic analysis (Vamvatsikos & Cornell 2002; the paper's Figs.\n"
      "5-6): every (record, level, variant) job, each record scaled so that its\n"
      "intensity measure (--im) equals the level, in parallel on all cores, one CSV\n"
      "row per job in a fixed order (DIR/ida.csv: the IM, level, scale factor used and\n"
      "the record's own IM, the peaks, the outcome; wall times in DIR/timing.csv;\n"
      "what each record is in DIR/records.csv).\n"
      "Over the records (MODEL.md 13): DIR/summary.csv has the 16/50/84 % fractile\n"
      "IDA curves of each peak (an overturned run counts as an infinite peak: 'inf'\n"
      "is a fractile that falls on collapses); DIR/fragility.csv the lognormal\n"
      "overturning fragility (and of each --limit) fitted two ways: to each record's\n"
      "first level at the limit (moments of ln IM; censored MLE when some records\n"
      "never reach it) and to the stripes, the count at each level (binomial MLE,\n"
      "Baker 2015), each with 90 % intervals on median and beta from a bootstrap\n"
      "over records (--bootstrap) and beta_total with --beta-modelling;\n"
      "DIR/fragility_points.csv their data; DIR/summary.json all of it, and the\n"
      "records that survive above their first overturning. A record counts as\n"
      "overturned from its first overturning on (--resurrection).\n"
      "Figures: with up to three records, one per record (peaks against the level,\n"
      "one line per variant); with two or more, one per peak quantity across the\n"
      "suite (every record thin and grey, fractiles bold, overturning crossed), one\n"
      "of the fragility curves with their data and intervals, and with --limit one\n"
      "of the damage states (every limit's fit in one panel per variant).\n"
      "Under `mpirun -np N` the jobs are split across the N processes and rank 0\n"
      "writes the same CSVs. Overturning is an outcome (the collapse point), not an\n"
      "error; a job that fails is reported in its row and the others go on.\n"
      "Exit codes: 0 every run done, 2 bad input, 4 some runs failed (their rows\n"
      "say why; the count is printed on stderr), 130 / 143 stopped by Ctrl-C /\n"
      "SIGTERM (the runs done are kept in the CSV; --resume continues).");
  auto a = std::make_shared<StudyArgs>();
  add_study_options(*cmd, *a, "out/ida");
  cmd->add_option("--variants", a->variants, "scene (as built), without:NAME (less the device the scene names\n"
                  "NAME, its [damper] included), fixed-base, no-devices, damper, no-damper\n"
                  "(the [damper] on, off). Default: as built, without each energy-dissipating\n"
                  "device, and on a fixed base when the scene rocks and is flexible")
      ->delimiter(',')
      ->type_name("LIST");
  cmd->add_flag("--hunt", a->hunt,
                "Hunt and fill (Vamvatsikos & Cornell 2004) for the level at which each\n"
                "record and variant first overturns: trace up from the first level by\n"
                "--hunt-step, the step growing x--hunt-growth each run, to --hunt-max\n"
                "itself, until a run overturns; bisect between the last survivor and it to\n"
                "--precision; then fill every level below it (below --hunt-max when the\n"
                "trace met no overturning) at --fill-step, and bisect below the lowest\n"
                "overturning the fill finds. A record is censored (no overturning up to\n"
                "--hunt-max) only when no level of the fill overturned either. Every level\n"
                "run and why is in DIR/hunt_points.csv. Overturning is not monotonic in\n"
                "the level: a structure that overturns at one level can survive a larger\n"
                "one (El Centro, with dampers, scaled: overturns at 10.45, survives 10.75\n"
                "to 13.0). Survivors above the lowest overturning are reported as\n"
                "resurrections. A window narrower than --fill-step below the answer can\n"
                "be missed: the answer bounds the lowest overturning level from above, to\n"
                "within the fill step. Writes DIR/hunt.csv, DIR/records.csv (what each\n"
                "record id is) and the overturning fragility of the records' collapse\n"
                "levels (DIR/fragility.csv, fragility_points.csv, summary.json).");
  cmd->add_option("--hunt-step", a->hunt_step, "First step of the hunt (default: the first level)")->type_name("X");
  cmd->add_option("--hunt-growth", a->hunt_growth, "Factor the step grows by each run (default 1.5)")->type_name("X");
  cmd->add_option("--hunt-max", a->hunt_max, "Largest level tried (default 50 x the first level)")->type_name("X");
  cmd->add_option("--precision", a->precision, "Width of the final bracket (default hunt step / 20)")->type_name("X");
  cmd->add_option("--fill-step", a->fill_step, "Step of the fill below the first overturning (default hunt step / 10)")
      ->type_name("X");
  cmd->footer(
      "Examples:\n"
      "  rocking ida --record ../shared/data/records/christchurch2011_pphs_s57e.at2 --scales 1:20:1\n"
      "  rocking ida --suite horizontal --im pga --levels 0.1:3:0.1 --variants damper,no-damper\n"
      "  rocking ida --record records/ --im sa:T1 --levels 0.2:6:0.2 --limit theta_over_alpha=0.5\n"
      "  rocking ida --record A.at2 B.at2 --variants damper,no-damper --hunt\n"
      "  mpirun -np 4 build/bin/rocking ida --suite horizontal --im pga --levels 0.1:3:0.1 --threads 1");
  return [a]() {
    check_study_args(*a);
    MpiSession mpi;
    std::vector<Variant> variants;
    if (a->variants.empty()) variants = default_variants(load_scene(a->scene));
    for (const std::string& v : a->variants) variants.push_back(named_variant(v));
    std::string scene_name;
    const auto study = make_study(*a, a->scene.overrides, std::move(variants), scene_name);
    if (a->hunt) return mpi.world().rank == 0 ? run_hunt(*a, *study) : 0;
    return run_ladder(*a, *study, "ida", scene_name, mpi.world());
  };
}

Command add_sweep_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "sweep",
      "Parametric study (the paper's Figs. 7-8): like `ida`, with one line per value\n"
      "of one scene key, given as --set KEY=V1,V2,... (e.g. damper.thickness=1,1.5,2,3\n"
      "or structure.EI_scale=0.25,0.5,1,2). Other --set values apply to every run.\n"
      "Exit codes: 0 every run done, 2 bad input, 4 some runs failed, 130 / 143\n"
      "stopped by Ctrl-C / SIGTERM (--resume continues).");
  auto a = std::make_shared<StudyArgs>();
  add_study_options(*cmd, *a, "out/sweep");
  cmd->footer(
      "Examples:\n"
      "  rocking sweep --record ../shared/data/records/elcentro_1940_ns.at2 --scales 1:5:1 \\\n"
      "                --set damper.thickness=1,1.5,2,3\n"
      "  rocking sweep --record FILE --set structure.EI_scale=0.25,0.5,1,2 --set damper.enabled=false");
  return [a]() {
    check_study_args(*a);
    MpiSession mpi;
    std::vector<std::string> common;
    std::vector<Variant> variants;
    for (const std::string& s : a->scene.overrides) {
      const auto eq = s.find('=');
      const std::string value = eq == std::string::npos ? "" : s.substr(eq + 1);
      if (value.find(',') == std::string::npos || value.starts_with("[") || value.starts_with("{")) {
        common.push_back(s);
        continue;
      }
      if (!variants.empty()) throw InputError(fmt::format("--set {}: sweep one key at a time", s));
      std::stringstream ss(value);
      for (std::string v; std::getline(ss, v, ',');) {
        const std::string one = s.substr(0, eq) + "=" + v;
        variants.push_back({one, {one}});
      }
    }
    if (variants.empty()) throw InputError("sweep: give the swept key as --set KEY=V1,V2,... (e.g. damper.thickness=1,2,3)");
    std::string scene_name;
    const auto study = make_study(*a, common, std::move(variants), scene_name);
    return run_ladder(*a, *study, "sweep", scene_name, mpi.world());
  };
}

}  // namespace rocking::app
