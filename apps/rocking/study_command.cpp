// `rocking ida` and `rocking sweep`: many runs at once (the paper's Figs. 5-8).
// Jobs run on a thread pool (and across MPI ranks under mpirun); rows are
// written in job order, so the CSV does not depend on how the work was split.
// Wall times go to a separate timing.csv for that reason.
#include "commands.hpp"
#include "mpi_jobs.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <sstream>
#include <fstream>
#include <memory>

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct StudyArgs {
  SceneOptions scene;
  std::vector<std::string> records;
  RecordFileOptions file;
  std::string scales = "1:20:1";
  std::vector<std::string> variants;
  int threads = 0;
  std::string out;
  SolverOptions solver;
  bool hunt = false;
  double hunt_step = 1, hunt_max = 50, precision = 0.05;
  std::string formats = "png,pdf,svg";
  bool no_plot = false;
  bool resume = false;
};

const char* csv_header =
    "record,scale,variant,delta_t,delta_e,theta_over_alpha,damper_d_m,base_shear,base_moment,mid_shear,"
    "mid_moment,top_total_mm,outcome,uplifts,impacts,rhs,error\n";

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string row(const Study& st, const std::vector<std::string>& ids, const Job& job, const JobResult& r) {
  std::string q;
  const RunResult& run = r.run;
  for (Quantity k : {Quantity::delta_t, Quantity::delta_e, Quantity::theta_over_alpha, Quantity::damper_d,
                     Quantity::base_shear, Quantity::base_moment, Quantity::mid_shear, Quantity::mid_moment}) {
    q += r.error.empty() && (run.has_forces || !is_force(k)) ? fmt::format("{:.9g},", run.peak(k)) : std::string(",");
  }
  return fmt::format("{},{:.6g},{},{}{},{},{},{},{}\n", csv_field(ids[job.record]), job.scale,
                     csv_field(st.variants()[job.variant].name), q,
                     r.error.empty() ? fmt::format("{:.6g}", run.top_total_mm) : "", outcome_name(run.outcome),
                     run.counts.uplifts, fmt::format("{},{}", run.counts.impacts, run.stats.rhs), csv_field(r.error));
}

// A job's line of figure data: the scale, the eight peaks, 1 if it
// overturned; empty for a job that failed.
std::string figure_line(const Job& job, const JobResult& r) {
  if (!r.error.empty()) return {};
  std::string out = fmt::format("{:.6g}", job.scale);
  for (std::size_t k : {0, 1, 3, 4, 6, 7, 8, 9}) out += fmt::format(",{:.9g}", r.run.peaks[k]);
  return out + (r.run.outcome == Outcome::overturned ? ",1" : ",0");
}

// One data file per (record, variant) and one figure per record: peaks
// against the scale, with each variant's first overturning drawn as collapse.
void study_figures(const StudyArgs& a, const Study& st, const std::vector<std::string>& ids,
                   const std::vector<Job>& jobs, const std::vector<std::string>& lines, const std::string& kind,
                   const std::string& scene_name) {
  const fs::path dir(a.out);
  for (std::size_t r = 0; r < st.records().size(); ++r) {
    std::string stem = ids[r];
    for (char& c : stem)
      if (c == '/' || c == '#') c = '_';
    stem = fs::path(stem).replace_extension().string();
    const std::string name = kind + "_" + stem;
    make_output_dir(dir / (name + ".data"));
    std::vector<plot::Series> series;
    for (std::size_t v = 0; v < st.variants().size(); ++v) {
      const std::string file = (fs::path(name + ".data") / (fmt::format("{}.csv", v))).string();
      std::ofstream out(dir / file);
      out << "scale,delta_t,delta_e,theta_over_alpha,damper_d,base_shear,base_moment,mid_shear,mid_moment,collapse\n";
      int rows = 0;
      bool fallen = false;
      for (std::size_t i = 0; i < jobs.size(); ++i) {
        if (jobs[i].record != r || jobs[i].variant != v || lines[i].empty()) continue;
        const bool down = lines[i].ends_with(",1");
        const int code = down ? (fallen ? 2 : 1) : (fallen ? 3 : 0);
        fallen = fallen || down;
        out << lines[i].substr(0, lines[i].size() - 1) << code << '\n';
        ++rows;
      }
      if (rows == 0) continue;
      plot::Series s{variant_label(st.variants()[v].name), file, {}, fallen ? 10 : 0};
      if (!st.can_overturn(v)) s.absent.push_back(2);    // a fixed base does not rock
      if (!st.has_damper(v)) s.absent.push_back(3);      // nor stretch a damper it has not
      series.push_back(std::move(s));
    }
    if (series.empty()) continue;
    plot::Figure fig;
    fig.dir = dir;
    fig.name = name;
    fig.formats = plot::parse_formats(a.formats);
    fig.width = 1100;
    fig.height = 1300;
    const GroundMotion* motion = st.motion(r);
    fig.title = fmt::format("{}: {}\n{}", scene_name,
                            kind == "ida" ? "incremental dynamic analysis" : "parametric study",
                            motion != nullptr ? motion_title(*motion) : ids[r]);
    const std::vector<plot::Panel> panels = {
        {"peak total top drift {/Symbol d}_t [%]", "$1", "$2*100", true, ""},
        {"peak elastic top drift {/Symbol d}_e [%]", "$1", "$3*100", true, ""},
        {"peak rocking angle {/Symbol q}/{/Symbol a}_{cg} [-]", "$1", "$4", true, ""},
        {"peak damper elongation d [mm]", "$1", "$5*1000", true, ""},
        {"peak base shear V/V_{ref} [-]", "$1", "$6", true, ""},
        {"peak base moment M/M_{ref} [-]", "$1", "$7", true, ""},
        {"peak mid-height shear V/V_{ref} [-]", "$1", "$8", true, ""},
        {"peak mid-height moment M/M_{ref} [-]", "$1", "$9", true, ""}};
    for (const fs::path& f : plot::render_panels(fig, 4, 2, "scale factor on the record [-]", panels, series))
      fmt::print("wrote {}\n", f.string());
  }
}

