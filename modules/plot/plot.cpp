module;
#include <cstdio>
#include <csignal>
#include <algorithm>
#include <array>
#include <cmath>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include <fmt/format.h>
module rocking.plot;
import rocking.errors;
import rocking.geometry;
import rocking.quantities;

namespace rocking::plot {

namespace fs = std::filesystem;

namespace {

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
// Series i's dash (gnuplot dash type), so that lines read apart in greyscale print.
std::size_t series_dash(std::size_t i) { return i % 4 + 1; }

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
      quote(formats), fmt::arg("w", fig.width), fmt::arg("h", fig.height), fmt::arg("wi", fig.width / 100.0),
      fmt::arg("hi", fig.height / 100.0), fmt::arg("name", quote(fig.name)), fmt::arg("body", body),
      fmt::arg("pt", points));
}

// Pixels of one line of text at `points` (cairo terminals: about 1.33 px per
// point, and line spacing 1.25).
double line_px(int points) { return 1.7 * points; }

// A multiplot of rows x cols panels placed by their margins, with room above
// them for the title and for a key shared by every panel. The key is a plot
// of its own spanning the figure's width (a key placed inside one panel of a
// grid wraps to that panel's width), drawn last.
struct Grid {
  std::string begin;               // starts the multiplot, with the title
  std::vector<std::string> panels; // places panel k (row-major)
  double key_bottom = 0, key_top = 0;
  int key_columns = 1;
};
Grid shared_key_grid(const Figure& fig, int rows, int cols, int points, const std::vector<std::string>& labels,
                     int panel_title_lines = 0) {
  const double W = fig.width, H = fig.height, line = line_px(points);
  // gnuplot gives every column of a key the width of its longest entry.
  std::size_t longest = 0;
  for (const std::string& l : labels) longest = std::max(longest, l.size());
  const double column_px = (static_cast<double>(longest) * 0.62 + 8) * points;
  const int columns = std::clamp(static_cast<int>(0.96 * W / column_px), 1, std::max<int>(1, static_cast<int>(labels.size())));
  const int key_rows = labels.empty() ? 0 : (static_cast<int>(labels.size()) + columns - 1) / columns;
  const int title_lines = 1 + static_cast<int>(std::count(fig.title.begin(), fig.title.end(), '\n'));
  const double title_px = 0.8 * line + title_lines * line;
  const double left = 8.5 * points / W, right = 1 - 3.0 * points / W;  // room for the last tick label
  const double bottom = 3.4 * line / H,
               top = 1 - (title_px + key_rows * line + (0.8 + 1.3 * panel_title_lines) * line) / H;
  const double xgap = 9.0 * points / W, ygap = (3.6 + 1.3 * panel_title_lines) * line / H;
  const double width = (right - left - (cols - 1) * xgap) / cols, height = (top - bottom - (rows - 1) * ygap) / rows;
  Grid g;
  g.begin = fmt::format("  set multiplot title {} noenhanced\n", quote(fig.title));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x0 = left + c * (width + xgap), y1 = top - r * (height + ygap);
      g.panels.push_back(fmt::format("  set lmargin at screen {:.4f}\n  set rmargin at screen {:.4f}\n"
                                     "  set tmargin at screen {:.4f}\n  set bmargin at screen {:.4f}\n",
                                     x0, x0 + width, y1, y1 - height));
    }
  g.key_top = 1 - title_px / H;
  g.key_bottom = top + (0.3 + 1.3 * panel_title_lines) * line / H;
  g.key_columns = columns;
  return g;
}

// The shared key: a plot of nothing but the key's entries ("NaN with lines
// linestyle 1 title ..."), in the band above the panels; restores what it unset.
std::string key_plot(const Grid& g, const std::vector<std::string>& entries) {
  if (entries.empty()) return {};
  return fmt::format(
             "  set lmargin at screen 0.02\n  set rmargin at screen 0.98\n"
             "  set tmargin at screen {:.4f}\n  set bmargin at screen {:.4f}\n"
             "  unset border\n  unset tics\n  unset xlabel\n  unset ylabel\n  unset grid\n  unset logscale\n"
             "  set xrange [0:1]\n  set yrange [0:1]\n"
             "  set key center center {} maxcols {} nobox noopaque samplen 2.5 width 2\n",
             // One column laid out "horizontal" loses its entries ("difficulty
             // fitting plot titles into key"); "vertical" draws the same column.
             g.key_top, g.key_bottom, g.key_columns == 1 ? "vertical" : "horizontal", g.key_columns) +
         plot_command(entries) +
         "  set border\n  set tics\n  set xrange [*:*]\n  set yrange [*:*]\n  unset key\n";
}

void write_script(const fs::path& file, const std::string& text) {
  std::ofstream out(file);
  out << text;
  out.close();
  if (!out) throw RunError(fmt::format("{}: cannot write the gnuplot script", file.string()));
}

// Whether a figure file ends as its format ends (a disk that filled while
// gnuplot wrote it leaves a file cut short): PNG's IEND chunk, PDF's %%EOF,
// SVG's closing tag, GIF's trailer byte.
bool complete(const fs::path& file, const std::string& format) {
  std::ifstream in(file, std::ios::binary);
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (!in || ec || size == 0) return false;
  const auto tail_size = static_cast<std::streamoff>(std::min<std::uintmax_t>(size, 64));
  in.seekg(-tail_size, std::ios::end);
  std::string tail(static_cast<std::size_t>(tail_size), '\0');
  in.read(tail.data(), tail_size);
  if (format == "png") return tail.size() >= 8 && tail.compare(tail.size() - 8, 4, "IEND") == 0;
  if (format == "pdf") return tail.find("%%EOF") != std::string::npos;
  if (format == "svg") return tail.find("</svg>") != std::string::npos;
  if (format == "gif") return tail.back() == ';';
  return true;
}

bool executable(const fs::path& p) { return ::access(p.c_str(), X_OK) == 0 && fs::is_regular_file(p); }

}  // namespace

std::string column(std::string_view name) {
  const bool plain = !name.empty() && std::ranges::all_of(name, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || std::string_view("_.-/ []").find(c) != std::string_view::npos;
  });
  if (!plain) throw InputError(fmt::format("gnuplot column {}: not a header name the program writes", quote(name)));
  return fmt::format("column('{}')", name);
}

std::string quote(std::string_view text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\n') {
      out += "' . \"\\n\" . '";
      continue;
    }
    if (c == '\'') out += '\'';
    out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? ' ' : c;
  }
  return out + "'";
}

std::string comment(std::string_view text) {
  std::string out(text);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return out;
}

void check_name(const std::string& name, const std::string& option) {
  const bool control = std::any_of(name.begin(), name.end(),
                                   [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos || control)
    throw InputError(fmt::format("{} {}: a file name without a folder (no '/', not '.' or '..', no control "
                                 "characters); --out chooses the folder",
                                 option, comment(name)));
}

namespace {
bool (*interrupt_requested)() = nullptr;
}  // namespace

int run_program(const fs::path& dir, const std::vector<std::string>& argv, const fs::path& log) {
  if (argv.empty()) return -1;
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, dir.c_str());
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  if (interrupt_requested == nullptr) {
    while (::waitpid(pid, &status, 0) < 0)
      if (errno != EINTR) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  // Polled every 20 ms: a stop ends the program within that.
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (done < 0 && errno != EINTR) return -1;
    if (interrupt_requested()) {
      ::kill(pid, SIGTERM);
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      return -1;
    }
    ::usleep(20000);
  }
}

