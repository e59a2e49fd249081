// `rocking tradeoff`: the speed/accuracy trade of the three integrators, in
// what users care about (peaks, event times, impact counts, final state),
// against a reference run; writes a CSV and a work-precision figure.
#include "commands.hpp"
#include "stop_signals.hpp"
#include "study_folder.hpp"
#include "run_output.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <fstream>
#include <memory>
#include <string_view>
import rocking.errors;
import rocking.plot;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct TradeoffArgs {
  SceneOptions scene;
  MotionOptions motion;
  std::string out = "out/tradeoff";
  std::string rtols = "1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10";
  std::vector<std::string> backends{"rk45", "rk45+exact", "arkode", "cvode"};
  std::string formats = "png,pdf,svg";
  int repeats = 3;
  double duration = 0;
  // The N axis: several scenes (e.g. the towers of data/scenes/towers), each
  // method's cost at equal accuracy against the scene's node count.
  std::vector<std::string> scenes;
  double accuracy = 1e-4;       // peak delta_t within this of the reference
  double reference_rtol = 1e-9;
  double budget = 60;           // seconds a run may take before it is stopped
  bool backends_given = false;
  bool resume = false;
};

// The rows an interrupted tradeoff measured (--resume), by their key: the
// first `key_fields` fields of the row (method and rtol; scene, N and method).
std::map<std::string, std::string> resumed_rows(const fs::path& file, const std::string& header, int key_fields) {
  std::map<std::string, std::string> out;
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("--resume: {} not found: nothing to resume", file.string()));
  std::string line;
  if (!std::getline(in, line) || line + "\n" != header)
    throw InputError(fmt::format("--resume: {}:1: not a tradeoff CSV of this version (header differs)", file.string()));
  while (std::getline(in, line) && !in.eof()) {
    std::size_t at = 0;
    for (int k = 0; k < key_fields && at != std::string::npos; ++k) at = line.find(',', at + (k > 0 ? 1 : 0));
    if (at == std::string::npos) continue;
    out.emplace(line.substr(0, at), line + "\n");
  }
  return out;
}

// Field k of a CSV row (no field holds a comma but the quoted scene path, first).
std::string field(const std::string& row, std::size_t k) {
  std::size_t start = row.starts_with('"') ? row.find('"', 1) + 1 : 0;
  for (std::size_t i = 0; i < k; ++i) start = row.find(',', start) + 1;
  const std::size_t end = row.find_first_of(",\n", start);
  return row.substr(start, end - start);
}

// A measured error as the figure's data file takes it (not comparable: inf).
double measured_value(const std::string& text) {
  return text.empty() ? std::numeric_limits<double>::infinity() : std::stod(text);
}

// "NAME" integrates every phase with backend NAME; "NAME+exact" steps full
// contact exactly (the default of a run) and integrates the rocking phases.
struct Method {
  ode::Backend backend;
  bool exact_contact;
};
Method parse_method(const std::string& name) {
  constexpr std::string_view suffix = "+exact";
  const bool exact = name.ends_with(suffix);
  try {
    return {ode::parse_backend(exact ? name.substr(0, name.size() - suffix.size()) : name), exact};
  } catch (const InputError&) {
    throw InputError(fmt::format("--backends {}: unknown backend (choose rk45, rosw, cvode or arkode, each with "
                                 "or without +exact)", name));
  }
}

// atol follows rtol: the chimney's displacements and angles are of order 1e-3.
RunOptions options_at(const RunOptions& base, Method m, double rtol) {
  RunOptions o = base;
  o.backend = m.backend;
  o.exact_full_contact = m.exact_contact;
  o.tolerances.rtol = rtol;
  o.tolerances.atol = 1e-3 * rtol;
  return o;
}

