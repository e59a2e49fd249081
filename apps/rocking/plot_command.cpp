// `rocking plot response` and `rocking plot modes`: the paper's Figs. 4 and 3
// as PNG, PDF and SVG, with their data and gnuplot script kept beside them.
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <cctype>
#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <tuple>
import rocking.study;
import rocking.errors;
import rocking.geometry;
import rocking.plot;

namespace rocking::app {

namespace fs = std::filesystem;

namespace {

struct FigureArgs {
  std::string out = "plots";
  std::string name;
  std::string formats = "png,pdf,svg";
  std::string size;
};

void add_figure_options(CLI::App& cmd, FigureArgs& a, const std::string& default_name) {
  a.name = default_name;
  cmd.add_option("--out", a.out, "Folder for the figure, its script and data (default plots)")->type_name("DIR");
  cmd.add_option("--name", a.name, fmt::format("File stem of the figure (default {})", default_name))->type_name("NAME");
  cmd.add_option("--formats", a.formats, "Comma-separated: png, pdf, svg (default all three)")->type_name("LIST");
  cmd.add_option("--size", a.size, "Width x height in pixels, e.g. 1000x1300 (PDF: 100 px per inch)")
      ->type_name("WxH");
}

plot::Figure figure(const FigureArgs& a, std::string title, int width, int height) {
  plot::Figure f;
  f.dir = a.out;
  f.name = a.name;
  plot::check_name(a.name, "--name");
  f.title = std::move(title);
  f.formats = plot::parse_formats(a.formats);
  f.width = width;
  f.height = height;
  if (!a.size.empty()) std::tie(f.width, f.height) = plot::parse_size(a.size, 200, 200, 10000);
  return f;
}

void report(const std::vector<fs::path>& files) {
  for (const fs::path& f : files) fmt::print("wrote {}\n", f.string());
}

// --- response ---------------------------------------------------------------

struct ResponseArgs {
  SceneOptions scene;
  MotionOptions motion;
  SolverOptions solver;
  FigureArgs figure;
  std::vector<std::string> variants;
  std::vector<std::string> from;
  std::string window;
};

int response(const ResponseArgs& a) {
  // Every option is checked before the first run.
  plot::Figure fig = figure(a.figure, "", 1000, 1300);
  catch_stop_signals();  // a stop ends a run within a step, gnuplot within 20 ms (main exits 130, 143)
  std::vector<plot::ResponseSeries> series;
  std::string title;
  const fs::path data_dir = fs::path(a.figure.out) / (a.figure.name + ".data");
  if (!a.from.empty()) {
    fig.time_range = window_range(a.window, {nullptr});
    make_output_dir(data_dir);
    std::vector<std::string> what;
    for (const std::string& run_dir : a.from) {
      const fs::path history = fs::path(run_dir) / "history.csv";
      const std::string label = fs::path(run_dir).filename().string();
      plot::check_history(history);  // refused before anything is copied
      fs::copy_file(history, data_dir / (label + ".csv"), fs::copy_options::overwrite_existing);
      series.push_back({label, (fs::path(a.figure.name + ".data") / (label + ".csv")).string()});
      // The run's own summary says what it was.
      const fs::path summary_file = fs::path(run_dir) / "summary.json";
      std::ifstream summary(summary_file);
      const auto s = nlohmann::json::parse(summary, nullptr, false);
      // A separated run's end: the joint in tension (separated_joint), or the columns' tops.
      if (!s.is_discarded() && s.is_object() && s.contains("outcome") && s["outcome"] == "separated") {
        if (s.contains("separated_joint") && s["separated_joint"].is_number_integer())
          series.back().end = {.separated = true, .joint = s["separated_joint"].get<int>()};
        else if (s.contains("columns"))
          series.back().end = {.separated = true, .joint = std::nullopt};
      }
      if (!s.is_discarded() && s.is_object() && s.contains("scene") && s.contains("motion") && s["scene"].is_string() &&
          s["motion"].is_string())
        what.push_back(fmt::format("{}: {} under {}", label, s["scene"].get<std::string>(), s["motion"].get<std::string>()));
      else if (summary.is_open())
        log::warn("{}: not a whole run summary (cut, or another program's); the title names the folders instead",
                     summary_file.string());
    }
    title = what.size() == a.from.size() ? fmt::format("{}", fmt::join(what, "\n"))
                                         : fmt::format("Runs: {}", fmt::join(a.from, ", "));
  } else {
    const Scene base = load_scene(a.scene);
    std::vector<Variant> variants;
    if (a.variants.empty()) variants = default_variants(base);
    for (const std::string& key : a.variants) variants.push_back(named_variant(key));
    std::vector<std::string> keys;
    for (const Variant& v : variants) keys.push_back(v.name);
    const GroundMotion motion = load_motion(base, a.motion);
    fig.time_range = window_range(a.window, {&motion});
    make_output_dir(data_dir);
    title = fmt::format("{}, {}\n{}", base.name, motion_scale(base, a.motion).describe(), motion_title(motion));
    for (std::size_t k = 0; k < keys.size(); ++k) {
      const std::string& key = keys[k];
      const Variant& v = variants[k];
      // The scene as run names what --set changed in it.
      const std::string label = key == "scene" && !a.scene.overrides.empty()
                                    ? fmt::format("scene, {}", fmt::join(a.scene.overrides, ", "))
                                    : variant_label(key);
      std::vector<std::string> overrides = a.scene.overrides;
      overrides.insert(overrides.end(), v.overrides.begin(), v.overrides.end());
      // The variant's run as `rocking simulate` makes it (rocking.run), under
      // the motion read once, sampled every 5 ms; the figure reads no energy.
      PreparedRun run = prepare_run({.scene = load_scene(SceneOptions{a.scene.path, overrides}), .motion = a.motion,
                                     .solver = a.solver, .history = {.columns = {}, .every = 0.005}, .track_energy = false},
                                    motion);
      run.options.stop = [] { return stop_signal() != 0; };
      const ContactModel& model = run.model;
      // The variant's data file: its name with anything but letters, digits, _ - . as _ ("without_damper.csv").
      std::string stem = key;
      for (char& c : stem)
        if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '_' && c != '-' && c != '.') c = '_';
      const fs::path csv = data_dir / (stem + ".csv");
      HistoryCsv history(csv, model);  // every column the figure may draw, whatever the scene's [output]
      const RunResult r = simulate(model, run.motion, run.options, &history);
      history.close();
      if (r.outcome == Outcome::failed) throw RunError(fmt::format("variant {}: {}", key, r.failure));
      // The rocking measure the run has: its base's, its columns' (MODEL.md 16), or none (a fixed base).
      const auto peak_or_dash = [&](Quantity q, const char* format) {
        return r.reports(q) ? fmt::format(fmt::runtime(format), r.peak(q)) : std::string("-");
      };
      const bool columns = r.reports(Quantity::columns_theta_over_alpha);
      fmt::print("{:<22} top {:7.1f} mm, {} {}, M/M_ref {}, {} uplifts, {}\n", label, r.top_total_mm,
                 columns ? "columns' theta/alpha" : "theta/alpha",
                 peak_or_dash(columns ? Quantity::columns_theta_over_alpha : Quantity::theta_over_alpha, "{:.4f}"),
                 peak_or_dash(Quantity::base_moment, "{:.3f}"), r.counts.uplifts, outcome_name(r.outcome));
      series.push_back({label, (fs::path(a.figure.name + ".data") / (stem + ".csv")).string()});
      if (r.outcome == Outcome::separated) series.back().end = {.separated = true, .joint = r.separated_joint};
    }
  }
  fig.title = title;
  report(plot::render_response(fig, series));
  return 0;
}

// --- modes -------------------------------------------------------------------

int modes(const SceneOptions& scene_opts, const FigureArgs& fa) {
  const Scene scene = load_elastic_scene(scene_opts);
  const ModalSummary m = modal_analysis(scene.structure, scene_devices(scene));
  const Eigen::VectorXd& H = scene.structure.heights;
  const Eigen::Index n = H.size();
  // Columns: fixed-base shapes, then rocking-phase total displacements u + H theta.
  Eigen::MatrixXd columns(n + 1, 2 * n + 1);
  columns.setZero();
  plot::ModePanel left{"fixed base", {}, {}}, right{"rocking phase (free), about a pivot", {}, {}};
  for (Eigen::Index k = 0; k < n; ++k) {
    columns.col(k).tail(n) = m.fixed_base.shapes.col(k);
    left.labels.push_back(fmt::format("mode {}: {:.2f} Hz", k + 1, m.fixed_base_hz[static_cast<std::size_t>(k)]));
    left.colours.push_back(static_cast<int>(k));
    left.columns.push_back(fmt::format("fixed_base_{}", k + 1));
  }
  // Mode k of the rocking phase takes the colour of fixed-base mode k; the
  // rocking mode R the last colour of the palette (grey).
  const RockingModes& rm = m.free_rocking;
  int elastic = 0;
  for (Eigen::Index k = 0; k < rm.lambda.size(); ++k) {
    const Eigen::VectorXd u = rm.shapes.col(k).head(n);
    columns.col(n + k).tail(n) = u + H * rm.shapes(n, k);
    const double lambda = rm.lambda[k];
    right.columns.push_back(fmt::format("rocking_{}", k + 1));
    if (lambda < 0) {
      right.labels.push_back(fmt::format("R: p = {:.3f} rad/s", std::sqrt(-lambda)));
      right.colours.push_back(5);
    } else {
      right.labels.push_back(fmt::format("mode {}: {:.2f} Hz", elastic + 1, std::sqrt(lambda) / (2 * M_PI)));
      right.colours.push_back(elastic++);
    }
  }
  for (Eigen::Index c = 0; c < columns.cols(); ++c) {  // top = 1
    const double top = columns(n, c);
    const double scale = std::abs(top) > 1e-12 * columns.col(c).cwiseAbs().maxCoeff() ? top : columns.col(c).cwiseAbs().maxCoeff();
    columns.col(c) /= scale;
  }
  const plot::Figure fig = figure(fa, fmt::format("{}: mode shapes of the linearised structure", scene.name), 1200, 800);
  make_output_dir(fig.dir);
  const std::string data = fa.name + ".dat";
  std::ofstream out(fig.dir / data);
  out << "# height [m], fixed-base shapes 1.." << n << ", rocking-phase shapes (u + H theta), top = 1\nheight";
  for (const plot::ModePanel* p : {&left, &right})
    for (const std::string& name : p->columns) out << ' ' << name;
  out << '\n';
  for (Eigen::Index i = 0; i <= n; ++i) {
    out << (i == 0 ? 0.0 : H[i - 1]);
    for (Eigen::Index c = 0; c < columns.cols(); ++c) out << ' ' << columns(i, c);
    out << '\n';
  }
  out.close();
  if (!out) throw InputError(fmt::format("{}: cannot write", (fig.dir / data).string()));
  report(plot::render_modes(fig, data, left, right));
  return 0;
}

}  // namespace

