// The subcommands of the `rocking` program. Each registers itself on the app
// and returns the function to run if it is chosen; main() dispatches and turns
// errors into exit codes (rocking.errors).
#pragma once
#include <rocking/eigen.hpp>  // before any import (TOOLCHAIN.md, Eigen in modules)
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>
import rocking;

namespace rocking::app {

using Command = std::function<int()>;

// SCENE (positional, optional) and --set KEY=VALUE..., shared by every command
// that works on a scene.
struct SceneOptions {
  std::string path;  // empty: the embedded Christchurch chimney
  std::vector<std::string> overrides;
};
void add_scene_options(CLI::App& cmd, SceneOptions& opts);
// The scene the options name (the embedded chimney when no path is given).
rocking::Scene load_scene(const SceneOptions& opts);
// The same, refusing a rigid block (it has no elastic modes) in one line.
rocking::Scene load_elastic_scene(const SceneOptions& opts);

// --format, --component, --units, --dt: how record files are read.
struct RecordFileOptions {
  std::string format = "auto";
  std::string component;
  std::string units;  // empty: the file's own (g where a file states none)
  double dt = 0;
  bool given() const { return format != "auto" || !component.empty() || !units.empty() || dt != 0; }
};
void add_record_file_options(CLI::App& cmd, RecordFileOptions& opts);
rocking::RecordOptions record_options(const RecordFileOptions& opts);
// Record ids for rows, tables and figures: a file's name, or as many of its
// last path components as make it unique ("x/a.at2", "y/a.at2"); the same
// file given twice becomes "a.at2" and "a.at2#2".
std::vector<std::string> record_ids(const std::vector<std::string>& paths);
// The formats and what they are, for --help.
std::string record_formats_help();

// --record FILE [--format] [--component] [--units] [--dt] [--scale]: the
// ground motion of a run.
struct MotionOptions {
  std::string record;  // empty: the scene's [excitation]
  RecordFileOptions file;
  double scale = 1;
};
void add_motion_options(CLI::App& cmd, MotionOptions& opts);
// The factors a run's ground motion is scaled by: the scene's [excitation]
// scale (its own record only) times --scale.
struct ScaleFactors {
  double scene = 1, option = 1;
  double total() const { return scene * option; }
  std::string describe() const;  // "x3", or "x6 (scene 2 x --scale 3)"
};
ScaleFactors motion_scale(const rocking::Scene& scene, const MotionOptions& opts);
rocking::GroundMotion load_motion(const rocking::Scene& scene, const MotionOptions& opts);

// --integrator, --rtol, --atol, --duration: how a run is integrated.
struct SolverOptions {
  std::string integrator = "auto";
  double rtol = 1e-4, atol = 1e-7;  // RunOptions' defaults: the measured knee
  double duration = 0;           // with duration_given: --duration
  bool duration_given = false;
  long max_events = 100000;
  long max_steps = 10'000'000;
  bool integrate_contact = false;  // full contact by the backend, not exact steps
};
void add_solver_options(CLI::App& cmd, SolverOptions& opts);
// scene_excitation: the run uses the scene's [excitation] (and its duration).
rocking::RunOptions run_options(const rocking::Scene& scene, const SolverOptions& opts, bool scene_excitation);

Command add_modal_command(CLI::App& app);
Command add_simulate_command(CLI::App& app);
Command add_plot_command(CLI::App& app);
Command add_ida_command(CLI::App& app);
Command add_sweep_command(CLI::App& app);
Command add_tradeoff_command(CLI::App& app);
Command add_spectrum_command(CLI::App& app);
Command add_animate_command(CLI::App& app);
Command add_record_command(CLI::App& app);
Command add_fit_command(CLI::App& app);

// The numbers of a FIRST:LAST:STEP or comma-list option; errors name the flag.
std::vector<double> number_list(const std::string& flag, const std::string& text);

// A variant in words, for legends: a named variant ("no-damper": "rocking,
// no damper") or a swept key ("damper.thickness=1.5": "damper thickness x1.5").
std::string variant_label(const std::string& name);

// The same on two lines, for figure titles.
std::string motion_title(const rocking::GroundMotion& motion);

}  // namespace rocking::app
