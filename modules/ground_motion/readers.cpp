// Text readers for ground-motion records: AT2, two-column, one-column.
module;
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
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

// Records beyond these are not records: refused with their line rather than
// run into a non-finite state or an absurd amount of work.
constexpr double max_acceleration_g = 100;  // |a| [g]
constexpr double max_record_duration = 1e5; // [s], about 28 hours
constexpr double min_record_dt = 1e-6;      // [s]

std::vector<Line> read_lines(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(fmt::format("{}: is a folder, not a record file", path));
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

// A number that is all of `text` (no trailing letters: "1e" is not 1).
std::optional<double> whole_number(std::string_view text) {
  double v = 0;
  const char* first = text.data() + (text.starts_with('+') ? 1 : 0);
  const auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || text.empty()) return std::nullopt;
  return v;
}

// Each acceleration (m/s^2) within max_acceleration_g, or an error at its line.
void check_acceleration(const std::string& path, int line, double a_si) {
  if (std::abs(a_si) > max_acceleration_g * to_si(AccelerationUnit::g))
    fail(path, line, fmt::format("acceleration {:g} m/s2 is beyond {} g: not a ground motion (wrong units?)", a_si,
                                 max_acceleration_g));
}

bool blank_or_comment(const Line& l) {
  const auto first = l.text.find_first_not_of(" \t");
  return first == std::string::npos || l.text[first] == '#';
}

// Where `key` (any case) stands in `text`, from `from`, or npos.
std::size_t find_word(std::string_view text, std::string_view key, std::size_t from = 0) {
  for (std::size_t i = from; i + key.size() <= text.size(); ++i) {
    bool same = true;
    for (std::size_t k = 0; k < key.size() && same; ++k)
      same = std::toupper(static_cast<unsigned char>(text[i + k])) == key[k];
    if (same) return i;
  }
  return std::string_view::npos;
}

// The value of "KEY = value" in a header line: the text after the '=' up to
// a space or comma; nullopt when no KEY is followed by '='. Scanned by hand:
// a regular expression recurses once per character of a long value.
std::optional<std::string> header_field(std::string_view text, std::string_view key) {
  for (std::size_t at = find_word(text, key); at != std::string_view::npos; at = find_word(text, key, at + 1)) {
    std::size_t i = at + key.size();
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i == text.size() || text[i] != '=') continue;
    ++i;
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t')) ++i;
    const std::size_t end = text.find_first_of(" \t,", i);
    return std::string(text.substr(i, end == std::string_view::npos ? std::string_view::npos : end - i));
  }
  return std::nullopt;
}

GroundMotion read_at2(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  // The header line is the first that names NPTS; its NPTS and DT are read
  // from there, and every error about them names that line.
  std::size_t h = 0;
  while (h < lines.size() && find_word(lines[h].text, "NPTS") == std::string::npos) ++h;
  if (h == lines.size()) fail(path, 1, "no line with NPTS= and DT= (not a PEER .AT2 file?)");
  const int at = lines[h].number;
  const std::optional<std::string> npts_field = header_field(lines[h].text, "NPTS");
  if (!npts_field) fail(path, at, "NPTS has no value (NPTS= count)");
  const std::string& npts_text = *npts_field;
  long npts = -1;
  const auto [end, ec] = std::from_chars(npts_text.data(), npts_text.data() + npts_text.size(), npts);
  if (ec == std::errc::result_out_of_range || (ec == std::errc() && end == npts_text.data() + npts_text.size() && npts < 0))
    fail(path, at, fmt::format("NPTS = {:.40} is not a count of samples", npts_text));
  if (ec != std::errc() || end != npts_text.data() + npts_text.size() || npts_text.empty())
    fail(path, at, fmt::format("NPTS = '{:.40}' is not a whole number", npts_text));
  const std::optional<std::string> dt_field = header_field(lines[h].text, "DT");
  if (!dt_field) fail(path, at, "no DT= on the NPTS line");
  const std::optional<double> dt_read = whole_number(*dt_field);
  if (!dt_read || !std::isfinite(*dt_read)) fail(path, at, fmt::format("DT = '{:.40}' is not a number", *dt_field));
  const double dt = *dt_read;
  if (!(dt > 0)) fail(path, at, fmt::format("DT must be positive (got {})", dt));
  if (dt < min_record_dt) fail(path, at, fmt::format("DT = {:g} s is below {:g} s: not a record's time step", dt, min_record_dt));
  if (o.dt > 0) fail(path, at, fmt::format("--dt {:g}: the file states its own time step (DT = {:g} s)", o.dt, dt));
  // The values, counted before anything is reserved: a header may claim more
  // than the file holds.
  std::vector<double> values;
  for (std::size_t i = h + 1; i < lines.size(); ++i)
    for (double v : numbers_of(path, lines[i])) {
      values.push_back(v * to_si(o.unit));
      check_acceleration(path, lines[i].number, values.back());
    }
  if (static_cast<long>(values.size()) != npts)
    fail(path, at, fmt::format("NPTS = {} but the file holds {} values", npts, values.size()));
  if (dt * static_cast<double>(npts) > max_record_duration)
    fail(path, at, fmt::format("DT x NPTS = {:g} s is beyond {:g} s: not a record's duration", dt * static_cast<double>(npts),
                               max_record_duration));
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
  if (columns == 2 && o.dt > 0) fail(path, 1, fmt::format("--dt {:g}: a two-column record gives its own times", o.dt));
  std::vector<double> times, values;
  for (const Line& l : lines) {
    if (blank_or_comment(l)) continue;
    const std::vector<double> row = numbers_of(path, l);
    if (row.size() != columns)
      fail(path, l.number, fmt::format("expected {} column{}, found {}", columns, columns == 1 ? "" : "s", row.size()));
    const double t = columns == 1 ? static_cast<double>(values.size()) * o.dt : row[0];
    if (times.empty() && t < 0)
      fail(path, l.number, fmt::format("the record starts at t = {:g} s: a run starts at 0, and would lose what "
                                       "comes before it (shift the times)", t));
    if (!times.empty() && !(t > times.back()))
      fail(path, l.number, fmt::format("times must increase ({} after {})", t, times.back()));
    if (t > max_record_duration)
      fail(path, l.number, fmt::format("t = {:g} s is beyond {:g} s: not a record's duration", t, max_record_duration));
    times.push_back(t);
    values.push_back(row.back() * to_si(o.unit));
    check_acceleration(path, l.number, values.back());
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
      const std::size_t columns = numbers_of(path, *first).size();
      if (columns > 2)
        fail(path, first->number, fmt::format("{} columns: a record has one (a, with --dt) or two (t, a)", columns));
      format = columns == 2 ? RecordFormat::two_column : RecordFormat::one_column;
    }
  }
  GroundMotion g = format == RecordFormat::at2          ? read_at2(path, lines, o)
                   : format == RecordFormat::two_column ? read_columns(path, lines, o, 2)
                                                        : read_columns(path, lines, o, 1);
  return o.scale == 1.0 ? g : g.scaled(o.scale);
}

}  // namespace rocking
