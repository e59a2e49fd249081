// The readers' shared text handling: lines, numbers (free and fixed-width),
// header fields, units, and the checks every record passes.
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
module rocking.records;
import rocking.errors;

namespace rocking::records {

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
    if (n == 1 && text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);  // a UTF-8 byte-order mark is no content
    lines.push_back({n, std::move(text)});
  }
  return lines;
}

void fail(const std::string& path, int line, std::string_view what) {
  throw InputError(fmt::format("{}:{}: {}", path, line, what));
}

std::string trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

std::optional<double> whole_number(std::string_view raw) {
  const std::string text = trim(raw);
  if (text.empty()) return std::nullopt;
  double v = 0;
  const char* first = text.data() + (text.starts_with('+') ? 1 : 0);
  const auto [ptr, ec] = std::from_chars(first, text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

double number_at(const std::string& path, int line, std::string_view field) {
  const std::optional<double> v = whole_number(field);
  if (!v) fail(path, line, fmt::format("'{:.40}' is not a number", trim(field)));
  if (!std::isfinite(*v)) fail(path, line, fmt::format("'{:.40}' is not a finite number", trim(field)));
  return *v;
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::string collapse_spaces(std::string text) {
  text.erase(std::unique(text.begin(), text.end(), [](char a, char b) { return a == ' ' && b == ' '; }), text.end());
  return text;
}

std::vector<std::string> split_fields(std::string_view text, char separator) {
  std::vector<std::string> out;
  if (separator == ' ') {
    for (std::size_t at = 0; at < text.size();) {
      at = text.find_first_not_of(" \t", at);
      if (at == std::string_view::npos) break;
      const std::size_t end = std::min(text.find_first_of(" \t", at), text.size());
      out.emplace_back(text.substr(at, end - at));
      at = end;
    }
    return out;
  }
  for (std::size_t at = 0;;) {
    const std::size_t end = text.find(separator, at);
    out.push_back(trim(text.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at)));
    if (end == std::string_view::npos) break;
    at = end + 1;
  }
  return out;
}

double printed_resolution(std::string_view number) {
  const std::size_t dot = number.find('.');
  const double digits = dot == std::string_view::npos ? 0.0 : static_cast<double>(number.size() - dot - 1);
  return 0.5 * std::pow(10.0, -digits);
}

std::vector<double> numbers_of(const std::string& path, const Line& line) {
  std::vector<double> out;
  const char* p = line.text.data();
  const char* end = p + line.text.size();
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == ',')) ++p;
    if (p == end) break;
    const char* start = p;
    while (p < end && *p != ' ' && *p != '\t' && *p != ',') ++p;
    out.push_back(number_at(path, line.number, std::string_view(start, p)));
  }
  return out;
}

std::vector<double> fixed_fields(const std::string& path, const Line& line, std::size_t width) {
  std::vector<double> out;
  const std::string_view text = line.text;
  for (std::size_t at = 0; at < text.size(); at += width) {
    const std::string_view field = text.substr(at, width);
    if (trim(field).empty()) {
      if (!trim(text.substr(at)).empty())
        fail(path, line.number, fmt::format("a blank field at column {} before more numbers", at + 1));
      break;
    }
    out.push_back(number_at(path, line.number, field));
  }
  return out;
}

std::size_t find_word(std::string_view text, std::string_view key, std::size_t from) {
  for (std::size_t i = from; i + key.size() <= text.size(); ++i) {
    bool same = true;
    for (std::size_t k = 0; k < key.size() && same; ++k)
      same = std::toupper(static_cast<unsigned char>(text[i + k])) == key[k];
    if (same) return i;
  }
  return std::string_view::npos;
}

// Scanned by hand: a regular expression recurses once per character of a
// long value (the fuzzer found the stack overflow).
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

bool blank_or_comment(const Line& l) {
  const auto first = l.text.find_first_not_of(" \t");
  return first == std::string::npos || l.text[first] == '#';
}

void check_acceleration(const std::string& path, int line, double a_si) {
  if (std::abs(a_si) > max_acceleration_g * gravity)
    fail(path, line, fmt::format("acceleration {:g} m/s2 is beyond {} g: not a ground motion (wrong units?)", a_si,
                                 max_acceleration_g));
}