void set_interrupt(bool (*requested)()) { interrupt_requested = requested; }

std::vector<fs::path> render_script(const Figure& fig, const std::string& script) {
  check_name(fig.name, "figure name");
  std::error_code ec;
  fs::create_directories(fig.dir, ec);
  if (ec || !fs::is_directory(fig.dir))
    throw InputError(fmt::format("{}: cannot create the output folder{}{}", fig.dir.string(), ec ? ": " : "",
                                 ec ? ec.message() : ""));
  const fs::path gp = fig.dir / (fig.name + ".gp");
  write_script(gp, script);
  const std::string gnuplot = find_gnuplot();
  const fs::path log = fig.dir / (fig.name + ".gnuplot.log");
  for (const std::string& f : fig.formats) fs::remove(fig.dir / (fig.name + "." + f), ec);
  // gnuplot runs in the figure's folder, as the script's relative paths expect.
  const fs::path where = fs::absolute(fig.dir, ec);
  const int status = run_program(where, {gnuplot, gp.filename().string()}, where / log.filename());
  std::vector<fs::path> written;
  for (const std::string& f : fig.formats) {
    const fs::path out = fig.dir / (fig.name + "." + f);
    if (fs::is_regular_file(out) && fs::file_size(out) > 0) written.push_back(out);
    if (status == 0 && fs::is_regular_file(out) && !complete(out, f))
      throw RunError(fmt::format("{}: gnuplot wrote it incomplete (a full disk?)", out.string()));
  }
  if (status != 0 || written.size() != fig.formats.size()) {
    // A gnuplot that failed or was stopped may have left a figure cut short
    // under its final name: none stays.
    if (status != 0)
      for (const std::string& f : fig.formats) fs::remove(fig.dir / (fig.name + "." + f), ec);
    if (interrupt_requested != nullptr && interrupt_requested())
      throw RunError(fmt::format("{}: stopped while gnuplot drew it", gp.string()));
    std::ifstream in(log);
    std::string first, line;
    while (std::getline(in, line))
      if (!line.empty()) { first = line; break; }
    throw RunError(fmt::format("gnuplot failed on {} (see {}){}{}", gp.string(), log.string(),
                               first.empty() ? "" : ": ", comment(first)));
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
    if (!dir.empty() && executable(fs::path(dir) / name)) return fs::absolute(fs::path(dir) / name).string();
  return {};
}

std::string find_gnuplot() {
  if (const char* env = std::getenv("ROCKING_GNUPLOT"); env != nullptr && *env != 0) {
    if (!executable(env))
      throw RunError(fmt::format("ROCKING_GNUPLOT={}: not an executable program", env));
    return fs::absolute(env).string();
  }
  std::string found = find_program("gnuplot");
  if (found.empty())
    throw RunError("gnuplot not found on PATH: install gnuplot-nox (scripts/setup.sh does) or set ROCKING_GNUPLOT");
  return found;
}

int HistoryContent::column(std::string_view name) const {
  for (const auto& [n, k] : columns)
    if (n == name) return k;
  return 0;
}

std::string HistoryContent::header(std::string_view name) const {
  const int k = column(name);
  return k > 0 ? headers[static_cast<std::size_t>(k - 1)] : std::string();
}

bool HistoryContent::moves(std::string_view name) const {
  const int k = column(name);
  return k > 0 && nonzero[static_cast<std::size_t>(k - 1)];
}

HistoryContent check_history(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: history file not found", file.string()));
  std::stringstream whole;
  whole << in.rdbuf();
  const std::string text = whole.str();
  HistoryContent content;
  const auto name = [](Quantity q) { return info(q).name; };
  int theta = 0, delta_e = 0, a_g = 0, damper_d = 0, phase = 0;
  int rows = 0;
  std::size_t fields = 0;
  std::size_t at = 0;
  for (int n = 1; at < text.size(); ++n) {
    const std::size_t eol = text.find('\n', at);
    // A history is written in whole rows: one that the file ends inside was cut.
    if (eol == std::string::npos)
      throw InputError(fmt::format("{}:{}: the file ends inside this row (no line end): a cut history; plot a "
                                   "complete run's", file.string(), n));
    const std::string line = text.substr(at, eol - at);
    at = eol + 1;
    if (n == 1) {
      if (!line.starts_with("t [s],")) throw InputError(fmt::format("{}:1: not a rocking history (header 't [s],...')", file.string()));
      std::stringstream header(line);
      int k = 0;
      for (std::string field; std::getline(header, field, ',');) {
        const auto unit = field.find(" [");
        content.columns.emplace_back(field.substr(0, unit), ++k);
        content.headers.push_back(field);
        if (const auto joint = parse_joint_quantity(content.columns.back().first))
          content.joints = std::max(content.joints, joint->joint);
      }
      fields = content.columns.size();
      content.nonzero.assign(fields, false);
      const std::string elongation = fmt::format(".{}", info(DeviceQuantity::elongation).name);
      for (const auto& [c, k2] : content.columns)
        if (c.ends_with(elongation) && content.column(c.substr(0, c.size() - elongation.size()) + "." +
                                                      std::string(info(DeviceQuantity::force).name)) > 0)
          content.devices.push_back(c.substr(0, c.size() - elongation.size()));
      theta = content.column(name(Quantity::theta));
      delta_e = content.column(name(Quantity::delta_e));
      a_g = content.column(name(Quantity::a_g));
      damper_d = content.column(name(Quantity::damper_d));
      phase = content.column(name(Quantity::phase));
      content.ground = a_g > 0;
      continue;
    }
    if (line.empty()) continue;
    // Every row whole: the header's number of fields, each a finite number,
    // empty (a broken device's value) or the phase's label.
    std::vector<double> row;
    std::size_t start = 0;
    for (std::size_t k = 1;; ++k) {
      const std::size_t comma = line.find(',', start);
      const std::string field = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (k > fields)
        throw InputError(fmt::format("{}:{}: more fields than the header's {}: not a rocking history", file.string(), n,
                                     fields));
      double v = 0;
      if (static_cast<int>(k) == phase && (field == "contact" || field == "rock+" || field == "rock-")) {
        v = field == "contact" ? 0 : 1;
      } else if (!field.empty()) {
        char* end = nullptr;
        v = std::strtod(field.c_str(), &end);
        if (end != field.c_str() + field.size() || !std::isfinite(v))
          throw InputError(fmt::format("{}:{}: '{:.20}' in column {}: not a finite number", file.string(), n, field,
                                       content.columns[k - 1].first));
      }
      row.push_back(v);
      if (v != 0 && std::isfinite(v)) content.nonzero[k - 1] = true;
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    if (row.size() != fields)
      throw InputError(fmt::format("{}:{}: {} fields where the header has {}: a cut or foreign row", file.string(), n,
                                   row.size(), fields));
    ++rows;
    auto value = [&](int k) { return k > 0 ? row[static_cast<std::size_t>(k - 1)] : 0.0; };
    content.rocks = content.rocks || value(theta) != 0;
    content.elastic = content.elastic || value(delta_e) != 0;
    content.ground_moves = content.ground_moves || value(a_g) != 0;
    content.has_damper = content.has_damper || value(damper_d) != 0;
  }
  if (rows < 2) throw InputError(fmt::format("{}: empty history ({} rows): nothing to plot", file.string(), rows));
  content.rows = rows;
  // The response figure's one panel every run has: the drift.
  if (content.column(name(Quantity::delta_t)) == 0)
    throw InputError(fmt::format("{}:1: no {} column: the response figure draws the drift (a history of "
                                 "`rocking simulate` with its default columns, or --history {},...)",
                                 file.string(), name(Quantity::delta_t), name(Quantity::delta_t)));
  return content;
}

namespace {

// The histories of a response figure's runs and what is drawn from them: each
// run's columns found by name, and the curves, loops and end markers made of
// them. Each run has its colour (linestyle i + 1, with its point type) and its
// dash (series_dash); the first run is drawn last, over the others it is
// compared with.
class ResponseRuns {
 public:
  ResponseRuns(const Figure& fig, const std::vector<ResponseSeries>& runs) : runs_(runs), end_drawn_(runs.size(), false) {
    for (const ResponseSeries& r : runs)
      contents_.push_back(check_history(fs::path(r.history).is_absolute() ? fs::path(r.history) : fig.dir / r.history));
  }
  const std::vector<ResponseSeries>& runs() const { return runs_; }
  const std::vector<HistoryContent>& contents() const { return contents_; }
  std::size_t size() const { return runs_.size(); }

  // Devices besides the paper's edge dampers (whose pair comes with the
  // damper_d column): a tendon, a scene's own dampers. With some, the figure
  // draws each device's loop and the devices' moment (the loops of
  // quantities that need devices); without, the paper's one signed damper
  // loop (those that need the paper's dampers).
  bool other_devices() const {
    return std::ranges::any_of(contents_, [](const HistoryContent& c) {
      return c.devices.size() > (c.column(info(Quantity::damper_d).name) > 0 ? std::size_t{2} : std::size_t{0});
    });
  }
  bool any_run_has(std::string_view name) const {
    return std::ranges::any_of(contents_, [&](const HistoryContent& c) { return c.column(name) > 0; });
  }
  // The most joints above the base of any run.
  int joints() const { return std::ranges::max(contents_, {}, &HistoryContent::joints).joints; }

  // A column of run i's history as a gnuplot expression, by its header name
  // ("column('delta_t [-]')"); empty when the history has none.
  std::string col(std::size_t i, std::string_view name) const {
    const std::string h = contents_[i].header(name);
    return h.empty() ? std::string() : column(h);
  }
  // A quantity against time, in its figure unit.
  std::string in_time(std::size_t i, std::string_view name, double factor) const {
    const std::string t = col(i, info(Quantity::t).name), c = col(i, name);
    return t.empty() || c.empty() ? std::string() : fmt::format("({}):({}*{:.9g})", t, c, factor);
  }
  // A loop: y against x, in their figure units, broken where either is zero
  // (d = 0: full contact, and the impacts where one edge's damper hands over
  // to the other's; F = 0: a broken device).
  std::string loop(std::size_t i, std::string_view x, double fx, std::string_view y, double fy) const {
    const std::string cx = col(i, x), cy = col(i, y);
    return cx.empty() || cy.empty() ? std::string()
                                    : fmt::format("({} == 0 || {} == 0 ? NaN : {}*{:.9g}):({}*{:.9g})", cx, cy, cx, fx,
                                                  cy, fy);
  }
  // One curve per run whose spec(i) (its `using` columns) is not empty, the
  // first run last.
  template <class Spec>
  std::vector<std::string> curve_items(Spec&& spec) const {
    std::vector<std::string> items;
    for (std::size_t i = runs_.size(); i-- > 0;) {
      const std::string using_spec = spec(i);
      if (using_spec.empty()) continue;
      items.push_back(fmt::format("{} using {} with lines linestyle {} dashtype {} title {} noenhanced",
                                  quote(runs_[i].history), using_spec, i + 1, series_dash(i), quote(runs_[i].label)));
    }
    return items;
  }

  // A separated run (RunEnd) stops where a joint turned tensile: its run's
  // point shape, large, in its colour, on the last row of the curve of that
  // joint's angle (the base's theta / alpha_cg, joint K's jointK.theta, the
  // columns' theta / alpha on a rocking frame), and a key entry in words. The
  // words are the program's own (a joint's number), never a run's label.
  static constexpr const char* end_marker = "pointsize 2.2";
  static std::string end_words(const RunEnd& e) {
    if (!e.joint) return std::string("a column top separates");
    return *e.joint == 0 ? std::string("the base separates") : fmt::format("joint {} separates", *e.joint);
  }
  // The column whose curve carries run i's end marker; empty when it did not separate.
  std::string end_column(std::size_t i) const {
    const RunEnd& e = runs_[i].end;
    if (!e.separated) return std::string();
    if (!e.joint) return std::string(info(Quantity::columns_theta_over_alpha).name);
    if (*e.joint == 0) return std::string(info(Quantity::theta_over_alpha).name);
    return JointQuantityName{*e.joint, JointQuantity::theta}.name();
  }
  // The end markers on the curves of a quantity, each run's noted as drawn (end_drawn) for the key.
  std::vector<std::string> end_items(std::string_view name, double factor) {
    std::vector<std::string> items;
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      const std::string spec = in_time(i, name, factor);
      if (!ends_on(i, name) || spec.empty()) continue;
      const int last = contents_[i].rows - 1;
      items.push_back(fmt::format("{} using {} every ::{}::{} with points linestyle {} {} notitle",
                                  quote(runs_[i].history), spec, last, last, i + 1, end_marker));
      end_drawn_[i] = true;
    }
    return items;
  }
  bool end_drawn(std::size_t i) const { return end_drawn_[i]; }

 private:
  bool ends_on(std::size_t i, std::string_view name) const {
    const std::string c = end_column(i);
    return !c.empty() && c == name;
  }
  const std::vector<ResponseSeries>& runs_;
  std::vector<HistoryContent> contents_;  // per run: its columns, found by name
  std::vector<bool> end_drawn_;
};

// A panel of the response figure, from the schema.
struct PlannedPanel {
  unsigned char rank;
  std::size_t order;  // in the schema's tables, for panels of one rank
  FigureRole role;
  std::optional<Quantity> scalar;        // a scalar quantity's panel, or ...
  std::optional<DeviceQuantity> device;  // ... the devices' loops, or ...
  std::optional<JointQuantity> joint;    // ... the joints'
};

// The panels the schema's figure roles give for what the runs hold, in the
// order of their ranks: a quantity's panel when some run has it (the
// excitation when the first run's ground moves; a loop when some run's loop
// has a point, of the paper's dampers or of the other devices as the runs
// have them), the devices' loops, the joints' panels.
std::vector<PlannedPanel> response_panels(const ResponseRuns& runs) {
  const std::vector<HistoryContent>& contents = runs.contents();
  const bool other_devices = runs.other_devices();
  std::vector<PlannedPanel> plan;
  for (const QuantityInfo& q : quantity_table) {
    const FigureUse use = q.figure;
    if (use.role == FigureRole::none || !runs.any_run_has(q.name)) continue;
    if (use.role == FigureRole::excitation &&
        !(contents.front().column(q.name) > 0 &&
          std::ranges::any_of(contents, [&](const HistoryContent& c) { return c.moves(q.name); })))
      continue;  // no panel for a ground that stays still
    // A loop is broken where x or y is zero: no panel when no run's loop has a point.
    if (use.role == FigureRole::loop &&
        (!std::ranges::any_of(contents, [&](const HistoryContent& c) { return c.moves(info(q.figure_x).name) && c.moves(q.name); }) ||
         (q.needs == Needs::devices && !other_devices) || (q.needs == Needs::dampers && other_devices)))
      continue;
    plan.push_back({use.rank, plan.size(), use.role, q.id, std::nullopt, std::nullopt});
  }
  if (other_devices)
    for (const DeviceQuantityInfo& q : device_quantity_table)
      if (q.figure.role == FigureRole::loop &&
          std::ranges::any_of(contents, [&](const HistoryContent& c) {
            return std::ranges::any_of(c.devices, [&](const std::string& d) {
              return c.moves(device_quantity_name(d, q.figure_x)) && c.moves(device_quantity_name(d, q.id));
            });
          }))
        plan.push_back({q.figure.rank, plan.size(), q.figure.role, std::nullopt, q.id, std::nullopt});
  const int joints = runs.joints();
  for (std::size_t k = 0; k < joint_quantity_count && joints > 0; ++k)
    if (joint_quantity_table[k].figure.role == FigureRole::joints)
      plan.push_back({joint_quantity_table[k].figure.rank, plan.size(), FigureRole::joints, std::nullopt, std::nullopt,
                      static_cast<JointQuantity>(k)});
  std::ranges::sort(plan, [](const PlannedPanel& a, const PlannedPanel& b) {
    return a.rank != b.rank ? a.rank < b.rank : a.order < b.order;
  });
  return plan;
}

// A y label longer than its panel (panel_px) is tall goes on as many lines as
// it needs, broken between its words (the symbol and the unit whole): about
// 0.6 em a visible character, enhanced text's markup left out.
std::string wrapped_ylabel(const Figure& fig, double panel_px, std::string_view words, std::string_view symbol,
                           std::string_view unit) {
  const auto visible = [](std::string_view text) {
    std::size_t n = 0;
    for (std::size_t k = 0; k < text.size(); ++k) {
      if (text.compare(k, 9, "{/Symbol ") == 0) k += 8;
      else if (text[k] != '{' && text[k] != '}' && text[k] != '_' && text[k] != '^') ++n;
    }
    return n;
  };
  std::vector<std::string> tokens;
  const std::string text(axis_words(words));
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find(' ', at), text.size());
    if (end > at) tokens.push_back(text.substr(at, end - at));
    at = end + 1;
  }
  tokens.emplace_back(symbol);
  tokens.push_back(fmt::format("[{}]", unit));
  const auto fits = static_cast<std::size_t>(std::max(8.0, panel_px / (0.6 * font_points(fig, 1000, 1300))));
  std::vector<std::string> lines{tokens.front()};
  for (std::size_t k = 1; k < tokens.size(); ++k) {
    if (visible(lines.back()) + 1 + visible(tokens[k]) <= fits) lines.back() += " " + tokens[k];
    else lines.push_back(tokens[k]);
  }
  std::vector<std::string> quoted;
  for (const std::string& l : lines) quoted.push_back(quote(l));
  return fmt::format("  set ylabel {}\n", fmt::join(quoted, " . \"\\n\" . "));
}