// The run each measurement varies the integrator of, as `rocking simulate`
// makes it (rocking.run) with the default solver and --duration; no energy
// balance is integrated (the costs compared are the motion's).
PreparedRun measured_run(const Scene& scene, const TradeoffArgs& a) {
  SolverOptions solver;
  if (a.duration != 0) solver.duration = a.duration;
  return prepare_run({.scene = scene, .motion = a.motion, .solver = solver, .history = {}, .track_energy = false});
}

// The figures of this command: wide, for a legend of every method.
plot::Figure wide_figure(const fs::path& dir, std::string name, const std::string& formats) {
  plot::Figure fig;
  fig.dir = dir;
  fig.name = std::move(name);
  fig.formats = plot::parse_formats(formats);
  fig.width = 1400;
  fig.height = 750;
  return fig;
}

// The fastest of `repeats` runs; each may take `budget` seconds before it is
// stopped (a run that fails or is stopped ends the repeats: it is the result).
RunResult best_of(const ContactModel& m, const GroundMotion& g, RunOptions o, int repeats,
                  double budget = std::numeric_limits<double>::infinity()) {
  RunResult best;
  for (int k = 0; k < repeats; ++k) {
    o.stop = [] { return stop_signal() != 0; };  // Ctrl-C or SIGTERM ends the run in flight
    if (std::isfinite(budget)) {
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
      o.stop = [deadline] { return stop_signal() != 0 || std::chrono::steady_clock::now() > deadline; };
    }
    RunResult r = simulate(m, g, o);
    if (r.outcome == Outcome::failed) return r;
    if (k == 0 || r.wall_s < best.wall_s) best = std::move(r);
  }
  return best;
}

// A measurement that a run stopped by a signal interrupts ends the command:
// the rows measured so far stay, whole, and --resume measures the rest (their
// timings then come from two sittings of the machine).
int stopped(const fs::path& csv_file, std::size_t rows) {
  const int signal = stop_signal();
  fmt::print(stderr, "rocking: stopped by {} after {} measurements; {} holds them; continue with the same command and "
                     "--resume\n",
             stop_signal_name(signal), rows, csv_file.string());
  return stop_exit_code(signal);
}

// A relative error or time difference as written: empty where the runs are
// not comparable (one overturned, one never impacted).
std::string measured(double x) { return std::isfinite(x) ? fmt::format("{:.3e}", x) : std::string(); }

double relative(double value, double reference) {
  return reference != 0 ? std::abs(value / reference - 1.0) : std::abs(value);
}

double time_error(double t, double reference) {
  if (std::isnan(t) && std::isnan(reference)) return 0.0;
  if (std::isnan(t) || std::isnan(reference)) return std::numeric_limits<double>::infinity();
  return std::abs(t - reference);
}

// One scene's run at the cheapest rtol of the ladder (loosest first) that
// meets the accuracy, or the reason none did.
struct CostAtAccuracy {
  bool met = false, over_budget = false;
  double rtol = 0, error = 0;
  RunResult run;
};
CostAtAccuracy cost_at_accuracy(const ContactModel& model, const GroundMotion& motion, const RunOptions& base,
                                Method m, const std::vector<double>& rtols, const RunResult& ref,
                                const TradeoffArgs& a) {
  CostAtAccuracy out;
  for (double rtol : rtols) {
    out.run = best_of(model, motion, options_at(base, m, rtol), a.repeats, a.budget);
    out.rtol = rtol;
    if (out.run.outcome == Outcome::failed) {
      out.over_budget = true;  // or failed otherwise: run.failure says which
      return out;
    }
    out.error = relative(out.run.peak(Quantity::delta_t), ref.peak(Quantity::delta_t));
    if (out.error <= a.accuracy) {
      out.met = true;
      return out;
    }
  }
  return out;
}