// A study's CSV fields (no field of a row holds a quoted comma but the error,
// which is last).
std::vector<std::string> csv_fields(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream ss(row);
  for (std::string f; std::getline(ss, f, ',');) out.push_back(f);
  if (row.ends_with(",")) out.emplace_back();  // the last field, empty
  return out;
}

// What an earlier, interrupted run of the same study left in DIR: its rows are
// the first jobs in order (rows are written in job order), each checked
// against the job it must be; their figure data follow from the rows.
struct Resumed {
  std::vector<std::string> rows, lines, timings;
};
Resumed read_resumed(const fs::path& csv_file, const fs::path& timing_file, const std::vector<Job>& jobs,
                     const std::vector<std::string>& ids, const Study& st) {
  Resumed r;
  std::ifstream in(csv_file);
  if (!in) throw InputError(fmt::format("--resume: {} not found: nothing to resume", csv_file.string()));
  std::string line;
  if (!std::getline(in, line) || line + "\n" != csv_header)
    throw InputError(fmt::format("--resume: {}:1: not a study CSV of this version (header differs)", csv_file.string()));
  for (int n = 2; std::getline(in, line); ++n) {
    if (in.eof()) break;  // a last line without its newline was cut: run that job again
    const std::size_t k = r.rows.size();
    const std::vector<std::string> f = csv_fields(line);
    const std::string expected = k < jobs.size() ? fmt::format("{},{:.6g},{}", csv_field(ids[jobs[k].record]), jobs[k].scale,
                                                               csv_field(st.variants()[jobs[k].variant].name))
                                                 : std::string("(no more jobs)");
    if (k >= jobs.size() || f.size() < 17 || !line.starts_with(expected + ","))
      throw InputError(fmt::format("--resume: {}:{}: this row is not job {} of this study ({}): give the same scene, "
                                   "--record, --scales and --variants as the interrupted run",
                                   csv_file.string(), n, k + 1, expected));
    r.rows.push_back(line + "\n");
    std::string data = f[1];
    for (std::size_t c = 3; c <= 10; ++c) data += "," + (f[c].empty() ? std::string("0") : f[c]);
    r.lines.push_back(f[16].empty() ? data + (f[12] == "overturned" ? ",1" : ",0") : std::string());
  }
  std::ifstream timing(timing_file);
  if (timing && std::getline(timing, line))
    while (r.timings.size() < r.rows.size() && std::getline(timing, line)) r.timings.push_back(line + "\n");
  return r;
}