// A response panel's y axis spans at least +-0.001 of its display unit
// (gnuplot's autoscale bounds): a response that stays at round-off (a joint
// that never opens, a base that does not lift) is drawn flat on that axis,
// not magnified into noise, nor on gnuplot's -1..1 for an all-zero curve.
constexpr const char* smallest_span = "  set yrange [*<-0.001:0.001<*]\n";

// Each device's dash pattern, and each joint's marker when there are
// several, named in an axis label so that no key covers the curves.
constexpr std::array<const char*, 5> device_dashes{"solid", "dashed", "dotted", "dash-dot", "dash-dot-dot"};
struct JointMarker {
  int pointtype;
  const char* words;
};
constexpr std::array<JointMarker, 5> joint_markers{JointMarker{6, "circles"}, JointMarker{8, "triangles"},
                                                   JointMarker{4, "squares"}, JointMarker{10, "inverted triangles"},
                                                   JointMarker{12, "diamonds"}};
const JointMarker& joint_marker(int joint) {
  return joint_markers[static_cast<std::size_t>(joint - 1) % joint_markers.size()];
}

// The panels' bodies: each sets its axes and plots its curves.
class ResponsePanels {
 public:
  ResponsePanels(const Figure& fig, ResponseRuns& runs, double panel_px, bool device_panels)
      : fig_(fig), runs_(runs), panel_px_(panel_px), device_panels_(device_panels) {}

