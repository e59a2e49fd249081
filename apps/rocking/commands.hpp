// The subcommands of the `rocking` program. Each registers itself on the app
// and returns the function to run if it is chosen; main() dispatches and turns
// errors into exit codes (rocking.errors).
#pragma once
#include <rocking/eigen.hpp>  // before any import (TOOLCHAIN.md, Eigen in modules)
#include <CLI/CLI.hpp>
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>
import rocking.scene;
import rocking.ground_motion;
import rocking.run;

namespace rocking::app {

using Command = std::function<int()>;

// SCENE (positional, optional) and --set KEY=VALUE..., shared by every command
// that works on a scene.
struct SceneOptions {
  std::string path;  // empty: the embedded Christchurch chimney
  std::vector<std::string> overrides;
};
// without: what runs when no scene is given, in words.
void add_scene_options(CLI::App& cmd, SceneOptions& opts,
                       const std::string& without = "the Christchurch chimney built into the program");
// The scene the options name (the embedded chimney when no path is given).
rocking::Scene load_scene(const SceneOptions& opts);
// The same, refusing a rigid block (it has no elastic modes) in one line.
rocking::Scene load_elastic_scene(const SceneOptions& opts);

// --format, --component, --units, --dt: how record files are read
// (rocking.run's RecordFileChoice, bound to the options).
using RecordFileOptions = rocking::RecordFileChoice;
void add_record_file_options(CLI::App& cmd, RecordFileOptions& opts);
// The formats and what they are, for --help.
std::string record_formats_help();

// --record FILE [--format] [--component] [--units] [--dt] [--scale]: the
// ground motion of a run (rocking.run's MotionChoice; load_motion and
// motion_scale are the library's).
using MotionOptions = rocking::MotionChoice;
void add_motion_options(CLI::App& cmd, MotionOptions& opts);

// --integrator, --rtol, --atol, --duration, --max-events, --max-steps,
// --integrate-contact: how a run is integrated (rocking.run's SolverChoice;
// run_options is the library's).
using SolverOptions = rocking::SolverChoice;
void add_solver_options(CLI::App& cmd, SolverOptions& opts);

// --window T0:T1 | auto: the time span a time-history figure shows.
void add_window_option(CLI::App& cmd, std::string& window);
// Its span [t0, t1] in seconds (none: the whole run). auto is the strong
// shaking of the records (rocking::strong_shaking_window, their union), the
// whole run for a pulse. InputError naming --window for anything else, and
// for auto without a record to measure.
std::optional<std::array<double, 2>> time_window(const std::string& window,
                                                 const std::vector<const rocking::GroundMotion*>& records);
// The same as a gnuplot range, "[t0:t1]" (empty: the whole run).
std::string window_range(const std::string& window, const std::vector<const rocking::GroundMotion*>& records);

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
Command add_serve_command(CLI::App& app);

// The numbers of a FIRST:LAST:STEP or comma-list option; errors name the flag.
std::vector<double> number_list(const std::string& flag, const std::string& text);

// A variant in words, for legends: a named variant ("no-damper": "rocking,
// no damper") or a swept key ("damper.thickness=1.5": "damper thickness x1.5").
std::string variant_label(const std::string& name);

// The same on two lines, for figure titles.
std::string motion_title(const rocking::GroundMotion& motion);

}  // namespace rocking::app