// The N axis: for each scene (its node count N) and method, the cost of the
// cheapest run whose peak delta_t is within --accuracy of the reference
// (rosw at --reference-rtol, cross-checked by rk45+exact where that takes
// less than the budget). A method that runs past the budget is not tried on
// larger scenes.
int cost_against_n(const TradeoffArgs& a, const std::vector<double>& rtols) {
  const std::vector<std::string> names =
      a.backends_given ? a.backends : std::vector<std::string>{"rk45+exact", "rosw+exact", "rosw"};
  std::vector<Method> methods;
  for (const std::string& name : names) methods.push_back(parse_method(name));
  const fs::path dir(a.out);
  make_output_dir(dir / "tradeoff_n.data");
  const std::string header = "scene,n,method,rtol,wall_s,rhs,steps,err_delta_t,accuracy,met,reference_check,over_budget\n";
  const auto resumed = a.resume ? resumed_rows(dir / "tradeoff_n.csv", header, 3) : std::map<std::string, std::string>{};
  std::ofstream csv(dir / "tradeoff_n.csv");
  csv << header;
  std::vector<std::ofstream> data;
  for (const std::string& name : names) {
    data.emplace_back(dir / "tradeoff_n.data" / (name + ".csv"));
    data.back() << "n,wall_s,rhs,rtol\n";
  }
  std::vector<bool> given_up(names.size(), false);
  catch_stop_signals();
  std::size_t rows = 0;
  fmt::print("cost at equal accuracy: peak delta_t within {:.0e} of rosw at rtol {:.0e}; rtols {}\n", a.accuracy,
             a.reference_rtol, a.rtols);
  fmt::print("{:>5} {:<12} {:>7} {:>10} {:>11} {:>9} {:>10}\n", "N", "method", "rtol", "wall [s]", "rhs", "steps",
             "err d_t");
  std::string first_name, last_name;
  long smallest_n = std::numeric_limits<long>::max(), largest_n = 0;
  std::vector<long> node_counts;
  // What the figure marks where a method has no point: over its budget there,
  // or not run because it was over at a smaller N.
  std::vector<plot::Mark> missing;
  auto mark_missing = [&](long n, std::size_t i, bool over) {
    missing.push_back({static_cast<double>(n), over ? fmt::format("{}: over {:g} s", names[i], a.budget)
                                                    : fmt::format("{}: not run", names[i])});
  };
  for (const std::string& path : a.scenes) {
    const Scene scene = load_scene(SceneOptions{path, a.scene.overrides});
    const PreparedRun run = measured_run(scene, a);
    const GroundMotion& motion = run.motion;
    const ContactModel& model = run.model;
    if (model.layout.n == 0)
      throw InputError(fmt::format("--scenes {}: a rigid block has no nodes to put on the N axis", path));
    RunOptions base = run.options;
    base.stop = [] { return stop_signal() != 0; };
    const long n = static_cast<long>(model.layout.n);
    auto key = [&](const std::string& name) { return fmt::format("\"{}\",{},{}", path, n, name); };
    if (first_name.empty()) first_name = scene.name;
    last_name = scene.name;
    smallest_n = std::min(smallest_n, n);
    largest_n = std::max(largest_n, n);
    node_counts.push_back(n);
    for (std::size_t i = 0; i < methods.size(); ++i)
      if (given_up[i]) mark_missing(n, i, false);
    // Rows measured before (--resume) are kept as they were.
    bool all_resumed = true;
    for (std::size_t i = 0; i < methods.size(); ++i) {
      if (given_up[i]) continue;
      const auto row = resumed.find(key(names[i]));
      if (row == resumed.end()) {
        all_resumed = false;
        continue;
      }
      csv << row->second << std::flush;
      ++rows;
      if (field(row->second, 9) == "true")
        data[i] << fmt::format("{},{},{},{}\n", n, field(row->second, 4), field(row->second, 5), field(row->second, 3));
      given_up[i] = field(row->second, 11) == "true";
      if (given_up[i]) mark_missing(n, i, true);
      fmt::print("{:>5} {:<12} (measured before, resumed)\n", n, names[i]);
    }
    if (all_resumed) continue;
    const RunResult ref = simulate(model, motion, options_at(base, {ode::Backend::rosw, true}, a.reference_rtol));
    if (stop_signal() != 0) return stopped(dir / "tradeoff_n.csv", rows);
    if (ref.outcome == Outcome::failed) throw RunError(fmt::format("{}: reference run failed: {}", path, ref.failure));
    const RunResult check = best_of(model, motion, options_at(base, {ode::Backend::rk45, true}, a.reference_rtol), 1,
                                    a.budget);
    const std::string checked =
        check.outcome == Outcome::failed
            ? std::string("rk45 over budget")
            : fmt::format("{:.1e}", relative(check.peak(Quantity::delta_t), ref.peak(Quantity::delta_t)));
    fmt::print("N = {}: {}; reference checked by rk45+exact at rtol {:.0e}: {}\n", n, scene.name, a.reference_rtol,
               checked);
    for (std::size_t i = 0; i < methods.size(); ++i) {
      if (given_up[i] || resumed.contains(key(names[i]))) continue;
      const CostAtAccuracy c = cost_at_accuracy(model, motion, base, methods[i], rtols, ref, a);
      if (stop_signal() != 0) return stopped(dir / "tradeoff_n.csv", rows);
      given_up[i] = c.over_budget;
      if (c.over_budget) mark_missing(n, i, true);
      csv << fmt::format("{},{:.0e},{:.6f},{},{},{:.3e},{:.0e},{},{},{}\n", key(names[i]), c.rtol, c.run.wall_s,
                         c.run.stats.rhs, c.run.stats.steps, c.error, a.accuracy, c.met ? "true" : "false", checked,
                         c.over_budget ? "true" : "false")
          << std::flush;
      ++rows;
      if (c.met) data[i] << fmt::format("{},{:.6e},{},{:.0e}\n", n, c.run.wall_s, c.run.stats.rhs, c.rtol);
      fmt::print("{:>5} {:<12} {:>7.0e} {:>10.4g} {:>11} {:>9} {:>10}\n", n, names[i], c.rtol, c.run.wall_s,
                 c.run.stats.rhs, c.run.stats.steps,
                 c.met ? fmt::format("{:.1e}", c.error) : (c.over_budget ? c.run.failure : std::string("not met")));
    }
  }
  csv.close();
  for (auto& d : data) d.close();
  fmt::print("wrote {}\n", (dir / "tradeoff_n.csv").string());
  plot::Figure fig = wide_figure(dir, "cost_against_n", a.formats);
  fig.title = fmt::format("cost against the number of nodes at equal accuracy (peak delta_t within {:.0e}), "
                          "{} to {}", a.accuracy, first_name, last_name);
  std::vector<plot::Series> series;
  for (const std::string& name : names) series.push_back({name, (fs::path("tradeoff_n.data") / (name + ".csv")).string(), {}});
  const std::string rtol_label = fmt::format("sprintf('%d', floor(log10({}) + 0.5))", plot::column("rtol"));
  // The node counts' own range, widened by a fifth on the log axis each side.
  const std::string xrange = fmt::format("[{:.6g}:{:.6g}]", smallest_n / 1.2, largest_n * 1.2);
  // A tick at each scene's N.
  std::sort(node_counts.begin(), node_counts.end());
  const std::string xtics = fmt::format("({})", fmt::join(node_counts, ", "));
  const std::vector<plot::Panel> panels = {
      {"wall time per run [s]", plot::column("n"), plot::column("wall_s"), false, rtol_label, missing, xrange, false, xtics},
      {"right-hand-side evaluations", plot::column("n"), plot::column("rhs"), false, rtol_label, missing, xrange, false,
       xtics}};
  for (const fs::path& f :
       plot::render_panels(fig, 1, 2, "nodes N   (labels: log_{10} rtol)", panels, series, true))
    fmt::print("wrote {}\n", f.string());
  return 0;
}

