module;
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>
#include <fmt/format.h>
module rocking.plot;
import rocking.errors;

namespace rocking::plot {

namespace fs = std::filesystem;

namespace {

// A gnuplot string literal: double quotes, with \ and " escaped, newlines kept.
std::string gp_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// Text size that stays readable at the size the figure is written.
int font_points(const Figure& fig, int reference_width, int reference_height) {
  const double ratio = std::min(static_cast<double>(fig.width) / reference_width,
                                static_cast<double>(fig.height) / reference_height);
  return std::clamp(static_cast<int>(std::lround(12 * ratio)), 7, 16);
}

// The loop over formats with their terminals, around a figure body.
std::string render_loop(const Figure& fig, const std::string& body, int points) {
  std::string formats;
  for (const std::string& f : fig.formats) formats += (formats.empty() ? "" : " ") + f;
  return fmt::format(
      "formats = {}\n"
      "do for [fmt in formats] {{\n"
      "  if (fmt eq \"png\") {{ set terminal pngcairo size {w},{h} enhanced font \"DejaVu Sans,{pt}\" linewidth 1.2 }}\n"
      "  if (fmt eq \"pdf\") {{ set terminal pdfcairo size {wi:.2f}in,{hi:.2f}in enhanced font \"DejaVu Sans,{pt}\" }}\n"
      "  if (fmt eq \"svg\") {{ set terminal svg size {w},{h} dynamic enhanced font \"DejaVu Sans,{pt}\" }}\n"
      "  set output {name} . \".\" . fmt\n"
      "{body}"
      "  unset multiplot\n"
      "  set output\n"
      "}}\n",
      gp_string(formats), fmt::arg("w", fig.width), fmt::arg("h", fig.height), fmt::arg("wi", fig.width / 100.0),
      fmt::arg("hi", fig.height / 100.0), fmt::arg("name", gp_string(fig.name)), fmt::arg("body", body),
      fmt::arg("pt", points));
}

void write_script(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  out.close();
  if (!out) throw InputError(fmt::format("{}: cannot write the gnuplot script", file.string()));
}

bool executable(const fs::path& p) { return ::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p); }

std::vector<fs::path> run_script(const Figure& fig, const std::string& script) {
  std::error_code ec;
  fs::create_directories(fig.dir, ec);
  if (ec || !fs::is_directory(fig.dir))
    throw InputError(fmt::format("{}: cannot create the output folder{}{}", fig.dir.string(), ec ? ": " : "",
                                 ec ? ec.message() : ""));
  const fs::path gp = fig.dir / (fig.name + ".gp");
  write_script(gp, script);
  const std::string gnuplot = find_gnuplot();
  const fs::path log = fig.dir / (fig.name + ".gnuplot.log");
  const std::string cmd = fmt::format("cd '{}' && '{}' '{}' >'{}' 2>&1", fig.dir.string(), gnuplot,
                                      gp.filename().string(), log.filename().string());
  const int status = std::system(cmd.c_str());
  std::vector<fs::path> written;
  for (const std::string& f : fig.formats) {
    const fs::path out = fig.dir / (fig.name + "." + f);
    if (fs::is_regular_file(out) && fs::file_size(out) > 0) written.push_back(out);
  }
  if (status != 0 || written.size() != fig.formats.size()) {
    std::ifstream in(log);
    std::string first, line;
    while (std::getline(in, line))
      if (!line.empty()) { first = line; break; }
    throw RunError(fmt::format("gnuplot failed on {} (see {}){}{}", gp.string(), log.string(),
                               first.empty() ? "" : ": ", first));
  }
  fs::remove(log, ec);
  return written;
}

}  // namespace

std::vector<std::string> parse_formats(const std::string& list) {
  std::vector<std::string> out;
  std::stringstream ss(list);
  std::string f;
  while (std::getline(ss, f, ',')) {
    if (f != "png" && f != "pdf" && f != "svg")
      throw InputError(fmt::format("--formats {}: unknown format '{}' (choose from png, pdf, svg)", list, f));
    out.push_back(f);
  }
  if (out.empty()) throw InputError("--formats: give at least one of png, pdf, svg");
  return out;
}

std::string find_gnuplot() {
  if (const char* env = std::getenv("ROCKING_GNUPLOT"); env != nullptr && *env != 0) {
    if (!executable(env))
      throw RunError(fmt::format("ROCKING_GNUPLOT={}: not an executable program", env));
    return env;
  }
  if (const char* path = std::getenv("PATH")) {
    std::stringstream ss(path);
    std::string dir;
    while (std::getline(ss, dir, ':'))
      if (!dir.empty() && executable(fs::path(dir) / "gnuplot")) return (fs::path(dir) / "gnuplot").string();
  }
  throw RunError("gnuplot not found on PATH: install gnuplot-nox (scripts/setup.sh does) or set ROCKING_GNUPLOT");
}