AccelerationUnit file_unit(const std::string& path, int line, AccelerationUnit stated, const RecordOptions& o) {
  if (o.unit && *o.unit != stated)
    fail(path, line, fmt::format("--units {}: the file states its values in {}", unit_name(*o.unit), unit_name(stated)));
  return stated;
}

void refuse_component(const std::string& path, const RecordOptions& o, std::string_view format) {
  if (!o.component.empty())
    throw InputError(fmt::format("{}: --component {}: a {} file holds one component", path, o.component, format));
}

void refuse_dt(const std::string& path, int line, const RecordOptions& o, double stated_dt) {
  if (o.dt > 0) fail(path, line, fmt::format("--dt {:g}: the file states its own time step ({:g} s)", o.dt, stated_dt));
}

namespace {
// The record of these samples with the file's metadata (its count, and its
// time step unless the file stated it) and, where the file names it, a
// description with its PGA.
GroundMotion with_info(const std::string& path, std::vector<double> times, std::vector<double> values, RecordInfo info) {
  info.npts = values.size();
  GroundMotion g =
      GroundMotion::from_samples(std::filesystem::path(path).filename().string(), std::move(times), std::move(values));
  if (info.dt == 0) info.dt = g.sample_interval();
  const std::string label = info.label();
  // Two decimals from 0.1 g up; two significant digits below (a weak K-NET record's 0.0042 g, not "0.00 g").
  const double pga = g.peak() / gravity;
  if (!label.empty())
    g.set_description(pga >= 0.1 ? fmt::format("{}, PGA {:.2f} g", label, pga) : fmt::format("{}, PGA {:.2g} g", label, pga));
  g.set_info(std::move(info));
  return g;
}
}  // namespace

GroundMotion evenly_sampled(const std::string& path, int header_line, std::vector<double> values, double dt,
                            RecordInfo info, double stated_resolution) {
  if (!(dt > 0) || !std::isfinite(dt)) fail(path, header_line, fmt::format("the time step must be positive (got {})", dt));
  if (dt < min_record_dt)
    fail(path, header_line, fmt::format("time step {:g} s is below {:g} s: not a record's time step", dt, min_record_dt));
  if (values.size() < 2) fail(path, header_line, fmt::format("a record needs at least two samples (found {})", values.size()));
  if (dt * static_cast<double>(values.size()) > max_record_duration)
    fail(path, header_line, fmt::format("{} samples of {:g} s is beyond {:g} s: not a record's duration", values.size(),
                                        dt, max_record_duration));
  double peak = 0;
  for (double v : values) peak = std::max(peak, std::abs(v));
  if (info.stated_peak && *info.stated_peak != 0) {  // 0: a file that states no peak
    const double stated = *info.stated_peak;
    if (std::abs(peak - stated) > std::max(1e-3 * stated, stated_resolution))
      fail(path, header_line, fmt::format("the file states a peak of {:.6g} m/s2 but its data peak at {:.6g} m/s2",
                                          stated, peak));
  }
  std::vector<double> times(values.size());
  for (std::size_t i = 0; i < times.size(); ++i) times[i] = static_cast<double>(i) * dt;
  info.dt = dt;
  return with_info(path, std::move(times), std::move(values), std::move(info));
}

void TimedSamples::add(const std::string& path, int line, double t, double a_si) {
  if (t_.empty() && t < 0)
    fail(path, line, fmt::format("the record starts at t = {:g} s: a run starts at 0, and would lose what "
                                 "comes before it (shift the times)", t));
  if (!t_.empty() && !(t > t_.back())) fail(path, line, fmt::format("times must increase ({} after {})", t, t_.back()));
  if (!t_.empty() && t - t_.back() < min_record_dt)
    fail(path, line, fmt::format("t = {:.9g} s is {:g} s after the sample before: below {:g} s, not a record's time step",
                                 t, t - t_.back(), min_record_dt));
  if (t > max_record_duration)
    fail(path, line, fmt::format("t = {:g} s is beyond {:g} s: not a record's duration", t, max_record_duration));
  check_acceleration(path, line, a_si);
  t_.push_back(t);
  a_.push_back(a_si);
}

GroundMotion TimedSamples::record(const std::string& path, int last_line, RecordInfo info) && {
  if (a_.size() < 2) fail(path, last_line, "a record needs at least two samples");
  return with_info(path, std::move(t_), std::move(a_), std::move(info));
}

}  // namespace rocking::records