int tradeoff(const TradeoffArgs& a) {
  const Scene scene = load_scene(a.scene);
  const PreparedRun run = measured_run(scene, a);
  const GroundMotion& motion = run.motion;
  const ContactModel& model = run.model;
  RunOptions base = run.options;
  if (a.repeats < 1 || a.repeats > 100) throw InputError(fmt::format("--repeats {}: must be in [1, 100]", a.repeats));
  std::vector<double> rtols;
  for (double r : number_list("--rtols", a.rtols)) {
    // The reference runs at 1e-12: a tighter rtol would be measured against a coarser run.
    if (!(r >= 1e-12 && r <= 0.1)) throw InputError(fmt::format("--rtols {}: {:g} is not in [1e-12, 0.1]", a.rtols, r));
    rtols.push_back(r);
  }
  if (rtols.size() > 50) throw InputError(fmt::format("--rtols {}: {} tolerances (at most 50)", a.rtols, rtols.size()));
  // The folder: one tradeoff at a time, and what it measures (--resume must match).
  const fs::path out_dir(a.out);
  make_output_dir(out_dir);
  const FolderLock lock(out_dir);
  check_outputs_free(out_dir, {"tradeoff.csv", "tradeoff_n.csv", "inputs.txt"});
  {
    std::string scenes_text = scene_toml(a.scene.path, a.scene.overrides);
    for (const std::string& path : a.scenes) scenes_text += scene_toml(path, a.scene.overrides);
    record_inputs(out_dir,
                  study_inputs(a.scenes.empty() ? "tradeoff" : "tradeoff --scenes", scenes_text,
                               a.motion.record.empty() ? std::vector<std::string>{} : std::vector{a.motion.record},
                               {{"rtols", a.rtols},
                                {"backends", fmt::format("{}", fmt::join(a.backends, ","))},
                                {"repeats", std::to_string(a.repeats)},
                                {"duration", fmt::format("{}", a.duration)},
                                {"scale", fmt::format("{}", a.motion.scale)},
                                {"accuracy", fmt::format("{} (reference rtol {}, budget {} s)", a.accuracy,
                                                         a.reference_rtol, a.budget)}}),
                  a.resume);
  }
  if (!a.scenes.empty()) {
    if (!(a.accuracy > 0 && a.accuracy < 1)) throw InputError(fmt::format("--accuracy {}: must be in (0, 1)", a.accuracy));
    if (!(a.reference_rtol > 0 && a.reference_rtol < 1))
      throw InputError(fmt::format("--reference-rtol {}: must be in (0, 1)", a.reference_rtol));
    if (!(a.budget > 0)) throw InputError(fmt::format("--budget {}: must be positive", a.budget));
    std::sort(rtols.begin(), rtols.end(), std::greater<>());  // loosest first: the cheapest that meets the accuracy
    return cost_against_n(a, rtols);
  }
  std::vector<Method> methods;
  for (const std::string& name : a.backends) methods.push_back(parse_method(name));  // before the long runs
  // The reference: rk45 at rtol 1e-12, checked against ARKODE's independent
  // implementation of the same method at the same tolerance.
  catch_stop_signals();
  base.stop = [] { return stop_signal() != 0; };
  const RunResult ref = simulate(model, motion, options_at(base, {ode::Backend::rk45, false}, 1e-12));
  const RunResult check = simulate(model, motion, options_at(base, {ode::Backend::arkode, false}, 1e-12));
  if (stop_signal() != 0) return stopped(fs::path(a.out) / "tradeoff.csv", 0);
  if (ref.outcome == Outcome::failed) throw RunError("reference run failed: " + ref.failure);
  const double ref_uncertainty = relative(check.peak(Quantity::delta_t), ref.peak(Quantity::delta_t));
  fmt::print("reference: rk45 at rtol 1e-12 (ARKODE at 1e-12 agrees on peak delta_t to {:.1e}); {} impacts\n",
             ref_uncertainty, ref.counts.impacts);
  const fs::path dir(a.out);
  make_output_dir(dir / "tradeoff.data");
  const std::string header =
      "backend,rtol,atol,wall_s,rhs,steps,err_delta_t,err_theta,err_first_uplift_s,err_first_impact_s,impacts,"
      "impacts_reference,err_final_state,outcome\n";
  const auto resumed = a.resume ? resumed_rows(dir / "tradeoff.csv", header, 2) : std::map<std::string, std::string>{};
  std::ofstream csv(dir / "tradeoff.csv");
  csv << header;
  std::size_t rows = 0;
  std::vector<plot::Series> series;
  fmt::print("{:<10} {:>7} {:>10} {:>9} {:>10} {:>10} {:>9}\n", "backend", "rtol", "wall [ms]", "rhs", "err d_t",
             "err theta", "impacts");
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const std::string& name = a.backends[i];
    const Method b = methods[i];
    const std::string file = (fs::path("tradeoff.data") / (name + ".csv")).string();
    std::ofstream data(dir / file);
    data << "wall_s,err_delta_t,err_theta,rtol\n";
    for (double rtol : rtols) {
      if (const auto row = resumed.find(fmt::format("{},{:.0e}", name, rtol)); row != resumed.end()) {
        csv << row->second << std::flush;  // measured before (--resume)
        ++rows;
        data << fmt::format("{},{:.3e},{:.3e},{:.0e}\n", field(row->second, 3),
                            std::max(measured_value(field(row->second, 6)), 1e-16),
                            std::max(measured_value(field(row->second, 7)), 1e-16), rtol);
        continue;
      }
      const RunOptions o = options_at(base, b, rtol);
      const RunResult r = best_of(model, motion, o, a.repeats);
      if (stop_signal() != 0) return stopped(dir / "tradeoff.csv", rows);
      const double e_dt = relative(r.peak(Quantity::delta_t), ref.peak(Quantity::delta_t));
      const double e_th = relative(r.peak(Quantity::theta), ref.peak(Quantity::theta));
      double e_final = std::numeric_limits<double>::infinity();
      if (r.final_state.size() == ref.final_state.size() && r.outcome == ref.outcome)
        e_final = (r.final_state - ref.final_state).norm() / std::max(ref.final_state.norm(), 1e-300);
      csv << fmt::format("{},{:.0e},{:.0e},{:.6f},{},{},{},{},{},{},{},{},{},{}\n", name, rtol, o.tolerances.atol,
                         r.wall_s, r.stats.rhs, r.stats.steps, measured(e_dt), measured(e_th),
                         measured(time_error(r.first_uplift, ref.first_uplift)),
                         measured(time_error(r.first_impact, ref.first_impact)), r.counts.impacts, ref.counts.impacts,
                         measured(e_final), outcome_name(r.outcome))
          << std::flush;
      ++rows;
      data << fmt::format("{:.6e},{:.3e},{:.3e},{:.0e}\n", r.wall_s, std::max(e_dt, 1e-16), std::max(e_th, 1e-16), rtol);
      fmt::print("{:<10} {:>7.0e} {:>10.2f} {:>9} {:>10.2e} {:>10.2e} {:>5}/{}\n", name, rtol, 1e3 * r.wall_s,
                 r.stats.rhs, e_dt, e_th, r.counts.impacts, ref.counts.impacts);
    }
    series.push_back({name, file, {}});
  }
  csv.close();
  fmt::print("wrote {}\n", (dir / "tradeoff.csv").string());
  plot::Figure fig = wide_figure(dir, "work_precision", a.formats);
  fig.title = fmt::format("{}: work-precision, {}, rtol {} (reference: rk45 at rtol 1e-12)\n{}", scene.name,
                          run.scale.describe(), a.rtols, motion_title(motion));
  // Each point is labelled with its rtol (the exponent: "-4" for 1e-4).
  const std::string rtol_label = fmt::format("sprintf('%d', floor(log10({}) + 0.5))", plot::column("rtol"));
  const std::vector<plot::Panel> panels = {
      {"relative error of peak total drift {/Symbol d}_t", plot::column("wall_s"), plot::column("err_delta_t"), false,
       rtol_label},
      {"relative error of peak rocking angle {/Symbol q}", plot::column("wall_s"), plot::column("err_theta"), false,
       rtol_label}};
  for (const fs::path& f : plot::render_panels(fig, 1, 2, "wall time per run [s]   (labels: log_{10} rtol)", panels, series, true))
    fmt::print("wrote {}\n", f.string());
  return 0;
}

}  // namespace