void check_history(const fs::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("{}: history file not found", file.string()));
  std::string line;
  int rows = 0;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 1) {
      if (!line.starts_with("t [s]")) throw InputError(fmt::format("{}:1: not a rocking history (header 't [s],...')", file.string()));
      continue;
    }
    if (!line.empty()) ++rows;
  }
  if (rows < 2) throw InputError(fmt::format("{}: empty history ({} rows): nothing to plot", file.string(), rows));
}

std::vector<fs::path> render_response(const Figure& fig, const std::vector<ResponseSeries>& runs) {
  if (runs.empty()) throw InputError("response figure: no runs to plot");
  for (const ResponseSeries& r : runs) check_history(fs::path(r.history).is_absolute() ? fs::path(r.history) : fig.dir / r.history);
  auto plot_command = [&](const std::string& using_spec, bool dampers_only) {
    std::string cmd;
    for (std::size_t i = 0; i < runs.size(); ++i) {
      if (dampers_only && !runs[i].has_damper) continue;
      cmd += fmt::format("{}{} skip 1 using {} with lines linestyle {} title {} noenhanced", cmd.empty() ? "  plot " : ", \\\n       ",
                         gp_string(runs[i].history), using_spec, i + 1, gp_string(runs[i].label));
    }
    return cmd.empty() ? std::string("  plot NaN title \"(no damper)\"\n") : cmd + "\n";
  };
  std::string body = fmt::format(
      "  set multiplot layout 4,1 title {} noenhanced\n"
      "  set grid\n"
      "  set key top right box opaque\n"
      "  set xlabel \"time t [s]\"\n"
      "  set ylabel \"total top drift {{/Symbol d}}_t [%]\"\n",
      gp_string(fig.title));
  body += plot_command("1:($6*100)", false);
  body += "  set ylabel \"elastic top drift {/Symbol d}_e [%]\"\n";
  body += plot_command("1:($7*100)", false);
  body += "  set ylabel \"rocking angle {/Symbol q}/{/Symbol a}_{cg} [-]\"\n";
  body += plot_command("1:5", false);
  body += "  set xlabel \"damper elongation d [mm] (signed by the pivot)\"\n"
          "  set ylabel \"damper force F_{hd} [kN]\"\n";
  // Break the loop where no damper is stretched (d = 0: full contact, and the
  // impacts where one edge's damper hands over to the other's).
  body += plot_command("($8 == 0 ? NaN : $8*1000):($9/1000)", true);
  const std::string script = fmt::format(
      "# rocking: response figure in the style of the paper's Fig. 4.\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: rocking simulate history CSV (t, phase, u_N, theta, theta/alpha_cg,\n"
      "# delta_t, delta_e, d, F_hd, base/mid shear and moment).\n"
      "set datafile separator \",\"\n"
      "set linetype 1 linecolor rgb \"#1f4e9c\" linewidth 1.5\n"
      "set linetype 2 linecolor rgb \"#c0392b\" linewidth 1.5\n"
      "set linetype 3 linecolor rgb \"#27864a\" linewidth 1.5\n"
      "set linetype 4 linecolor rgb \"#8e44ad\" linewidth 1.5\n"
      "set style line 1 linetype 1\nset style line 2 linetype 2\nset style line 3 linetype 3\nset style line 4 linetype 4\n"
      "{}",
      fig.name, render_loop(fig, body, font_points(fig, 1000, 1300)));
  return run_script(fig, script);
}

std::vector<fs::path> render_panels(const Figure& fig, int rows, int cols, const std::string& xlabel,
                                    const std::vector<Panel>& panels, const std::vector<Series>& series, bool loglog) {
  if (series.empty()) throw InputError("figure: no series to plot");
  std::string body = fmt::format(
      "  set multiplot layout {},{} title {} noenhanced\n"
      "  set grid\n"
      "  set key top left box opaque\n"
      "  set xlabel {}\n{}",
      rows, cols, gp_string(fig.title), gp_string(xlabel),
      loglog ? "  set logscale xy\n  set format x \"10^{%T}\"\n  set format y \"10^{%T}\"\n" : "");
  for (const Panel& p : panels) {
    body += fmt::format("  set ylabel {}\n", gp_string(p.ylabel));
    for (std::size_t i = 0; i < series.size(); ++i)
      body += fmt::format("{}{} skip 1 using {} with linespoints linestyle {} title {} noenhanced",
                          i == 0 ? "  plot " : ", \\\n       ", gp_string(series[i].file), p.using_spec, i + 1,
                          gp_string(series[i].label));
    body += "\n";
  }
  const std::string script = fmt::format(
      "# rocking: study figure (peaks against the scale factor or a parameter).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\n"
      "set style line 1 linecolor rgb \"#1f4e9c\" linewidth 1.5 pointtype 7 pointsize 0.6\n"
      "set style line 2 linecolor rgb \"#c0392b\" linewidth 1.5 pointtype 5 pointsize 0.6\n"
      "set style line 3 linecolor rgb \"#27864a\" linewidth 1.5 pointtype 9 pointsize 0.7\n"
      "set style line 4 linecolor rgb \"#8e44ad\" linewidth 1.5 pointtype 11 pointsize 0.7\n"
      "set style line 5 linecolor rgb \"#d35400\" linewidth 1.5 pointtype 13 pointsize 0.7\n"
      "set style line 6 linecolor rgb \"#555555\" linewidth 1.5 pointtype 3 pointsize 0.7\n"
      "{}",
      fig.name, render_loop(fig, body, font_points(fig, 1000, 1200)));
  return run_script(fig, script);
}