int run_ladder(const StudyArgs& a, const Study& st, const std::string& kind, const std::string& scene_name,
               const MpiWorld& world) {
  const std::vector<Job> jobs = st.ladder(number_list("--scales", a.scales));
  const std::vector<std::string> ids = record_ids(st.records());
  const int threads = thread_count(a.threads);
  if (!a.no_plot) plot::parse_formats(a.formats);  // refused before any run
  if (a.resume && world.size > 1) throw InputError("--resume: run it as one process (not under mpirun)");
  const fs::path dir(a.out), csv_file = dir / (kind + ".csv"), timing_file = dir / "timing.csv";
  const Resumed resumed = a.resume ? read_resumed(csv_file, timing_file, jobs, ids, st) : Resumed{};
  const std::size_t first = resumed.rows.size();
  if (world.rank == 0) make_output_dir(dir);
  if (world.size == 1) catch_stop_signals();
  std::vector<std::size_t> mine;
  for (std::size_t i = first; i < jobs.size(); ++i)
    if (static_cast<int>(i % static_cast<std::size_t>(world.size)) == world.rank) mine.push_back(i);
  if (world.rank == 0)
    spdlog::info("{}: {} jobs on {} thread(s){}{}", kind, jobs.size() - first, threads,
                 world.size > 1 ? fmt::format(" x {} processes", world.size) : "",
                 first > 0 ? fmt::format(" ({} done before, resumed)", first) : "");
  std::vector<std::pair<long, std::string>> rows, timings, lines;
  for (std::size_t i = 0; i < first; ++i) {
    timings.emplace_back(static_cast<long>(i), i < resumed.timings.size() ? resumed.timings[i] : std::string());
    lines.emplace_back(static_cast<long>(i), resumed.lines[i]);
  }
  // A single process streams its rows (a long study shows them as they come)
  // into a temporary file, renamed when the study ends or stops.
  const fs::path partial = csv_file.string() + ".partial";
  std::ofstream csv;
  if (world.size == 1) {
    csv.open(partial);
    if (!csv) throw InputError(fmt::format("{}: cannot write", partial.string()));
    csv << csv_header;
    for (const std::string& r : resumed.rows) csv << r;
    csv << std::flush;
  }
  Progress progress(world.rank == 0 && spdlog::get_level() <= spdlog::level::info);
  const std::size_t emitted = parallel_ordered<JobResult>(
      mine.size(), threads, [&](std::size_t k) { return st.run(jobs[mine[k]]); },
      [&](std::size_t k, const JobResult& r) {
        const std::size_t i = mine[k];
        const std::string text = row(st, ids, jobs[i], r);
        const std::string timing = fmt::format("{},{:.6g},{},{:.6f}\n", csv_field(ids[jobs[i].record]),
                                               jobs[i].scale, csv_field(st.variants()[jobs[i].variant].name), r.run.wall_s);
        if (world.size == 1) {
          csv << text << std::flush;
        } else {
          rows.emplace_back(static_cast<long>(i), text);
        }
        timings.emplace_back(static_cast<long>(i), timing);
        lines.emplace_back(static_cast<long>(i), figure_line(jobs[i], r));
      },
      [&](std::size_t done, std::size_t total) { progress(done, total); }, [] { return stop_signal() != 0; });
  if (world.size > 1) {
    auto all = gather_rows(world, rows);
    std::sort(all.begin(), all.end());
    if (world.rank == 0) {
      csv.open(partial);
      csv << csv_header;
      for (const auto& [i, text] : all) csv << text;
    }
  }
  auto all_timings = gather_rows(world, timings);
  auto all_lines = gather_rows(world, lines);
  std::sort(all_timings.begin(), all_timings.end());
  std::sort(all_lines.begin(), all_lines.end());
  if (world.rank != 0) return 0;
  csv.close();
  if (!csv) throw RunError(fmt::format("{}: cannot write", partial.string()));
  fs::rename(partial, csv_file);
  std::string timing_text = "record,scale,variant,wall_s\n";
  for (const auto& [i, text] : all_timings) timing_text += text;
  write_text(timing_file, timing_text);
  // What each record id is, as its file says (rows name records by id).
  std::string records_text = "record,file,format,event,date,station,component,pga_g\n";
  for (std::size_t r = 0; r < ids.size(); ++r) {
    const GroundMotion* m = st.motion(r);
    const RecordInfo info = m ? m->info() : RecordInfo{};
    records_text += fmt::format("{},{},{},{},{},{},{},{}\n", csv_field(ids[r]), csv_field(st.records()[r]),
                                csv_field(info.format), csv_field(info.event), csv_field(info.date),
                                csv_field(info.station), csv_field(info.component),
                                m ? fmt::format("{:.6g}", m->peak() / standard_gravity) : std::string());
  }
  write_text(dir / "records.csv", records_text);
  if (emitted < mine.size()) {  // stopped by a signal (one process: mine is every job left)
    const std::size_t done = first + emitted;
    const int signal = stop_signal();
    fmt::print(stderr, "rocking: stopped by {} after {} of {} runs; {} holds them; continue with the same command and "
                       "--resume\n",
               signal == SIGTERM ? "SIGTERM" : "SIGINT", done, jobs.size(), csv_file.string());
    return stop_exit_code(signal);
  }
  std::vector<std::string> figure_lines(jobs.size());
  for (auto& [i, text] : all_lines) figure_lines[static_cast<std::size_t>(i)] = std::move(text);
  const auto failed = std::count(figure_lines.begin(), figure_lines.end(), std::string());
  fmt::print("wrote {} ({} runs)\n", csv_file.string(), jobs.size());
  if (!a.no_plot) study_figures(a, st, ids, jobs, figure_lines, kind, scene_name);
  if (failed > 0) {
    fmt::print(stderr, "rocking: {} of {} runs failed: see the error column of {}\n", failed, jobs.size(),
               csv_file.string());
    return exit_jobs_failed;
  }
  return 0;
}