  std::string body(const PlannedPanel& pl) {
    if (pl.role == FigureRole::excitation) return excitation_panel(info(*pl.scalar));
    if (pl.role == FigureRole::response) return response_panel(info(*pl.scalar));
    if (pl.joint) return joint_panel(info(*pl.joint), *pl.joint);
    if (pl.device) return device_loop_panel(info(*pl.device));
    return scalar_loop_panel(info(*pl.scalar));
  }

 private:
  std::string scalar_ylabel(Quantity q) const {
    return wrapped_ylabel(fig_, panel_px_, info(q).words, info(q).symbol, info(q).figure_unit);
  }
  // The excitation the response answers, the first run's.
  std::string excitation_panel(const QuantityInfo& q) const {
    return scalar_ylabel(q.id) + fmt::format("  plot {} using {} with lines linecolor rgb \"#555555\" notitle\n",
                                             quote(runs_.runs().front().history), runs_.in_time(0, q.name, q.figure_factor));
  }
  // A quantity against time, one curve per run, with the end markers on it.
  std::string response_panel(const QuantityInfo& q) {
    std::string out = scalar_ylabel(q.id) + smallest_span;
    std::vector<std::string> items =
        runs_.curve_items([&](std::size_t i) { return runs_.in_time(i, q.name, q.figure_factor); });
    for (std::string& item : runs_.end_items(q.name, q.figure_factor)) items.push_back(std::move(item));
    return out + plot_command(items) + "  set yrange [*:*]\n";
  }
  // Each joint above the base against time, in its run's colour and dash (as
  // the key draws the run); with several joints, one marker per joint (the
  // same in every run), named in the x label.
  std::string joint_panel(const JointQuantityInfo& q, JointQuantity which) {
    const int joints = runs_.joints();
    std::string out;
    if (joints > 1) {
      std::vector<std::string> legend;
      for (int j = 1; j <= joints; ++j) legend.push_back(fmt::format("{} joint {}", joint_marker(j).words, j));
      out += fmt::format("  set xlabel {} noenhanced\n",
                         quote(fmt::format("{}   ({})", axis_label(Quantity::t), fmt::join(legend, ", "))));
    }
    out += wrapped_ylabel(fig_, panel_px_, q.words, q.symbol, q.figure_unit);
    out += smallest_span;
    std::vector<std::string> items;
    for (std::size_t i = runs_.size(); i-- > 0;)
      for (int j = 1; j <= runs_.contents()[i].joints; ++j) {
        const std::string spec = runs_.in_time(i, JointQuantityName{j, which}.name(), q.figure_factor);
        if (spec.empty()) continue;
        const std::string marker = joints > 1 ? fmt::format(" pointtype {} pointnumber 12", joint_marker(j).pointtype)
                                   : device_panels_ ? std::string(" pointnumber 12")
                                                    : std::string();
        items.push_back(fmt::format("{} using {} with {} linestyle {} dashtype {}{} notitle",
                                    quote(runs_.runs()[i].history), spec, marker.empty() ? "lines" : "linespoints",
                                    i + 1, series_dash(i), marker));
      }
    for (int j = 1; j <= joints; ++j)
      for (std::string& item : runs_.end_items(JointQuantityName{j, which}.name(), q.figure_factor))
        items.push_back(std::move(item));
    out += plot_command(items);
    out += "  set yrange [*:*]\n";
    // The time axis's own label again for the panels below.
    if (joints > 1) out += fmt::format("  set xlabel {}\n", quote(axis_label(Quantity::t)));
    return out;
  }
  // Each device's force against its elongation, in its run's colour and with
  // its run's markers (about a dozen along the run), with one dash pattern
  // per device name (the same in every run), named in the axis label so that
  // no key covers the loops.
  std::string device_loop_panel(const DeviceQuantityInfo& y_info) const {
    std::vector<std::string> names;
    for (const HistoryContent& c : runs_.contents())
      for (const std::string& name : c.devices)
        if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    std::vector<std::string> legend;
    for (std::size_t k = 0; k < names.size(); ++k)
      legend.push_back(fmt::format("{} {}", device_dashes[k % device_dashes.size()], names[k]));
    const DeviceQuantityInfo& x_info = info(y_info.figure_x);
    std::string out = fmt::format("  set autoscale x\n  set xlabel {} noenhanced\n",
                                  quote(fmt::format("device {} {} [{}]   ({})", x_info.words, x_info.symbol,
                                                    x_info.figure_unit, fmt::join(legend, ", ")))) +
                      fmt::format("  set ylabel {}\n",
                                  quote(fmt::format("device {} {} [{}]", y_info.words, y_info.symbol, y_info.figure_unit)));
    std::vector<std::string> items;
    for (std::size_t i = runs_.size(); i-- > 0;)
      for (const std::string& device : runs_.contents()[i].devices) {
        const auto dash = std::find(names.begin(), names.end(), device) - names.begin();
        const std::string spec = runs_.loop(i, device_quantity_name(device, x_info.id), x_info.figure_factor,
                                            device_quantity_name(device, y_info.id), y_info.figure_factor);
        if (spec.empty()) continue;
        items.push_back(fmt::format("{} using {} with linespoints linestyle {} dashtype {} pointnumber 12 notitle",
                                    quote(runs_.runs()[i].history), spec, i + 1,
                                    static_cast<std::size_t>(dash) % device_dashes.size() + 1));
      }
    return out + plot_command(items);
  }
  // A scalar loop: the paper's damper, the devices' moment against theta.
  std::string scalar_loop_panel(const QuantityInfo& y) const {
    const QuantityInfo& x = info(y.figure_x);
    return fmt::format("  set autoscale x\n  set xlabel {} enhanced\n", quote(axis_label(x.id))) + scalar_ylabel(y.id) +
           plot_command(runs_.curve_items(
               [&](std::size_t i) { return runs_.loop(i, x.name, x.figure_factor, y.name, y.figure_factor); }));
  }

