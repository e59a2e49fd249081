// Options shared by the commands that run a scene: which scene, which ground
// motion, which integrator.
#include "commands.hpp"
#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <filesystem>
import rocking.study;
import rocking.errors;
import rocking.records;

namespace rocking::app {

void add_scene_options(CLI::App& cmd, SceneOptions& opts, const std::string& without) {
  cmd.add_option("scene", opts.path,
                 fmt::format("Scene file (TOML), e.g. data/scenes/christchurch_chimney.toml.\nWithout it: {}.", without));
  cmd.add_option("--set", opts.overrides,
                 "Override a scene value, TABLE.KEY=VALUE (repeatable), e.g.\n"
                 "--set structure.EI_scale=0.5 --set damper.enabled=false")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

std::string variant_label(const std::string& name) {
  if (name == "damper") return "rocking, with dampers";
  if (name == "no-damper") return "rocking, no damper";
  if (name == "fixed-base") return "fixed base";
  if (name == "scene") return "as built";
  if (name == "no-devices") return "no devices";
  if (name.starts_with("without:")) return "without " + name.substr(8);
  const auto eq = name.find('=');
  if (eq == std::string::npos) return name;
  const std::string key = name.substr(0, eq), value = name.substr(eq + 1);
  if (key == "damper.thickness") return "damper thickness x" + value;
  if (key == "structure.EI_scale") return "EI x" + value;
  if (key == "damper.stiffness") return "damper stiffness " + value + " N/m";
  if (key == "damper.enabled") return value == "false" ? "no damper" : "with dampers";
  if (key == "contact.restitution") return "restitution " + value;
  if (key == "contact.rocking") return value == "false" ? "fixed base" : "rocking";
  std::string words = key.substr(key.find('.') + 1);
  for (char& c : words)
    if (c == '_') c = ' ';
  return words + " " + value;
}

std::vector<double> number_list(const std::string& flag, const std::string& text) {
  try {
    return parse_number_list(text);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{} {}", flag, e.what()));
  }
}

rocking::Scene load_scene(const SceneOptions& opts) {
  return opts.path.empty() ? load_default_scene(opts.overrides) : rocking::load_scene(opts.path, opts.overrides);
}

rocking::Scene load_elastic_scene(const SceneOptions& opts) {
  rocking::Scene scene = load_scene(opts);
  if (scene.structure.rigid)
    throw InputError(fmt::format("{}: a rigid block has no elastic modes (structure.rigid = true)", scene.source));
  return scene;
}

std::string record_formats_help() {
  std::string out;
  for (const RecordFormatInfo& f : record_formats()) out += fmt::format("\n  {:8} {}", f.name, f.description);
  return out;
}

void add_record_file_options(CLI::App& cmd, RecordFileOptions& opts) {
  cmd.add_option("--format", opts.format,
                 "Record file format (default auto: detected from the content):" + record_formats_help())
      ->type_name("NAME");
  cmd.add_option("--component", opts.component,
                 "Component of a file that holds several (GeoNet: 1-3 or its name, e.g. N28W;\n"
                 "CSV: the acceleration column's name or number). Default: the first")
      ->type_name("C");
  cmd.add_option("--units", opts.units,
                 "Acceleration unit of the values: g, m/s2, cm/s2 (gal) or mm/s2. Default: the\n"
                 "file's own (GeoNet mm/s2, K-NET gal, COSMOS and CSV as stated), else g")
      ->type_name("UNIT");
  cmd.add_option("--dt", opts.dt, "Sample interval of a one-column record or a CSV without time [s]")->type_name("S");
  cmd.add_option("--process", opts.process,
                 "Process every record read, as the field does, in this order: cut=T0:T1 [s],\n"
                 "detrend=K (polynomial of order K removed; 0: the mean), taper=F (cosine,\n"
                 "fraction F at each end), highpass=F1 and lowpass=F2 [Hz] (Butterworth of\n"
                 "order=N, default 4, run forward and backward: zero phase), vfit=K (the\n"
                 "velocity-fit baseline correction), dt=S (resample). E.g.\n"
                 "detrend=1,taper=0.05,highpass=0.1,lowpass=25,vfit=2. Outputs that name the\n"
                 "record say how it was processed")
      ->type_name("SPEC");
}

void add_motion_options(CLI::App& cmd, MotionOptions& opts) {
  cmd.add_option("--record", opts.record,
                 "Ground-motion file in any format --format lists (PEER .AT2, GeoNet,\n"
                 "K-NET, COSMOS, CSV, columns). Without it: the scene's [excitation].")
      ->type_name("FILE");
  add_record_file_options(cmd, opts.file);
  cmd.add_option("--vertical", opts.vertical,
                 "Vertical ground motion (upward; gravity becomes g + a_v in the rocking\n"
                 "equations and the uplift condition): a record file, or a component of\n"
                 "the --record file (GeoNet: --component N28W --vertical Up). Default: the\n"
                 "scene's excitation.vertical with its own excitation, else none")
      ->type_name("FILE|C");
  cmd.add_option("--vertical-component", opts.vertical_file.component,
                 "Component of a --vertical file that holds several (its name or number)")
      ->type_name("C");
  cmd.add_option("--vertical-units", opts.vertical_file.units,
                 "Acceleration unit of a --vertical file's values (default: the file's own)")
      ->type_name("UNIT");
  cmd.add_option_function<double>(
         "--azimuth", [&opts](double v) { opts.azimuth = v; },
         "Run the structure's plane at this azimuth [degrees] from the record's\n"
         "component toward its other horizontal one: a1 cos phi + a2 sin phi\n"
         "(MODEL.md 14). The other is the file's own (GeoNet: --component N28W\n"
         "--azimuth 30 turns from N28W toward S62W) or --second's")
      ->type_name("DEG");
  cmd.add_option("--second", opts.second,
                 "The other horizontal component's file, for --azimuth (a PEER pair:\n"
                 "--record X_n89w.at2 --second X_s01w.at2)")
      ->type_name("FILE");
  cmd.add_option("--scale", opts.scale, "Scale factor on the ground acceleration, vertical too (default 1)")
      ->type_name("SF");
}

void add_solver_options(CLI::App& cmd, SolverOptions& opts) {
  cmd.add_option("--integrator", opts.integrator,
                 "auto (default): rk45, or rosw for a structure whose highest modes would hold\n"
                 "rk45's steps far below the record's; rk45 (the project's Dormand-Prince);\n"
                 "rosw (Rosenbrock-W, linearly implicit in the elastic forces: tall or finely\n"
                 "meshed structures); cvode (SUNDIALS BDF) or arkode (SUNDIALS explicit\n"
                 "Dormand-Prince), the references")
      ->type_name("NAME");
  cmd.add_option("--rtol", opts.rtol, "Relative tolerance (default 1e-4: the knee of `rocking tradeoff`)")->type_name("X");
  cmd.add_option("--atol", opts.atol, "Absolute tolerance (default 1e-7)")->type_name("Y");
  cmd.add_option_function<double>(
         "--duration",
         [&opts](double v) { opts.duration = v; },
                 "Simulated time [s] (default: the length of --record, else the\n"
                 "scene's excitation.duration)")
      ->type_name("S");
  cmd.add_option("--max-events", opts.max_events,
                 "Stop with an error after this many phase changes (default 100000)")
      ->type_name("N");
  cmd.add_option("--max-steps", opts.max_steps,
                 "Stop with an error after this many integrator steps (default 1e7)")
      ->type_name("N");
  cmd.add_flag("--integrate-contact", opts.integrate_contact,
               "Integrate full contact with the chosen integrator too. By default a\n"
               "flexible structure in full contact under a record is stepped exactly\n"
               "(the phase is linear and the record piecewise linear; runs that track\n"
               "energy, and pulses, are always integrated)");
}

void add_window_option(CLI::App& cmd, std::string& window) {
  cmd.add_option("--window", window,
                 "Time span of the time axes: T0:T1 in seconds, or auto (the strong\n"
                 "shaking: 5 % to 95 % of the record's Arias intensity, widened by a\n"
                 "quarter of that span, at least 2 s, each side) (default: the whole run)")
      ->type_name("T0:T1|auto");
}

std::optional<std::array<double, 2>> time_window(const std::string& window,
                                                 const std::vector<const GroundMotion*>& records) {
  if (window.empty()) return std::nullopt;
  if (window == "auto") {
    double from = std::numeric_limits<double>::infinity(), to = -from;
    for (const GroundMotion* g : records) {
      if (g == nullptr) throw InputError("--window auto: needs the record itself (not --from); give T0:T1");
      if (!g->piecewise_linear()) return std::nullopt;  // a pulse is short: the whole run
      const std::array<double, 2> w = strong_shaking_window(*g);
      from = std::min(from, w[0]);
      to = std::max(to, w[1]);
    }
    if (!(to > from)) return std::nullopt;
    return std::array<double, 2>{from, to};
  }
  // A whole number text, nothing before or after it.
  auto number = [](const std::string& text, double& v) {
    char* end = nullptr;
    v = std::strtod(text.c_str(), &end);
    return !text.empty() && end == text.c_str() + text.size() && !std::isspace(static_cast<unsigned char>(text[0]));
  };
  const auto colon = window.find(':');
  double t0 = 0, t1 = 0;
  const bool read = colon != std::string::npos && number(window.substr(0, colon), t0) &&
                    number(window.substr(colon + 1), t1);
  if (!read || !(t0 >= 0) || !(t1 > t0) || !std::isfinite(t1))
    throw InputError(fmt::format("--window {}: give T0:T1 in seconds (0 <= T0 < T1) or auto", window));
  return std::array<double, 2>{t0, t1};
}

std::string window_range(const std::string& window, const std::vector<const GroundMotion*>& records) {
  const auto w = time_window(window, records);
  return w ? fmt::format("[{:.6g}:{:.6g}]", (*w)[0], (*w)[1]) : std::string();
}

}  // namespace rocking::app