std::string motion_title(const GroundMotion& motion) {
  const std::string name = describe_motion(motion.name());
  const std::string title = motion.description().empty() ? name : fmt::format("{}\n{}", motion.description(), name);
  const GroundMotion* up = motion.vertical();
  if (!up) return title;
  const std::string vertical = up->info().component.empty() ? describe_motion(up->name()) : up->info().component;
  return fmt::format("{}, with vertical {} (PGA {:.2f} g)", title, vertical, up->peak() / gravity);
}

Command add_plot_command(CLI::App& app) {
  auto* cmd = app.add_subcommand("plot", "Figures, rendered headlessly with gnuplot (PNG, PDF, SVG)");
  cmd->require_subcommand(1);
  auto* resp = cmd->add_subcommand(
      "response",
      "Response figure in the style of the paper's Fig. 4: total and elastic top\n"
      "drift, rocking angle over alpha_cg, the joints' rotations (a structure with\n"
      "[[joint]]s), and the damper's force-elongation loop (or each device's),\n"
      "one line per variant. Runs the variants itself, or plots earlier runs'\n"
      "histories with --from. The figure's data (NAME.data/) and gnuplot script\n"
      "(NAME.gp) are kept beside it: restyle and re-render with `gnuplot NAME.gp`.");
  auto ra = std::make_shared<ResponseArgs>();
  add_scene_options(*resp, ra->scene);
  add_motion_options(*resp, ra->motion);
  add_solver_options(*resp, ra->solver);
  add_figure_options(*resp, ra->figure, "response");
  add_window_option(*resp, ra->window);
  resp->add_option("--variants", ra->variants,
                   "Comma-separated runs to overlay: scene (as built), without:NAME (less\n"
                   "the device the scene names NAME, its [damper] included), fixed-base,\n"
                   "no-devices, damper, no-damper (the [damper] on, off). Default: as built,\n"
                   "without each energy-dissipating device, and on a fixed base when the\n"
                   "scene rocks and is flexible")
      ->delimiter(',')
      ->type_name("LIST");
  resp->add_option("--from", ra->from, "Plot the history.csv of earlier `rocking simulate --out DIR` runs")
      ->type_name("DIR")
      ->excludes("--variants");
  resp->footer(
      "Examples:\n"
      "  rocking plot response                          chimney, default pulse\n"
      "  rocking plot response data/scenes/controlled_rocking_wall.toml \\\n"
      "      --variants scene,without:tendon,without:dampers,no-devices   self-centring\n"
      "  rocking plot response --record ../shared/data/records/elcentro_1940_ns.at2 --scale 3\n"
      "  rocking plot response --record ../shared/data/records/formats/20161113_110259_WTMC_20.V2A \\\n"
      "      --component N28W --window auto                strong shaking only\n"
      "  rocking plot response --from out/a --from out/b --name compare");
  auto* mod = cmd->add_subcommand("modes",
                                  "Mode shapes in the style of the paper's Fig. 3: fixed-base modes and the\n"
                                  "modes of the rocking phase, with the rocking mode R and its p.");
  auto ms = std::make_shared<SceneOptions>();
  auto mf = std::make_shared<FigureArgs>();
  add_scene_options(*mod, *ms);
  add_figure_options(*mod, *mf, "modes");
  return [resp, mod, ra, ms, mf]() {
    if (resp->parsed()) return response(*ra);
    if (mod->parsed()) return modes(*ms, *mf);
    return 2;
  };
}

}  // namespace rocking::app
