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

// The figures' colours, in series order, and the point shapes that go with them.
constexpr const char* palette[] = {"1f4e9c", "c0392b", "27864a", "8e44ad", "d35400", "555555"};
constexpr int point_types[] = {7, 5, 9, 11, 13, 3};
constexpr std::size_t palette_size = std::size(palette);

// "set style line i ..." for every colour of the palette.
std::string style_lines(double width, double point_size) {
  std::string out;
  for (std::size_t i = 0; i < palette_size; ++i)
    out += fmt::format("set style line {} linecolor rgb \"#{}\" linewidth {} pointtype {} pointsize {}\n", i + 1,
                       palette[i], width, point_types[i], point_size);
  return out;
}

// One gnuplot plot command over several items (each "file using ... title ...").
std::string plot_command(const std::vector<std::string>& items) {
  std::string cmd;
  for (const std::string& item : items) cmd += (cmd.empty() ? "  plot " : ", \\\n       ") + item;
  return cmd + "\n";
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

}  // namespace

std::vector<fs::path> render_script(const Figure& fig, const std::string& script) {
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

std::pair<int, int> parse_size(const std::string& text, int min_width, int min_height, int max_side) {
  int width = 0, height = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> width >> x >> height) || x != 'x' || !in.eof() || width < min_width || height < min_height ||
      width > max_side || height > max_side)
    throw InputError(fmt::format("--size {}: expected WIDTHxHEIGHT in pixels, {}x{} to {}x{}", text, min_width,
                                 min_height, max_side, max_side));
  return {width, height};
}

std::string find_program(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path != nullptr ? path : "");
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && executable(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return {};
}

std::string find_gnuplot() {
  if (const char* env = std::getenv("ROCKING_GNUPLOT"); env != nullptr && *env != 0) {
    if (!executable(env))
      throw RunError(fmt::format("ROCKING_GNUPLOT={}: not an executable program", env));
    return env;
  }
  std::string found = find_program("gnuplot");
  if (found.empty())
    throw RunError("gnuplot not found on PATH: install gnuplot-nox (scripts/setup.sh does) or set ROCKING_GNUPLOT");
  return found;
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
  auto curves = [&](const std::string& using_spec, bool dampers_only) {
    std::vector<std::string> items;
    for (std::size_t i = 0; i < runs.size(); ++i)
      if (!dampers_only || runs[i].has_damper)
        items.push_back(fmt::format("{} skip 1 using {} with lines linestyle {} title {} noenhanced",
                                    gp_string(runs[i].history), using_spec, i + 1, gp_string(runs[i].label)));
    return items.empty() ? std::string("  plot NaN title \"(no damper)\"\n") : plot_command(items);
  };
  std::string body = fmt::format(
      "  set multiplot layout 4,1 title {} noenhanced\n"
      "  set grid\n"
      "  set key top right box opaque\n"
      "  set xlabel \"time t [s]\"\n"
      "  set ylabel \"total top drift {{/Symbol d}}_t [%]\"\n",
      gp_string(fig.title));
  body += curves("1:($6*100)", false);
  body += "  set ylabel \"elastic top drift {/Symbol d}_e [%]\"\n";
  body += curves("1:($7*100)", false);
  body += "  set ylabel \"rocking angle {/Symbol q}/{/Symbol a}_{cg} [-]\"\n";
  body += curves("1:5", false);
  body += "  set xlabel \"damper elongation d [mm] (signed by the pivot)\"\n"
          "  set ylabel \"damper force F_{hd} [kN]\"\n";
  // Break the loop where no damper is stretched (d = 0: full contact, and the
  // impacts where one edge's damper hands over to the other's).
  body += curves("($8 == 0 ? NaN : $8*1000):($9/1000)", true);
  const std::string script = fmt::format(
      "# rocking: response figure in the style of the paper's Fig. 4.\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: rocking simulate history CSV (t, phase, u_N, theta, theta/alpha_cg,\n"
      "# delta_t, delta_e, d, F_hd, base/mid shear and moment).\n"
      "set datafile separator \",\"\n"
      "{}{}",
      fig.name, style_lines(1.5, 0.6), render_loop(fig, body, font_points(fig, 1000, 1300)));
  return render_script(fig, script);
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
    std::vector<std::string> items;
    for (std::size_t i = 0; i < series.size(); ++i)
      items.push_back(fmt::format("{} skip 1 using {} with linespoints linestyle {} title {} noenhanced",
                                  gp_string(series[i].file), p.using_spec, i + 1, gp_string(series[i].label)));
    body += plot_command(items);
  }
  const std::string script = fmt::format(
      "# rocking: study figure (peaks against the scale factor or a parameter).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\n"
      "{}{}",
      fig.name, style_lines(1.5, 0.7), render_loop(fig, body, font_points(fig, 1000, 1200)));
  return render_script(fig, script);
}

std::vector<fs::path> render_spectrum(const Figure& fig, const std::vector<Series>& series,
                                      const std::string& normalised_x, const std::string& normalised_y) {
  if (series.empty()) throw InputError("spectrum figure: no series to plot");
  auto panel = [&](const std::string& using_spec) {
    std::vector<std::string> items;
    for (std::size_t i = 0; i < series.size(); ++i)  // the palette, 60 % transparent ("#AARRGGBB")
      items.push_back(fmt::format("{} skip 1 using {} with points pointtype 5 pointsize 0.9 linecolor rgb \"#60{}\" "
                                  "title {} noenhanced",
                                  gp_string(series[i].file), using_spec, palette[i % palette_size],
                                  gp_string(series[i].label)));
    return plot_command(items);
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
  return render_script(fig, script);
}

std::vector<fs::path> render_modes(const Figure& fig, const std::string& data_file, const ModePanel& left,
                                   const ModePanel& right) {
  auto panel = [&](const ModePanel& p, std::size_t first_column) {
    std::vector<std::string> items;
    for (std::size_t i = 0; i < p.labels.size(); ++i)
      items.push_back(fmt::format("{} using {}:1 with linespoints linestyle {} title {} noenhanced", gp_string(data_file),
                                  first_column + i, i + 1, gp_string(p.labels[i])));
    return fmt::format("  set title {} noenhanced\n", gp_string(p.title)) + plot_command(items);
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
      "{}{}",
      fig.name, data_file, style_lines(2, 1), render_loop(fig, body, font_points(fig, 1200, 800)));
  return render_script(fig, script);
}

}  // namespace rocking::plot