  const Figure& fig_;
  ResponseRuns& runs_;
  double panel_px_;
  bool device_panels_;
};

// The key's labels, for its layout: the runs', then the words of each end
// marker a run may draw.
std::vector<std::string> response_key_labels(const ResponseRuns& runs) {
  std::vector<std::string> labels;
  for (const ResponseSeries& r : runs.runs()) labels.push_back(r.label);
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (!runs.end_column(i).empty() && runs.contents()[i].column(runs.end_column(i)) > 0)
      labels.push_back(ResponseRuns::end_words(runs.runs()[i].end));
  return labels;
}

// The key's entries: each run as its curves draw it (with the markers the
// devices' loops carry), then each end marker drawn.
std::vector<std::string> response_key_entries(const ResponseRuns& runs, bool device_panels) {
  std::vector<std::string> entries;
  for (std::size_t i = 0; i < runs.size(); ++i)
    entries.push_back(fmt::format("NaN with {} linestyle {} dashtype {} title {} noenhanced",
                                  device_panels ? "linespoints" : "lines", i + 1, series_dash(i),
                                  quote(runs.runs()[i].label)));
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (runs.end_drawn(i))
      entries.push_back(fmt::format("NaN with points linestyle {} {} title {} noenhanced", i + 1,
                                    ResponseRuns::end_marker, quote(ResponseRuns::end_words(runs.runs()[i].end))));
  return entries;
}

// The response figure's gnuplot script around its body.
std::string response_script(const Figure& fig, const std::string& body, int points) {
  return fmt::format(
      "# rocking: response figure in the style of the paper's Fig. 4.\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: rocking simulate history CSVs, their columns read by their header\n"
      "# names (rocking simulate --list-quantities).\n"
      "set datafile separator \",\"\n"
      "set datafile columnheaders\n"
      "{}{}",
      fig.name, style_lines(1.5, 0.6), render_loop(fig, body, points));
}

}  // namespace

std::vector<fs::path> render_response(const Figure& fig, const std::vector<ResponseSeries>& runs) {
  if (runs.empty()) throw InputError("response figure: no runs to plot");
  ResponseRuns histories(fig, runs);
  const std::vector<PlannedPanel> plan = response_panels(histories);
  const int panels = static_cast<int>(plan.size());
  // The key draws the runs with their markers when the devices' loops carry them.
  const bool device_panels = std::ranges::any_of(plan, [](const PlannedPanel& p) { return p.device.has_value(); });
  const int points = font_points(fig, 1000, 1300);
  const Grid grid = shared_key_grid(fig, panels, 1, points, response_key_labels(histories));
  // The time axis (set first, and again by a time panel that follows a loop).
  const std::string time_label = fmt::format("  set autoscale xfix\n  set xlabel {}\n", quote(axis_label(Quantity::t)));
  const std::string time_range = fig.time_range.empty() ? "" : fmt::format("  set xrange {}\n", fig.time_range);
  const std::string time_axis = time_label + time_range;
  std::string body = grid.begin + "  set grid\n" + time_label + "  unset key\n" + time_range;
  ResponsePanels bodies(fig, histories, 0.8 * fig.height / std::max(panels, 1), device_panels);
  bool x_is_time = true;
  for (std::size_t p = 0; p < plan.size(); ++p) {
    body += grid.panels[p];
    const bool in_time_panel = plan[p].role != FigureRole::loop;
    if (in_time_panel && !x_is_time) body += time_axis;
    x_is_time = in_time_panel;
    body += bodies.body(plan[p]);
  }
  body += key_plot(grid, response_key_entries(histories, device_panels));
  return render_script(fig, response_script(fig, body, points));
}

