// Every figure the program makes, reviewed from the gnuplot script it keeps
// beside it, as a journal's reviewer would look at it: no key over a data
// series (keys sit in their own band or outside the panels), every series of
// a plot distinguishable in greyscale print (its own dash, marker or fill,
// not its colour alone), and titles in words, with no option syntax
// ("--limit", "theta_over_alpha>=0.5", "sa:0.46").
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include "run_program.hpp"
#include "records.hpp"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string file_text_of(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The script's statements: continuation lines (", \") joined, trimmed.
std::vector<std::string> statements(const std::string& script) {
  std::vector<std::string> out;
  std::stringstream ss(script);
  std::string line, pending;
  while (std::getline(ss, line)) {
    const auto first = line.find_first_not_of(' ');
    line = first == std::string::npos ? std::string() : line.substr(first);
    if (line.ends_with("\\")) {
      pending += line.substr(0, line.size() - 1);
      continue;
    }
    out.push_back(pending + line);
    pending.clear();
  }
  return out;
}

// The items of a plot statement, split at the commas between them (outside
// quotes and parentheses).
std::vector<std::string> plot_items(const std::string& statement) {
  std::vector<std::string> items;
  std::string cur;
  int depth = 0;
  char quote = 0;
  for (char c : statement.substr(5)) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == '(' || c == '[') {
      ++depth;
    } else if (c == ')' || c == ']') {
      --depth;
    } else if (c == ',' && depth == 0) {
      items.push_back(cur);
      cur.clear();
      continue;
    }
    cur += c;
  }
  items.push_back(cur);
  return items;
}

// The value after a gnuplot keyword in an item ("dashtype 2" -> "2"), or "".
std::string after(const std::string& item, const std::string& keyword) {
  const std::regex re("(^|\\s)" + keyword + "\\s+(\\S+)");
  std::smatch m;
  return std::regex_search(item, m, re) ? m[2].str() : std::string();
}

bool titled(const std::string& item) {
  return item.find(" notitle") == std::string::npos && item.find(" title ") != std::string::npos;
}

// How an item looks in greyscale: its kind (lines, points, fill), dash and
// width, marker and marker size, fill pattern. Colour is left out on purpose.
std::string greyscale_look(const std::string& item, const std::map<std::string, std::string>& style_points) {
  std::smatch m;
  std::string with;
  if (std::regex_search(item, m, std::regex("\\swith\\s+(\\w+)"))) with = m[1].str();
  const std::string style = after(item, "linestyle");
  std::string look = with;
  const bool lines = with == "lines" || with == "linespoints";
  const bool points = with == "points" || with == "linespoints";
  if (lines) look += " dash " + (after(item, "dashtype").empty() ? std::string("1") : after(item, "dashtype")) +
                    " width " + after(item, "linewidth");
  if (points) {
    std::string pt = after(item, "pointtype");
    if (pt.empty() && style_points.contains(style)) pt = style_points.at(style);
    look += " marker " + pt + " size " + after(item, "pointsize");
  }
  if (item.find("fillstyle") != std::string::npos) {
    const std::string fill = after(item, "fillstyle");
    look += " fill " + fill + (fill == "pattern" ? " " + after(item, "pattern") : std::string());
  }
  return look;
}

struct Review {
  std::vector<std::string> problems;
};