Command add_tradeoff_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "tradeoff",
      "Speed against accuracy: runs the scene with rk45, ARKODE and CVODE (every\n"
      "phase integrated) and rk45+exact (full contact stepped exactly, the\n"
      "default of a run under a record) over a ladder of tolerances, and\n"
      "measures each run's error against a reference (rk45 at rtol 1e-12 in\n"
      "every phase, cross-checked by ARKODE) in peak delta_t and theta,\n"
      "first uplift and impact times, impact count and final state, and its cost\n"
      "(best-of-3 wall time, rhs evaluations, steps). Writes DIR/tradeoff.csv and\n"
      "a work-precision figure DIR/work_precision.{png,pdf,svg}.\n"
      "With --scenes: the N axis. For each scene (its node count N) and method\n"
      "(default rk45+exact, rosw+exact, rosw), the cost of the cheapest run of the\n"
      "ladder whose peak delta_t is within --accuracy of a reference (rosw at\n"
      "--reference-rtol, cross-checked by rk45+exact); writes DIR/tradeoff_n.csv\n"
      "and DIR/cost_against_n.{png,pdf,svg}.");
  auto a = std::make_shared<TradeoffArgs>();
  add_scene_options(*cmd, a->scene);
  add_motion_options(*cmd, a->motion);
  cmd->add_option("--out", a->out, "Output folder (default out/tradeoff)")->type_name("DIR");
  cmd->add_option("--rtols", a->rtols, "Relative tolerances (default 1e-3,...,1e-10; atol = 1e-3 rtol)")
      ->type_name("LIST");
  cmd->add_option_function<std::vector<std::string>>(
         "--backends", [a](const std::vector<std::string>& v) { a->backends = v; a->backends_given = true; },
         "Backends (rk45, rosw, cvode, arkode); NAME+exact steps full contact exactly\n"
         "(default rk45,rk45+exact,arkode,cvode)")
      ->delimiter(',')
      ->type_name("LIST");
  cmd->add_option("--scenes", a->scenes,
                  "Scenes for the N axis, e.g. data/scenes/towers/tower_8.toml,...,tower_64.toml")
      ->delimiter(',')
      ->type_name("LIST");
  cmd->add_option("--accuracy", a->accuracy, "With --scenes: the peak delta_t error to reach (default 1e-4)")
      ->type_name("X");
  cmd->add_option("--reference-rtol", a->reference_rtol, "With --scenes: the reference's rtol (default 1e-9)")
      ->type_name("X");
  cmd->add_option("--budget", a->budget, "With --scenes: seconds a run may take (default 60)")->type_name("S");
  cmd->add_option("--duration", a->duration, "Simulated time [s] (default: the motion's)")->type_name("S");
  cmd->add_option("--repeats", a->repeats, "Runs per point; the fastest counts (default 3)")->type_name("N");
  cmd->add_option("--formats", a->formats, "Figure formats (default png,pdf,svg)")->type_name("LIST");
  cmd->add_flag("--resume", a->resume,
                "Continue a tradeoff stopped by Ctrl-C or SIGTERM in the same --out with the\n"
                "same inputs: the measurements done are kept (their timings are of the\n"
                "first sitting)");
  cmd->footer("Example: rocking tradeoff --record ../shared/data/records/elcentro_1940_ns.at2");
  return [a]() { return tradeoff(*a); };
}

}  // namespace rocking::app