int run_hunt(const StudyArgs& a, const Study& st) {
  const fs::path dir(a.out);
  make_output_dir(dir);
  if (!(a.hunt_step > 0) || !(a.precision > 0) || !(a.hunt_max > 0) || !std::isfinite(a.hunt_max))
    throw InputError("--hunt-step, --hunt-max and --precision must be positive");
  const double first = number_list("--scales", a.scales).front();
  if (a.hunt_max < first)
    throw InputError(fmt::format("--hunt-max {:g}: below the first scale {:g}, the hunt would run nothing", a.hunt_max, first));
  // Runs per record and variant: the steps up, then the bisection.
  const double runs = (a.hunt_max - first) / a.hunt_step + std::log2(std::max(1.0, a.hunt_step / a.precision)) + 1;
  if (runs > 1e5)
    throw InputError(fmt::format("--hunt-step {:g}: up to {:.3g} runs per record and variant (at most 1e5); take a "
                                 "larger step",
                                 a.hunt_step, runs));
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t r = 0; r < st.records().size(); ++r)
    for (std::size_t v = 0; v < st.variants().size(); ++v) pairs.emplace_back(r, v);
  const std::vector<std::string> ids = record_ids(st.records());
  std::ofstream csv(dir / "hunt.csv");
  if (!csv) throw InputError(fmt::format("{}: cannot write", (dir / "hunt.csv").string()));
  csv << "record,variant,collapse_scale,survived_scale,runs,error\n";
  Progress progress(spdlog::get_level() <= spdlog::level::info);
  parallel_ordered<HuntResult>(
      pairs.size(), thread_count(a.threads),
      [&](std::size_t k) { return hunt_collapse(st, pairs[k].first, pairs[k].second, first, a.hunt_step, a.hunt_max, a.precision); },
      [&](std::size_t k, const HuntResult& h) {
        const std::string& record = ids[pairs[k].first];
        const std::string variant = st.variants()[pairs[k].second].name;
        csv << fmt::format("{},{},{},{:.6g},{},{}\n", csv_field(record), csv_field(variant),
                           h.collapsed ? fmt::format("{:.6g}", h.collapse_scale) : "", h.survived_scale, h.runs,
                           csv_field(h.fixed_base ? "fixed base: cannot overturn" : h.error));
        fmt::print("{} / {}: {}\n", record, variant,
                   !h.error.empty() ? "error: " + h.error
                   : h.fixed_base   ? std::string("a fixed base cannot overturn (not run)")
                   : h.collapsed    ? fmt::format("overturns at scale {:.4g} (survives {:.4g}; {} runs)", h.collapse_scale,
                                                  h.survived_scale, h.runs)
                                    : fmt::format("no overturning up to scale {:.4g} ({} runs)", h.survived_scale, h.runs));
      },
      [&](std::size_t done, std::size_t total) { progress(done, total); });
  fmt::print("note: overturning is not monotonic in the scale factor; the hunt reports the first overturning it\n"
             "      meets stepping by {:g}, and can step over a narrower window below it (see `rocking ida --help`)\n",
             a.hunt_step);
  fmt::print("wrote {}\n", (dir / "hunt.csv").string());
  return 0;
}