Review review(const fs::path& gp) {
  Review r;
  const std::string script = file_text_of(gp);
  const std::vector<std::string> lines = statements(script);
  std::map<std::string, std::string> style_points;  // linestyle -> its pointtype
  const std::regex style_re("^set style line (\\d+) .*pointtype (\\d+)");
  const std::regex option_syntax("--[a-z]|[a-z]_[a-z_]*>=|\\b(sa|saavg|pga|pgv):[0-9]");
  enum class Key { off, outside, inside } key = Key::inside;  // gnuplot's default: inside the panel
  for (const std::string& s : lines) {
    std::smatch m;
    if (std::regex_search(s, m, style_re)) style_points[m[1].str()] = m[2].str();
    if (s.starts_with("set multiplot") || s.starts_with("set title")) {
      const auto at = s.find("title");
      if (at != std::string::npos && std::regex_search(s.substr(at), option_syntax))
        r.problems.push_back("option syntax in a title: " + s);
    }
    if (s.starts_with("unset key")) key = Key::off;
    if (s.starts_with("set key")) {
      const bool out = s.find("outside") != std::string::npos || s.find(" at screen") != std::string::npos ||
                       s.find(" above") != std::string::npos || s.find(" below") != std::string::npos ||
                       s.find(" tmargin") != std::string::npos || s.find(" bmargin") != std::string::npos;
      key = out ? Key::outside : Key::inside;
    }
    if (!s.starts_with("plot ")) continue;
    const std::vector<std::string> items = plot_items(s);
    bool data = false, any_title = false;
    for (const std::string& item : items) {
      const auto first = item.find_first_not_of(' ');
      const bool empty_entry = item.compare(first, 3, "NaN") == 0 || item.find("[0:1] [0:1] NaN") != std::string::npos;
      data = data || !empty_entry;
      any_title = any_title || titled(item);
    }
    // A key drawn inside a panel that holds data sits over it.
    if (data && any_title && key == Key::inside) r.problems.push_back("a key inside a panel with data: " + s.substr(0, 160));
    // In a plot that keys its series, each titled series looks different in greyscale.
    std::map<std::string, std::string> seen;
    for (const std::string& item : items) {
      if (!titled(item)) continue;
      const std::string look = greyscale_look(item, style_points);
      if (seen.contains(look))
        r.problems.push_back("two series look the same in greyscale (" + look + "):\n    " + seen[look].substr(0, 140) +
                             "\n    " + item.substr(0, 140));
      else
        seen[look] = item;
    }
  }
  return r;
}

void review_all(const fs::path& dir) {
  int scripts = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().extension() != ".gp") continue;
    ++scripts;
    const Review r = review(e.path());
    CAPTURE(e.path().string());
    for (const std::string& p : r.problems) FAIL_CHECK(p);
  }
  CHECK(scripts > 0);
}

void make(const std::string& args) {
  const Result r = run(args);
  REQUIRE_MESSAGE(r.code == 0, args << "\n" << r.err);
}

}  // namespace

TEST_CASE("the review of a script finds keys over data, series alike in greyscale and option syntax in titles") {
  // The checks themselves, on a script with each fault.
  const fs::path dir = temp_path("figure_review_self");
  fs::create_directories(dir);
  std::ofstream(dir / "bad.gp") << "set style line 1 linecolor rgb \"#000000\" linewidth 1 pointtype 7 pointsize 1\n"
                                   "set style line 2 linecolor rgb \"#ff0000\" linewidth 1 pointtype 7 pointsize 1\n"
                                   "set multiplot title 'IDA by sa:0.459562, --limit theta_over_alpha>=0.5'\n"
                                   "plot 'a.csv' using 1:2 with lines linestyle 1 title 'a', \\\n"
                                   "     'b.csv' using 1:2 with lines linestyle 2 title 'b'\n"
                                   "unset key\n"
                                   "plot 'a.csv' using 1:2 with linespoints linestyle 1 title 'a', \\\n"
                                   "     'b.csv' using 1:2 with linespoints linestyle 2 title 'b'\n"
                                   "plot 'a.csv' using 1:2 with lines linestyle 1 dashtype 1 title 'a', \\\n"
                                   "     'b.csv' using 1:2 with lines linestyle 2 dashtype 2 title 'b'\n";
  const Review r = review(dir / "bad.gp");
  REQUIRE(r.problems.size() == 4);
  CHECK(r.problems[0].starts_with("option syntax in a title"));
  CHECK(r.problems[1].starts_with("a key inside a panel with data"));
  CHECK(r.problems[2].starts_with("two series look the same in greyscale (lines dash 1 width"));
  CHECK(r.problems[3].starts_with("two series look the same in greyscale (linespoints dash 1 width"));
}