std::vector<fs::path> render_fit(const Figure& fig, const std::string& data_file, const std::string& fitted_label,
                                 const std::string& time_label, const std::string& time_column) {
  const std::string e = column("e [m]"), measured = column("F measured [N]"), fitted = column("F fitted [N]");
  const std::vector<std::string> labels{"measured", fitted_label};
  const int points = font_points(fig, 1100, 480);
  const Grid grid = shared_key_grid(fig, 1, 2, points, labels);
  const std::string data = quote(data_file);
  std::string body = grid.begin + "  set grid\n  unset key\n";
  body += grid.panels[0] + "  set xlabel \"elongation e [mm]\"\n  set ylabel \"force F [kN]\"\n";
  // The fitted line first and thin, the measured points over it, open and
  // dark: both stay visible where they agree.
  body += plot_command({fmt::format("{} using ({}*1000):({}/1000) with lines linestyle 1 linewidth 1.1 notitle", data,
                                    e, fitted),
                        fmt::format("{} using ({}*1000):({}/1000) with points pointtype 6 pointsize 0.45 "
                                    "linewidth 0.8 linecolor rgb \"#303030\" notitle",
                                    data, e, measured)});
  body += grid.panels[1] + fmt::format("  set xlabel {} noenhanced\n", quote(time_label)) +
          "  set ylabel \"residual F_{fit} - F [kN]\"\n";
  body += plot_command({fmt::format("{} using ({}):(({}-{})/1000) with lines linestyle 2 notitle", data,
                                    column(time_column), fitted, measured)});
  body += key_plot(grid, {"NaN with points pointtype 6 pointsize 0.8 linewidth 0.8 linecolor rgb \"#303030\" title "
                          "\"measured\" noenhanced",
                          fmt::format("NaN with lines linestyle 1 linewidth 1.1 title {} noenhanced", quote(fitted_label))});
  const std::string script = fmt::format(
      "# rocking: a device law fitted to a cyclic test (the paper's Fig. 2, top right).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: time or sample, elongation [m], measured force [N], fitted force [N].\n"
      "set datafile separator \",\"\n"
      "set datafile columnheaders\n"
      "{}{}",
      fig.name, style_lines(1.8, 1.0), render_loop(fig, body, points));
  return render_script(fig, script);
}

std::string_view line_colour(const Line& l) {
  return l.colour < 0 ? "404040" : palette[static_cast<std::size_t>(l.colour) % palette_size];
}

std::vector<fs::path> render_lines(const Figure& fig, int rows, int cols, const std::string& xlabel,
                                   const std::string& ylabel, const std::vector<LinePanel>& panels) {
  using Style = Line::Style;
  // How each style draws; the key entry of a label is its first line's.
  auto style = [](const Line& l) -> std::string {
    const std::string colour = fmt::format("linecolor rgb \"#{}\"", line_colour(l));
    // A line with markers: a few along it, which tell it apart in greyscale.
    const std::string kind = l.marker > 0 ? "linespoints" : "lines";
    const std::string marker =
        l.marker > 0 ? fmt::format(" pointtype {} pointsize 1.3 pointnumber 7", l.marker) : std::string();
    switch (l.style) {
      case Style::thin_grey: return "with lines linewidth 0.6 linecolor rgb \"#a0a0a0\"";
      case Style::bold: return fmt::format("with {} linewidth 3 dashtype {} {}{}", kind, l.dash + 1, colour, marker);
      case Style::bold_dashed: return fmt::format("with {} linewidth 2.2 dashtype 2 {}{}", kind, colour, marker);
      case Style::circles: return "with points pointtype 6 pointsize 1.1 linewidth 1.5 " + colour;
      case Style::squares: return "with points pointtype 4 pointsize 1.1 linewidth 1.5 " + colour;
      case Style::crosses: return "with points pointtype 2 pointsize 1.3 linewidth 1.5 " + colour;
      case Style::band: return "with filledcurves fillstyle transparent solid 0.22 noborder " + colour;
    }
    return "with lines";
  };
  std::vector<std::string> labels, entries;
  for (const LinePanel& p : panels)
    for (const Line& l : p.lines)
      if (!l.label.empty() && std::find(labels.begin(), labels.end(), l.label) == labels.end()) {
        labels.push_back(l.label);
        // A key sample of a band: a line with no length drawn as a filled box.
        entries.push_back(l.style == Style::band
                              ? fmt::format("NaN with boxes fillstyle transparent solid 0.22 noborder linecolor rgb "
                                            "\"#{}\" title {} noenhanced",
                                            line_colour(l), quote(l.label))
                              : fmt::format("NaN {} title {} noenhanced", style(l), quote(l.label)));
      }
  const int points = font_points(fig, 550 * cols, 420 * rows);
  const Grid grid = shared_key_grid(fig, rows, cols, points, labels, 1);
  std::string body = grid.begin + fmt::format("  set grid\n  set xlabel {}\n  set ylabel {}\n", quote(xlabel),
                                               quote(ylabel));
  for (std::size_t k = 0; k < panels.size() && k < grid.panels.size(); ++k) {
    const LinePanel& panel = panels[k];
    body += grid.panels[k] + "  unset key\n  unset label\n";
    body += fmt::format("  set title {} noenhanced\n  set xrange [{}]\n  set yrange [{}]\n", quote(panel.title),
                        panel.xrange, panel.yrange);
    if (std::ranges::all_of(panel.lines, [](const Line& l) { return l.file.empty(); })) {
      body += "  set label 1 \"(nothing to show for this variant)\" at graph 0.5,0.5 center\n"
              "  plot [0:1] [0:1] NaN notitle\n  unset label 1\n";
      continue;
    }
    std::vector<std::string> items;
    for (const Line& l : panel.lines)
      if (!l.file.empty()) {
        if (l.columns.size() != (l.style == Line::Style::band ? 3u : 2u))
          throw InputError(fmt::format("figure line {}: name its {} columns", quote(l.file),
                                       l.style == Line::Style::band ? "x, low and high" : "x and y"));
        std::string spec;
        for (const std::string& c : l.columns) spec += fmt::format("{}({})", spec.empty() ? "" : ":", column(c));
        items.push_back(fmt::format("{} using {} {} notitle", quote(l.file), spec, style(l)));
      }
    body += plot_command(items);
  }
  body += "  unset title\n  set xrange [*:*]\n  set yrange [*:*]\n";
  body += key_plot(grid, entries);
  const std::string script = fmt::format(
      "# rocking: curves over a suite of records (IDA curves, fragility).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\n"
      "set datafile columnheaders\n"
      "{}",
      fig.name, render_loop(fig, body, points));
  return render_script(fig, script);
}