std::unique_ptr<Study> make_study(const StudyArgs& a, const std::vector<std::string>& overrides,
                                  std::vector<Variant> variants, std::string& scene_name) {
  if (a.records.empty()) throw InputError("--record: give at least one ground-motion file");
  const Scene scene = load_scene(SceneOptions{a.scene.path, overrides});
  scene_name = scene.name;
  const RecordOptions ro = record_options(a.file);
  RunOptions run = run_options(scene, a.solver, false);
  return std::make_unique<Study>(a.scene.path, overrides, a.records, ro, std::move(variants), run);
}

void add_study_options(CLI::App& cmd, StudyArgs& a, const std::string& default_out) {
  a.out = default_out;
  add_scene_options(cmd, a.scene);
  cmd.add_option("--record", a.records, "Ground-motion files in any format --format lists; repeat or list several")
      ->type_name("FILE...")
      ->required();
  add_record_file_options(cmd, a.file);
  cmd.add_option("--scales", a.scales, "Scale factors: FIRST:LAST:STEP or a list 0.5,1,2 (default 1:20:1)")
      ->type_name("SPEC");
  cmd.add_option("--threads", a.threads, "Worker threads (default: every core)")->type_name("N");
  cmd.add_option("--out", a.out, fmt::format("Output folder (default {})", default_out))->type_name("DIR");
  cmd.add_option("--formats", a.formats, "Figure formats: png,pdf,svg (default all)")->type_name("LIST");
  cmd.add_flag("--no-plot", a.no_plot, "Write the CSV only");
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
      "Incremental dynamic analysis (the paper's Figs. 5-6): every (record, scale,\n"
      "variant) job, in parallel on all cores, one CSV row per job in a fixed order\n"
      "(DIR/ida.csv; wall times in DIR/timing.csv; what each record is in\n"
      "DIR/records.csv), and per record a figure of each\n"
      "peak quantity against the scale factor, one line per variant.\n"
      "Under `mpirun -np N` the jobs are split across the N processes and rank 0\n"
      "writes the same CSV. Overturning is an outcome (the collapse point), not an\n"
      "error; a job that fails is reported in its row and the others go on.\n"
      "Exit codes: 0 every run done, 2 bad input, 4 some runs failed (their rows\n"
      "say why; the count is printed on stderr), 130 / 143 stopped by Ctrl-C /\n"
      "SIGTERM (the runs done are kept in the CSV; --resume continues).");
  auto a = std::make_shared<StudyArgs>();
  add_study_options(*cmd, *a, "out/ida");
  cmd->add_option("--variants", a->variants, "damper, no-damper, fixed-base, scene (default the first three)")
      ->delimiter(',')
      ->type_name("LIST");
  cmd->add_flag("--hunt", a->hunt,
                "Find the scale at which each record and variant overturns: step up from\n"
                "the first scale by --hunt-step to --hunt-max, then bisect to --precision.\n"
                "Overturning is not monotonic in the scale factor: a structure that\n"
                "overturns at one scale can survive a larger one (El Centro, with dampers:\n"
                "overturns at 10.45, survives 10.75 to 13.0, overturns from 13.05). The\n"
                "hunt finds the first overturning on its steps, and misses a window\n"
                "narrower than --hunt-step below it: its answer bounds the lowest\n"
                "overturning scale from above. For the lowest, run a fine ladder\n"
                "(--scales 1:20:0.05) and read the first 'overturned' row.");
  cmd->add_option("--hunt-step", a->hunt_step, "Step of the hunt (default 1)")->type_name("X");
  cmd->add_option("--hunt-max", a->hunt_max, "Largest scale tried (default 50)")->type_name("X");
  cmd->add_option("--precision", a->precision, "Width of the final bracket (default 0.05)")->type_name("X");
  cmd->footer(
      "Examples:\n"
      "  rocking ida --record ../shared/data/records/christchurch2011_pphs_s57e.at2 --scales 1:20:1\n"
      "  rocking ida --record A.at2 B.at2 --variants damper,no-damper --hunt\n"
      "  mpirun -np 4 build/bin/rocking ida --record A.at2 --threads 1");
  return [a]() {
    MpiSession mpi;
    std::vector<Variant> variants;
    for (const std::string& v : a->variants.empty() ? std::vector<std::string>{"damper", "no-damper", "fixed-base"}
                                                    : a->variants)
      variants.push_back(named_variant(v));
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
    MpiSession mpi;
    std::vector<std::string> common;
    std::vector<Variant> variants;
    for (const std::string& s : a->scene.overrides) {
      const auto eq = s.find('=');
      const std::string value = eq == std::string::npos ? "" : s.substr(eq + 1);
      if (value.find(',') == std::string::npos || value.starts_with("[")) {
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