std::vector<fs::path> render_spectrum(const Figure& fig, const std::vector<Series>& series,
                                      const std::string& normalised_x, const std::string& normalised_y) {
  if (series.empty()) throw InputError("spectrum figure: no series to plot");
  static const char* colours[] = {"#601f4e9c", "#60c0392b", "#6027864a", "#608e44ad"};
  auto panel = [&](const std::string& using_spec) {
    std::string cmd;
    for (std::size_t i = 0; i < series.size(); ++i)
      cmd += fmt::format("{}{} skip 1 using {} with points pointtype 5 pointsize 0.9 linecolor rgb \"{}\" title {} noenhanced",
                         i == 0 ? "  plot " : ", \\\n       ", gp_string(series[i].file), using_spec,
                         colours[i % 4], gp_string(series[i].label));
    return cmd + "\n";
  };
  std::string body = fmt::format(
      "  set multiplot layout 1,2 title {} noenhanced\n"
      "  set grid\n"
      "  set key top left box opaque\n"
      "  set xlabel {}\n  set ylabel {}\n",
      gp_string(fig.title), gp_string(normalised_x), gp_string(normalised_y));
  body += panel("1:($5 > 0 ? $2 : NaN)");
  body += "  set xlabel \"pulse period T [s]\"\n  set ylabel \"pulse amplitude a_p / g [-]\"\n";
  body += panel("3:($5 > 0 ? $4 : NaN)");
  const std::string script = fmt::format(
      "# rocking: overturning spectrum (shaded: the block overturns).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\n{}",
      fig.name, render_loop(fig, body, font_points(fig, 1200, 600)));
  return run_script(fig, script);
}

std::vector<fs::path> render_modes(const Figure& fig, const std::string& data_file, const ModePanel& left,
                                   const ModePanel& right) {
  auto panel = [&](const ModePanel& p, std::size_t first_column) {
    std::string cmd = fmt::format("  set title {} noenhanced\n", gp_string(p.title));
    for (std::size_t i = 0; i < p.labels.size(); ++i)
      cmd += fmt::format("{}{} using {}:1 with linespoints linestyle {} title {} noenhanced", i == 0 ? "  plot " : ", \\\n       ",
                         gp_string(data_file), first_column + i, i + 1, gp_string(p.labels[i]));
    return cmd + "\n";
  };
  std::string body = fmt::format(
      "  set multiplot layout 1,2 title {} noenhanced\n"
      "  set grid\n"
      "  set key bottom left box opaque\n"
      "  set xlabel \"lateral displacement (normalised, top = 1) [-]\"\n"
      "  set ylabel \"height [m]\"\n"
      "  set xzeroaxis\n",
      gp_string(fig.title));
  body += panel(left, 2);
  body += panel(right, 2 + left.labels.size());
  const std::string script = fmt::format(
      "# rocking: mode shapes in the style of the paper's Fig. 3.\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: {} (height, then one column per shape).\n"
      "set style line 1 linecolor rgb \"#1f4e9c\" linewidth 2 pointtype 7\n"
      "set style line 2 linecolor rgb \"#c0392b\" linewidth 2 pointtype 5\n"
      "set style line 3 linecolor rgb \"#27864a\" linewidth 2 pointtype 9\n"
      "set style line 4 linecolor rgb \"#8e44ad\" linewidth 2 pointtype 11\n"
      "set style line 5 linecolor rgb \"#d35400\" linewidth 2 pointtype 13\n"
      "{}",
      fig.name, data_file, render_loop(fig, body, font_points(fig, 1200, 800)));
  return run_script(fig, script);
}

}  // namespace rocking::plot