namespace {
// How series i draws: with its markers, or (a line only) with its own dash,
// so that series read apart in greyscale print.
std::string line_style(const Series& s, std::size_t i) {
  return s.points ? fmt::format("linespoints linestyle {}", i + 1)
                  : fmt::format("lines linestyle {} dashtype {}", i + 1, series_dash(i));
}
}  // namespace

std::vector<fs::path> render_panels(const Figure& fig, int rows, int cols, const std::string& xlabel,
                                    const std::vector<Panel>& panels, const std::vector<Series>& series, bool loglog) {
  if (series.empty()) throw InputError("figure: no series to plot");
  // The collapse markers the key explains: those some series draws.
  struct Marker {
    Collapse code;
    const char* style;
    const char* words;
  };
  static constexpr std::array<Marker, 3> markers{
      Marker{Collapse::first, "pointtype 2 pointsize 2.6 linewidth 3", "first overturning"},
      Marker{Collapse::again, "pointtype 2 pointsize 1.2", "overturned again"},
      Marker{Collapse::standing_again, "pointtype 6 pointsize 1.2", "standing again after overturning"}};
  std::vector<std::string> labels;
  unsigned codes = 0;
  for (const Series& s : series) {
    labels.push_back(s.label);
    if (!s.collapse_column.empty()) codes |= s.collapse_codes;
  }
  for (const Marker& m : markers)
    if ((codes & collapse_bit(m.code)) != 0) labels.push_back(m.words);
  const int points = font_points(fig, 550 * cols, 320 * rows);
  const Grid grid = shared_key_grid(fig, rows, cols, points, labels);
  std::string body = grid.begin + fmt::format("  set grid\n  set autoscale xfix\n  set offsets 0, 0, graph 0.05, 0\n"
                                               "  set xlabel {}\n{}",
                                               quote(xlabel),
                                               loglog ? "  set logscale xy\n  set format x \"10^{%T}\"\n"
                                                        "  set format y \"10^{%T}\"\n  set autoscale x\n  set offsets 0, 0, 0, 0\n"
                                                      : "");
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const Panel& panel = panels[p];
    body += grid.panels[p] + "  unset key\n";
    body += fmt::format("  set ylabel {}\n  set yrange [{}:*]\n", quote(panel.ylabel),
                        panel.from_zero && !panel.log_y ? "0" : "*");
    if (!loglog)
      body += panel.log_y ? "  set logscale y\n  set format y \"10^{%T}\"\n" : "  unset logscale y\n  set format y \"% h\"\n";
    body += "  unset arrow\n  unset label\n";
    if (!panel.xrange.empty()) body += fmt::format("  set xrange {}\n", panel.xrange);
    if (!panel.xtics.empty()) body += fmt::format("  set xtics {}\n  set format x \"%g\"\n", panel.xtics);
    else body += loglog ? "  set xtics autofreq\n  set format x \"10^{%T}\"\n" : "  set xtics autofreq\n  set format x \"% h\"\n";
    // A mark in the right half of a given x range is labelled to the left of
    // its line, so that the label stays inside the panel.
    double x0 = 0, x1 = 0;
    const bool ranged = !panel.xrange.empty() && std::sscanf(panel.xrange.c_str(), "[%lf:%lf]", &x0, &x1) == 2 &&
                        x0 > 0 && x1 > x0;
    for (std::size_t m = 0; m < panel.marks.size(); ++m) {
      const double x = panel.marks[m].x;
      const bool right = ranged && (loglog ? std::log(x) > 0.5 * (std::log(x0) + std::log(x1)) : x > 0.5 * (x0 + x1));
      body += fmt::format("  set arrow from first {0:.9g}, graph 0 to first {0:.9g}, graph 1 nohead dashtype 2 "
                          "linecolor rgb \"#555555\"\n  set label {1} {2} at first {0:.9g}, graph 0.97 {5} offset "
                          "char {6},-{3} font \",{4}\" noenhanced\n",
                          x, m + 10, quote(panel.marks[m].label), m, std::max(7, points - 3), right ? "right" : "left",
                          right ? "-0.3" : "0.3");
    }
    std::vector<std::string> items;
    // On a logarithmic axis a value <= 0 has no place: not drawn (gnuplot would warn).
    const std::string y = panel.log_y ? fmt::format("(({0}) > 0 ? ({0}) : NaN)", panel.y) : panel.y;
    for (std::size_t i = 0; i < series.size(); ++i) {
      const Series& s = series[i];
      if (std::find(s.absent.begin(), s.absent.end(), p) != s.absent.end()) continue;
      const std::string file = quote(s.file);
      const std::string title = fmt::format("title {} noenhanced", quote(s.label));
      if (s.collapse_column.empty()) {
        items.push_back(fmt::format("{} using ({}):({}) with {} {}", file, panel.x, y, line_style(s, i), title));
      } else {
        const std::string code = column(s.collapse_column);
        items.push_back(fmt::format("{} using ({}):({} == 0 ? {} : NaN) with linespoints linestyle {} {}", file,
                                    panel.x, code, y, i + 1, title));
        for (const Marker& m : markers)
          if ((s.collapse_codes & collapse_bit(m.code)) != 0)
            items.push_back(fmt::format("{} using (({}) + {:.9g}):({} == {} ? {} : NaN) with points linestyle {} "
                                        "{} notitle",
                                        file, panel.x, s.dodge, code, static_cast<unsigned>(m.code), y, i + 1,
                                        m.style));
      }
      // Point labels above the points of even series and below those of odd
      // ones, so that neighbouring series' labels keep apart.
      if (!panel.point_label.empty())
        items.push_back(fmt::format("{} using ({}):({}):({}) with labels offset char 0,{} font \",{}\" "
                                    "textcolor rgb \"#{}\" notitle",
                                    file, panel.x, y, panel.point_label, i % 2 == 0 ? "0.9" : "-0.9",
                                    std::max(7, points - 3), palette[i % palette_size]));
    }
    if (items.empty()) {  // an empty panel that says so
      body += "  set label 1 \"(none of these runs has this quantity)\" at graph 0.5,0.5 center\n"
              "  plot [0:1] [0:1] NaN notitle\n  unset label 1\n";
      continue;
    }
    body += plot_command(items);
  }
  body += "  unset arrow\n  unset label\n";
  std::vector<std::string> entries;
  for (std::size_t i = 0; i < series.size(); ++i)
    entries.push_back(fmt::format("NaN with {} title {} noenhanced", line_style(series[i], i), quote(series[i].label)));
  for (const Marker& m : markers)
    if ((codes & collapse_bit(m.code)) != 0)
      entries.push_back(fmt::format("NaN with points {} linecolor rgb \"#222222\" title \"{}\"", m.style, m.words));
  body += key_plot(grid, entries);
  const std::string script = fmt::format(
      "# rocking: study figure (peaks against the scale factor or a parameter).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\n"
      "set datafile columnheaders\n"
      "{}{}",
      fig.name, style_lines(1.5, 0.7), render_loop(fig, body, points));
  return render_script(fig, script);
}

