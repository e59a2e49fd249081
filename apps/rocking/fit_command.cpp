// `rocking fit`: a device law fitted to a cyclic test (rocking.fitting), the
// fitted [[device]] table ready for a scene, and the figure of the fit.
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include "commands.hpp"
import rocking.errors;
import rocking.fitting;
import rocking.quantities;
import rocking.plot;

namespace rocking::app {

namespace {

namespace fs = std::filesystem;

struct FitArgs {
  std::string file;
  std::string law = "bouc-wen";
  std::vector<std::string> fixes;
  CyclicColumns columns;
  double thickness = 1;
  std::optional<double> stiffness, yield;
  std::string at = "edges", name = "plates";
  std::string scene;  // the scene the table is for (empty: the built-in chimney)
  bool json = false;
  std::string out, figure_name = "fit", formats = "png,pdf,svg";
};

std::vector<std::pair<std::string, double>> parse_fixes(const std::vector<std::string>& fixes) {
  std::vector<std::pair<std::string, double>> out;
  for (const std::string& f : fixes) {
    const auto eq = f.find('=');
    const std::string key = eq == std::string::npos ? "" : f.substr(0, eq);
    const std::string text = eq == std::string::npos ? "" : f.substr(eq + 1);
    char* end = nullptr;
    const double v = text.empty() ? NAN : std::strtod(text.c_str(), &end);
    if (key.empty() || text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
      throw InputError(fmt::format("--fix {}: write KEY=VALUE with a number in SI units, e.g. --fix beta=0", f));
    out.emplace_back(key, v);
  }
  return out;
}

// The [[device]] table of the fitted law, in SI units, for a scene.
std::string device_table(const FitArgs& a, const Fit& fit, const std::vector<std::pair<std::string, double>>& values) {
  std::string at = a.at;
  char* end = nullptr;
  const double x = std::strtod(at.c_str(), &end);
  at = (end == at.c_str() + at.size() && !at.empty()) ? fmt::format("{:.9g}", x) : fmt::format("\"{}\"", at);
  std::string t = fmt::format("[[device]]\nname = \"{}\"\nkind = \"{}\"\nat = {}\n", a.name, fit.law, at);
  for (const auto& [key, value] : values) t += fmt::format("{} = {:.9g}\n", key, value);
  return t;
}

int run_fit(const FitArgs& a) {
  // Checked before the fit: the table is written into scenes, the figure beside --out.
  const bool plain = !a.name.empty() && std::all_of(a.name.begin(), a.name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  if (!plain) throw InputError(fmt::format("--name {}: letters, digits, _ or - (it names a device)", plot::comment(a.name)));
  if (a.at != "edges") {
    char* end = nullptr;
    const double x = std::strtod(a.at.c_str(), &end);
    if (a.at.empty() || end != a.at.c_str() + a.at.size() || !std::isfinite(x) || std::abs(x) > 1e4)
      throw InputError(fmt::format("--at {}: edges, or x [m] from the centre line (a finite number)", plot::comment(a.at)));
    // The anchor lies on the base of the scene the table is written into.
    const Scene scene = load_scene(SceneOptions{a.scene, {}});
    const double B = scene.structure.half_width;
    if (!(std::abs(x) <= B))
      throw InputError(fmt::format("--at {:g}: x must lie on the base of {}, -B <= x <= B = {:g} m (--scene FILE for "
                                   "another scene, or edges)", x, a.scene.empty() ? "the built-in chimney" : a.scene, B));
  } else if (!a.scene.empty()) {
    (void)load_scene(SceneOptions{a.scene, {}});  // a scene named is a scene that reads
  }
  if (!a.out.empty()) plot::check_name(a.figure_name, "--figure");
  const CyclicTest test = read_cyclic_test(a.file, a.columns);
  const Fit fit = fit_law(test, {a.law, parse_fixes(a.fixes)});
  const PlateScaling scaling{a.thickness, a.stiffness, a.yield};
  const auto values = scaled_parameters(fit, scaling);
  const std::string table = device_table(a, fit, values);
  std::vector<fs::path> figures;
  if (!a.out.empty()) {
    const fs::path dir(a.out);
    plot::Figure fig{dir, a.figure_name, fmt::format("{} law fitted to {}", fit.law, fs::path(a.file).filename().string())};
    fig.formats = plot::parse_formats(a.formats);
    fig.width = 1100;
    fig.height = 520;
    std::error_code ec;
    fs::create_directories(dir, ec);
    const fs::path data = dir / (a.figure_name + ".csv");
    std::ofstream csv(data);
    csv << (test.t.empty() ? "sample" : "t [s]") << ",e [m],F measured [N],F fitted [N]\n";
    for (std::size_t i = 0; i < test.e.size(); ++i)
      csv << fmt::format("{:.9g},{:.9g},{:.9g},{:.9g}\n", test.t.empty() ? static_cast<double>(i) : test.t[i],
                         test.e[i], test.F[i], fit.force[i]);
    csv.close();
    if (!csv) throw InputError(fmt::format("{}: cannot write the fit's data", data.string()));
    std::ofstream toml(dir / (a.figure_name + ".toml"));
    toml << table;
    figures = plot::render_fit(fig, data.filename().string(),
                               fmt::format("fitted {} (RMS error {:.3g} kN)", fit.law, fit.rms_error / 1000),
                               test.t.empty() ? "sample" : "time t [s]", test.t.empty() ? "sample" : "t [s]");
  }
  if (a.json) {
    nlohmann::json params = nlohmann::json::array();
    for (const FittedParameter& p : fit.parameters)
      params.push_back({{"key", p.key}, {"unit", p.unit}, {"value", p.value}, {"standard_error", p.standard_error},
                        {"fixed", p.fixed}, {"one_minus", p.one_minus}});
    nlohmann::json scaled = nlohmann::json::object();
    for (const auto& [key, value] : values) scaled[key] = value;
    nlohmann::json j{{"law", fit.law},          {"file", a.file},
                     {"samples", fit.samples},  {"parameters", params},
                     {"rms_error_N", fit.rms_error}, {"peak_error_N", fit.peak_error},
                     {"peak_force_N", fit.peak_force}, {"rcond", fit.rcond},
                     {"iterations", fit.iterations}, {"device", scaled}, {"table", table}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  fmt::print("{} law fitted to {} ({} samples{})\n\n", fit.law, a.file, fit.samples,
             test.t.empty() ? ", no times" : "");
  for (const FittedParameter& p : fit.parameters) {
    if (!p.one_minus.empty())
      fmt::print("  {:<6} {:>13.6g} {:<12} (1 - {})  {}\n", p.key, p.value, p.unit, p.one_minus, p.doc);
    else if (p.fixed)
      fmt::print("  {:<6} {:>13.6g} {:<12} (fixed)     {}\n", p.key, p.value, p.unit, p.doc);
    else
      fmt::print("  {:<6} {:>13.6g} {:<12} +- {:<9.2g} {}\n", p.key, p.value, p.unit, p.standard_error, p.doc);
  }
  fmt::print("\n  RMS error {:.4g} N ({:.2f} % of the peak force {:.4g} N), peak error {:.4g} N\n", fit.rms_error,
             100 * fit.rms_error / fit.peak_force, fit.peak_force, fit.peak_error);
  fmt::print("  {} iterations; reciprocal condition number of the Jacobian {:.2g}{}\n", fit.iterations, fit.rcond,
             fit.rcond < 1e-8 ? " (ill-conditioned: some parameters are not determined by this test; --fix some)" : "");
  if (scaling.any())
    fmt::print("\nScaled to the structure's plates (thickness x{:g}{}{}):\n", a.thickness,
               a.stiffness ? fmt::format(", k = {:g} N/m", *a.stiffness) : "",
               a.yield ? fmt::format(", d_y = {:g} m", *a.yield) : "");
  fmt::print("\nFor a scene (SI units):\n\n{}", table);
  for (const fs::path& f : figures) fmt::print("\nwrote {}", f.string());
  if (!figures.empty()) fmt::print("\n");
  return 0;
}

}  // namespace

Command add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fit",
      "Fit a device law to a cyclic test (the paper's Fig. 2): parameters with standard\n"
      "errors, the fit's error, and the [[device]] table for a scene");
  cmd->add_option("file", a->file,
                  "The test: a table with a header row naming each column and its unit in\n"
                  "brackets, e.g. 'time [s], displacement [mm], force [kN]' (CSV or spaces)")
      ->required();
  std::string laws;
  for (const LawInfo& l : device_laws()) laws += fmt::format("\n  {:10} {}", l.name, l.summary);
  cmd->add_option("--law", a->law, "The law to fit (default bouc-wen):" + laws)->type_name("NAME");
  cmd->add_option("--fix", a->fixes,
                  "Hold a parameter at a value, SI units (repeatable); the paper held\n"
                  "--fix beta=0 --fix n=1. The rest start from the data.")
      ->type_name("KEY=VALUE");
  cmd->add_option("--time", a->columns.time, "The time column, by name or 1-based number (default: t or time)")
      ->type_name("COL");
  cmd->add_option("--elongation", a->columns.elongation,
                  "The elongation column (default: a name starting disp, elong, stroke, or e, d, u, x)")
      ->type_name("COL");
  cmd->add_option("--force", a->columns.force, "The force column (default: a name starting force or load, or f, p)")
      ->type_name("COL");
  cmd->add_option("--thickness", a->thickness,
                  "Scale the tested plate to the structure's: thickness x TAU gives stiffness\n"
                  "x TAU^3 and yield elongation x 1/TAU (MODEL.md 5); shape kept")
      ->type_name("TAU");
  cmd->add_option("--stiffness", a->stiffness, "The structure's plate stiffness k [N/m] (shape kept)")->type_name("K");
  cmd->add_option("--yield", a->yield, "The structure's plate yield elongation d_y [m] (shape kept)")->type_name("D");
  cmd->add_option("--at", a->at, "The table's anchor: edges (default) or x [m]")->type_name("X");
  cmd->add_option("--name", a->name, "The table's device name (default plates)")->type_name("NAME");
  cmd->add_option("--scene", a->scene,
                  "The scene the table is for, whose base bounds --at X (default: the\n"
                  "Christchurch chimney built into the program)")
      ->type_name("FILE");
  cmd->add_flag("--json", a->json, "Print the fit as JSON");
  cmd->add_option("--out", a->out,
                  "Write the figure (measured and fitted loops, residual), its data and the\n"
                  "table (FIGURE.toml, see --figure) to this folder")
      ->type_name("DIR");
  cmd->add_option("--figure", a->figure_name, "File stem of the figure (default fit)")->type_name("NAME");
  cmd->add_option("--formats", a->formats, "Comma-separated: png, pdf, svg (default all three)")->type_name("LIST");
  cmd->footer(
      "Example (the synthetic test in data/tests, made by scripts/make_cyclic_tests.sh):\n"
      "  rocking fit data/tests/bouc_wen_cyclic.csv --out plots\n"
      "Paste the printed table into a scene, or try it: --set 'device+={...}'.");
  return [a]() { return run_fit(*a); };
}

}  // namespace rocking::app