// Every renderer is reviewed: sweep figures are IDA figures (render_panels),
// and tradeoff --scenes draws with the work-precision figure's renderer.
TEST_CASE("every figure kind passes the review: response, devices, joints, modes, fit, animation, spectrum, records, IDA, suite, fragility, tradeoff") {
  const fs::path dir = temp_path("figure_review");
  const std::string out = dir.string();
  make("plot response --formats svg --out " + out + " --name response");
  make("plot response " ROCKING_SOURCE_DIR "/data/scenes/controlled_rocking_wall.toml "
       "--variants scene,without:tendon,without:dampers,no-devices --formats svg --out " + out + " --name devices");
  make("plot response " ROCKING_SOURCE_DIR "/data/scenes/segmental_pier.toml --formats svg --out " + out +
       " --name joints");
  make("plot modes --formats svg --out " + out);
  make("fit " ROCKING_SOURCE_DIR "/data/tests/bouc_wen_cyclic.csv --formats svg --out " + out + "/fit");
  make("animate --fps 2 --out " + out + "/animation/response.gif");
  make("spectrum --sizes 1,4 --frequencies 0.5:10:1.5 --amplitudes 0.5:8:1.5 --formats svg --out " + out + "/spectrum");
  if (const auto records = records_dir()) {
    const std::string elcentro = *records + "/elcentro_1940_ns.at2", chichi = *records + "/chichi1999_chy028_n.at2";
    make("record " + elcentro + " " + chichi + " --window auto --formats svg --out " + out + "/record");
    make("ida --record " + elcentro + " --scales 0.5,1,2 --variants damper,no-damper,fixed-base --formats svg --out " +
         out + "/ida");
    make("ida --record " + elcentro + " --record " + chichi + " --im sa:T1 --levels 0.2,0.6 --variants damper,no-damper "
         "--limit theta_over_alpha=0.1 --bootstrap 20 --formats svg --out " + out + "/suite");
    make("tradeoff --record " + elcentro + " --rtols 1e-3,1e-4 --repeats 1 --duration 5 --formats svg --out " + out +
         "/tradeoff");
    for (const char* script : {"record/record.gp", "record/spectrum.gp", "ida/ida_elcentro_1940_ns.gp",
                               "suite/ida_theta_over_alpha.gp", "suite/ida_fragility.gp", "suite/ida_damage_states.gp",
                               "tradeoff/work_precision.gp"}) {
      CAPTURE(script);
      CHECK(fs::is_regular_file(dir / script));
    }
  }
  review_all(dir);
}

TEST_CASE("a response that stays at round-off is drawn flat on at least +-0.001 of its unit, not magnified into noise") {
  // The stacked blocks' base never lifts (its theta/alpha_cg stays within round-off of 0) while joint 1 rocks:
  // each time panel asks gnuplot for an axis of at least +-0.001 and gives the next panel its autoscale back.
  const fs::path dir = temp_path("figure_span");
  make("plot response " ROCKING_SOURCE_DIR "/data/scenes/stacked_blocks.toml --formats svg --out " + dir.string() +
       " --name stack");
  const std::vector<std::string> s = statements(file_text_of(dir / "stack.gp"));
  int spanned = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (!s[k].starts_with("plot ") || s[k].find("theta_over_alpha [-]") == std::string::npos) continue;
    REQUIRE(k >= 1);
    CHECK(s[k - 1] == "set yrange [*<-0.001:0.001<*]");
    REQUIRE(k + 1 < s.size());
    CHECK(s[k + 1] == "set yrange [*:*]");
    ++spanned;
  }
  CHECK(spanned == 1);
  // The curve it spans is round-off: every |theta/alpha_cg| below 1e-6.
  std::ifstream data(dir / "stack.data" / "scene.csv");
  std::string header, row;
  std::getline(data, header);
  std::size_t column = 0;
  for (std::size_t at = 0, k = 0; at != std::string::npos; at = header.find(',', at + 1), ++k)
    if (header.compare(at == 0 ? 0 : at + 1, 20, "theta_over_alpha [-]") == 0) column = k;
  double largest = 0;
  while (std::getline(data, row)) {
    std::stringstream cells(row);
    std::string cell;
    for (std::size_t k = 0; std::getline(cells, cell, ','); ++k)
      if (k == column) largest = std::max(largest, std::abs(std::stod(cell)));
  }
  CHECK(column > 0);
  CHECK(largest < 1e-6);
}