std::vector<fs::path> render_spectrum(const Figure& fig, const std::vector<Series>& series,
                                      const std::string& normalised_x, const std::string& normalised_y) {
  if (series.empty()) throw InputError("spectrum figure: no series to plot");
  // Each overturning grid point fills its cell: a region per series, the
  // first solid and translucent ("#AARRGGBB"), the others cross-hatched in
  // their colour, so that overlapping regions show both and the series read
  // apart in greyscale print.
  auto fill = [&](std::size_t i) {
    return i == 0 ? fmt::format("fillstyle solid 1.0 noborder linecolor rgb \"#70{}\"", palette[0])
                  : fmt::format("fillstyle pattern {} transparent noborder linecolor rgb \"#{}\"", i % 2 == 1 ? 1 : 2,
                                palette[i % palette_size]);
  };
  // A panel of x against y, each overturning point's cell from x_low to
  // x_high and y_low to y_high (the names of the cell's columns).
  auto panel = [&](std::string_view x, std::string_view y, std::string_view x_low, std::string_view x_high,
                   std::string_view y_low, std::string_view y_high) {
    std::vector<std::string> items;
    for (std::size_t i = 0; i < series.size(); ++i)
      items.push_back(fmt::format("{} using ({}):({} > 0 ? {} : NaN):({}):({}):({}):({}) with boxxyerror {} title {} "
                                  "noenhanced",
                                  quote(series[i].file), column(x), column("overturned"), column(y), column(x_low),
                                  column(x_high), column(y_low), column(y_high), fill(i), quote(series[i].label)));
    return plot_command(items);
  };
  // A series' label without its parenthesised note: "block x1".
  auto short_label = [](const std::string& label) { return label.substr(0, label.find(" (")); };
  const bool several = series.size() > 1;
  std::vector<std::string> labels;
  for (const Series& s : series) labels.push_back(s.label);
  for (std::size_t i = 0; several && i < series.size(); ++i) labels.push_back("not computed for " + short_label(series[i].label));
  const int points = font_points(fig, 1200, 600);
  const Grid grid = shared_key_grid(fig, 1, 2, points, labels);
  std::string body = grid.begin + grid.panels[0] + "  unset key\n  set grid front\n  set autoscale xfix\n  set autoscale yfix\n" +
                     fmt::format("  set xlabel {}\n  set ylabel {}\n", quote(normalised_x), quote(normalised_y));
  body += panel("frequency_ratio", "amplitude_ratio", "frequency_ratio_low", "frequency_ratio_high",
                "amplitude_ratio_low", "amplitude_ratio_high");
  body += grid.panels[1] + "  set xlabel \"pulse period T [s]\"\n  set ylabel \"pulse amplitude a_p / g [-]\"\n";
  // In seconds and g the series' grids cover different regions: outside its
  // own (the extremes of its cells, found by stats), a series was never
  // computed, which is hatched in its colour rather than left white.
  std::string extents;
  for (std::size_t i = 0; several && i < series.size(); ++i) {
    extents += fmt::format("stats {0} using ({2}):({3}) nooutput prefix \"LO{1}\"\n"
                           "stats {0} using ({4}):({5}) nooutput prefix \"HI{1}\"\n",
                           quote(series[i].file), i, column("period_low_s"), column("amplitude_low_g"),
                           column("period_high_s"), column("amplitude_high_g"));
    const std::string hatch = fmt::format("front fillstyle pattern {} transparent noborder fillcolor rgb \"#{}\"",
                                          6 + i % 2, palette[i % palette_size]);
    const std::size_t id = 10 * (i + 1);
    body += fmt::format(
        "  set object {0} rectangle from graph 0, graph 0 to first LO{1}_min_x, graph 1 {2}\n"
        "  set object {3} rectangle from first HI{1}_max_x, graph 0 to graph 1, graph 1 {2}\n"
        "  set object {4} rectangle from first LO{1}_min_x, graph 0 to first HI{1}_max_x, first LO{1}_min_y {2}\n"
        "  set object {5} rectangle from first LO{1}_min_x, first HI{1}_max_y to first HI{1}_max_x, graph 1 {2}\n",
        id, i, hatch, id + 1, id + 2, id + 3);
  }
  body += panel("period_s", "amplitude_g", "period_low_s", "period_high_s", "amplitude_low_g", "amplitude_high_g");
  if (several) body += "  unset object\n";
  std::vector<std::string> entries;
  for (std::size_t i = 0; i < series.size(); ++i)
    entries.push_back(fmt::format("NaN with boxes {} title {} noenhanced", fill(i), quote(series[i].label)));
  for (std::size_t i = 0; several && i < series.size(); ++i)
    entries.push_back(fmt::format("NaN with boxes fillstyle pattern {} transparent noborder linecolor rgb \"#{}\" "
                                  "title {} noenhanced",
                                  6 + i % 2, palette[i % palette_size],
                                  quote(labels[series.size() + i])));
  body += key_plot(grid, entries);
  const std::string script = fmt::format(
      "# rocking: overturning spectrum (filled: the block overturns; hatched,\n"
      "# right: outside a series' grid, never computed).\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "set datafile separator \",\"\nset datafile columnheaders\n{}{}",
      fig.name, extents, render_loop(fig, body, points));
  return render_script(fig, script);
}

std::vector<fs::path> render_modes(const Figure& fig, const std::string& data_file, const ModePanel& left,
                                   const ModePanel& right) {
  auto panel = [&](const ModePanel& p) {
    if (p.columns.size() != p.labels.size())
      throw InputError(fmt::format("mode figure {}: {} shapes named, {} labelled", quote(p.title), p.columns.size(),
                                   p.labels.size()));
    std::vector<std::string> items;
    for (std::size_t i = 0; i < p.labels.size(); ++i) {
      const int colour = i < p.colours.size() ? p.colours[i] : static_cast<int>(i);
      items.push_back(fmt::format("{} using ({}):({}) with linespoints linestyle {} title {} noenhanced",
                                  quote(data_file), column(p.columns[i]), column("height"),
                                  colour % static_cast<int>(palette_size) + 1, quote(p.labels[i])));
    }
    return fmt::format("  set title {} noenhanced\n", quote(p.title)) + plot_command(items);
  };
  std::string body = fmt::format(
      "  set multiplot layout 1,2 title {} noenhanced\n"
      "  set grid\n"
      // The axis label's second (empty) line keeps the key below clear of it.
      "  set key outside below center vertical maxrows 3 width 1 nobox\n"
      "  set xlabel \"lateral displacement (normalised, top = 1) [-]\\n\"\n"
      "  set ylabel \"height [m]\"\n"
      "  set xzeroaxis\n",
      quote(fig.title));
  body += panel(left);
  body += panel(right);
  const std::string script = fmt::format(
      "# rocking: mode shapes in the style of the paper's Fig. 3.\n"
      "# Re-render after restyling: gnuplot {}.gp (in this folder).\n"
      "# Data: {} (height, then one column per shape, named in its header).\n"
      "set datafile columnheaders\n"
      "{}{}",
      fig.name, comment(data_file), style_lines(2, 1), render_loop(fig, body, font_points(fig, 1200, 800)));
  return render_script(fig, script);
}

}  // namespace rocking::plot
