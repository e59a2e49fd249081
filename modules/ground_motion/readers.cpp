// Text readers for ground-motion records: AT2, two-column, one-column.
module;
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.ground_motion;
import rocking.errors;

namespace rocking {

namespace {

struct Line {
  int number;
  std::string text;  // without the line end (CR stripped)
};

std::vector<Line> read_lines(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(fmt::format("{}: record file not found", path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read the record file", path));
  std::vector<Line> lines;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    lines.push_back({n, std::move(text)});
  }
  return lines;
}

[[noreturn]] void fail(const std::string& path, int line, std::string_view what) {
  throw InputError(fmt::format("{}:{}: {}", path, line, what));
}

// The whitespace-separated numbers of one line; text among them is an error.
std::vector<double> numbers_of(const std::string& path, const Line& line) {
  std::vector<double> out;
  const char* p = line.text.data();
  const char* end = p + line.text.size();
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == ',')) ++p;
    if (p == end) break;
    const char* start = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != ',') ++p;
    double v = 0;
    const char* first = *start == '+' ? start + 1 : start;
    const auto [ptr, ec] = std::from_chars(first, p, v);
    if (ec != std::errc() || ptr != p)
      fail(path, line.number, fmt::format("'{}' is not a number", std::string_view(start, p)));
    if (!std::isfinite(v)) fail(path, line.number, fmt::format("'{}' is not a finite number", std::string_view(start, p)));
    out.push_back(v);
  }
  return out;
}

bool blank_or_comment(const Line& l) {
  const auto first = l.text.find_first_not_of(" \t");
  return first == std::string::npos || l.text[first] == '#';
}

GroundMotion read_at2(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  static const std::regex header(R"(NPTS\s*=\s*(\d+)\s*,?\s*DT\s*=\s*([0-9.Ee+-]+))", std::regex::icase);
  std::size_t h = 0;
  std::smatch m;
  while (h < lines.size() && !std::regex_search(lines[h].text, m, header)) ++h;
  if (h == lines.size()) fail(path, 1, "no line with NPTS= and DT= (not a PEER .AT2 file?)");
  const long npts = std::stol(m[1].str());
  double dt = 0;
  try { dt = std::stod(m[2].str()); } catch (...) { fail(path, lines[h].number, "DT is not a number"); }
  if (!(dt > 0)) fail(path, lines[h].number, fmt::format("DT must be positive (got {})", dt));
  std::vector<double> values;
  values.reserve(static_cast<std::size_t>(npts));
  for (std::size_t i = h + 1; i < lines.size(); ++i)
    for (double v : numbers_of(path, lines[i])) values.push_back(v * to_si(o.unit));
  if (static_cast<long>(values.size()) != npts)
    fail(path, lines[h].number, fmt::format("NPTS = {} but the file holds {} values", npts, values.size()));
  std::vector<double> times(values.size());
  for (std::size_t i = 0; i < times.size(); ++i) times[i] = static_cast<double>(i) * dt;
  GroundMotion g =
      GroundMotion::from_samples(std::filesystem::path(path).filename().string(), std::move(times), std::move(values));
  // The header's description: PEER NGA files name the database on line 1 and
  // the event, date, station and component on line 2; older files describe
  // the record on line 1 ("Data for El Centro 1940 ...").
  std::string what = h > 0 ? lines[0].text : "";
  if (what.starts_with("PEER") && h > 1) what = lines[1].text;
  if (what.starts_with("Data for ")) what = what.substr(9);
  while (!what.empty() && (what.back() == ' ' || what.back() == ',')) what.pop_back();
  if (!what.empty()) g.set_description(fmt::format("{}, PGA {:.2f} g", what, g.peak() / to_si(AccelerationUnit::g)));
  return g;
}

GroundMotion read_columns(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o,
                          std::size_t columns) {
  if (columns == 1 && !(o.dt > 0)) fail(path, 1, fmt::format("a one-column record needs --dt > 0 (got {})", o.dt));
  std::vector<double> times, values;
  for (const Line& l : lines) {
    if (blank_or_comment(l)) continue;
    const std::vector<double> row = numbers_of(path, l);
    if (row.size() != columns)
      fail(path, l.number, fmt::format("expected {} column{}, found {}", columns, columns == 1 ? "" : "s", row.size()));
    const double t = columns == 1 ? static_cast<double>(values.size()) * o.dt : row[0];
    if (!times.empty() && !(t > times.back()))
      fail(path, l.number, fmt::format("times must increase ({} after {})", t, times.back()));
    times.push_back(t);
    values.push_back(row.back() * to_si(o.unit));
  }
  if (values.size() < 2) fail(path, lines.empty() ? 1 : lines.back().number, "a record needs at least two samples");
  return GroundMotion::from_samples(std::filesystem::path(path).filename().string(), std::move(times), std::move(values));
}

}  // namespace

GroundMotion read_record(const std::string& path, const RecordOptions& o) {
  if (!std::isfinite(o.scale)) throw InputError(fmt::format("--scale must be finite (got {})", o.scale));
  const std::vector<Line> lines = read_lines(path);
  RecordFormat format = o.format;
  if (format == RecordFormat::automatic) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    bool has_npts = false;
    for (std::size_t i = 0; i < lines.size() && i < 10; ++i) has_npts |= lines[i].text.find("NPTS") != std::string::npos;
    if (ext == ".at2" || has_npts) format = RecordFormat::at2;
    else {
      const auto first = std::find_if(lines.begin(), lines.end(), [](const Line& l) { return !blank_or_comment(l); });
      if (first == lines.end()) fail(path, 1, "the record is empty");
      format = numbers_of(path, *first).size() == 2 ? RecordFormat::two_column : RecordFormat::one_column;
    }
  }
  GroundMotion g = format == RecordFormat::at2          ? read_at2(path, lines, o)
                   : format == RecordFormat::two_column ? read_columns(path, lines, o, 2)
                                                        : read_columns(path, lines, o, 1);
  return o.scale == 1.0 ? g : g.scaled(o.scale);
}

}  // namespace rocking
