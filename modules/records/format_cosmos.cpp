// COSMOS strong-motion data format V1/V2 (COSMOS, "Strong Motion Data Format",
// v1.20, 2001; the V2c files of CESMD and USGS): line 1 "... (Format v01.20
// with 13 text lines)", the text lines (line 2 the event, line 4 the origin,
// line 5 the station, line 11 "Processed: ... Max = -6.852 cm/sec2 at ..."),
// then "100 Integer-header values follow on 10 lines, Format= (10I8)", the
// integers, "100 Real-header values follow on 20 lines, Format= (5F15.6)",
// the reals (field 62 the time step in ms, else field 34 in s; field 64 the
// peak), "6 Comment line(s) follow", the comments, and "42000 acceleration
// pts, approx 210 secs, units=cm/sec2(04), Format=(1E15.6)" before the data,
// read in the stated Fortran fields. V2 files may follow with velocity and
// displacement blocks, which are not read.
module;
#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking::records {

namespace {

bool detect(const std::string&, const std::vector<Line>& lines) {
  return !lines.empty() && find_word(lines[0].text, "(FORMAT V") != std::string::npos &&
         find_word(lines[0].text, "TEXT LINES") != std::string::npos;
}

// The whole number that starts `text` (after blanks), or nullopt.
std::optional<long> leading_count(std::string_view text) {
  const std::string t = trim(text);
  std::size_t n = 0;
  while (n < t.size() && std::isdigit(static_cast<unsigned char>(t[n]))) ++n;
  if (n == 0 || n > 9) return std::nullopt;
  return std::stol(t.substr(0, n));
}

// A Fortran format "(10I8)", "(5F15.6)", "(1E15.6)": fields a line and width.
struct Fields {
  std::size_t per_line = 0, width = 0;
};
std::optional<Fields> fortran_fields(std::string_view text) {
  const std::size_t open = find_word(text, "FORMAT");
  if (open == std::string_view::npos) return std::nullopt;
  const std::size_t paren = text.find('(', open);
  if (paren == std::string_view::npos) return std::nullopt;
  std::size_t i = paren + 1;
  auto integer = [&](std::size_t& value) {
    const std::size_t from = i;
    while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i]))) ++i;
    if (i == from || i - from > 4) return false;
    value = std::stoul(std::string(text.substr(from, i - from)));
    return true;
  };
  Fields f;
  if (!integer(f.per_line)) f.per_line = 1;
  if (i >= text.size() || !std::isalpha(static_cast<unsigned char>(text[i]))) return std::nullopt;
  ++i;
  if (!integer(f.width) || f.per_line == 0 || f.width == 0) return std::nullopt;
  return f;
}

// The values of a block of `count` numbers in `fields`, from line index `at`.
std::vector<double> block(const std::string& path, const std::vector<Line>& lines, std::size_t at, std::size_t count,
                          const Fields& f, std::string_view what) {
  std::vector<double> out;
  out.reserve(std::min<std::size_t>(count, 1u << 20));
  for (std::size_t i = at; out.size() < count; ++i) {
    if (i >= lines.size())
      fail(path, lines.back().number, fmt::format("the file ends after {} of its {} {}", out.size(), count, what));
    const std::vector<double> row = fixed_fields(path, lines[i], f.width);
    const std::size_t expect = std::min(f.per_line, count - out.size());
    if (row.size() != expect)
      fail(path, lines[i].number, fmt::format("expected {} {} on this line, found {}", expect, what, row.size()));
    out.insert(out.end(), row.begin(), row.end());
  }
  return out;
}

// A "N ... follow on L lines, Format= (...)" line at index `at`.
struct BlockHeader {
  std::size_t count;
  Fields fields;
};
BlockHeader block_header(const std::string& path, const std::vector<Line>& lines, std::size_t at, std::string_view what) {
  if (at >= lines.size()) fail(path, lines.back().number, fmt::format("the file ends before its {}", what));
  const Line& l = lines[at];
  const std::optional<long> n = leading_count(l.text);
  const std::optional<Fields> f = fortran_fields(l.text);
  if (!n || !f) fail(path, l.number, fmt::format("expected the {} line ('N ... Format=(...)'), found '{:.50}'", what, trim(l.text)));
  return {static_cast<std::size_t>(*n), *f};
}

// An acceleration unit COSMOS codes (Table 2): its factor to m/s^2 and, where
// --units can name it, the unit.
struct Unit {
  double to_si;
  std::optional<AccelerationUnit> unit;
};
std::optional<Unit> cosmos_unit(int code) {
  switch (code) {
    case 2: return Unit{gravity, AccelerationUnit::g};
    case 4:
    case 10: return Unit{0.01, AccelerationUnit::cm_per_s2};
    case 7: return Unit{0.0254, std::nullopt};
    case 11: return Unit{1e-3 * gravity, std::nullopt};
    default: return std::nullopt;
  }
}

// The real header's "unknown" value, stated in the text lines as "...
// unknown/unspecified: -999, -999.00" (integer, then real); -999 if not.
double unknown_real(const std::vector<Line>& lines, std::size_t text_lines) {
  for (std::size_t i = 1; i < std::min(text_lines + 1, lines.size()); ++i) {
    const std::string& t = lines[i].text;
    const std::size_t k = find_word(t, "UNSPECIFIED:");
    if (k == std::string::npos) continue;
    const std::size_t comma = t.find(',', k);
    if (comma == std::string::npos) continue;
    if (const std::optional<double> v = whole_number(t.substr(comma + 1)); v && std::isfinite(*v)) return *v;
  }
  return -999.0;
}

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  refuse_component(path, o, "COSMOS");
  const std::size_t with = find_word(lines[0].text, "WITH");
  const std::optional<long> ntext = with == std::string::npos ? std::nullopt : leading_count(lines[0].text.substr(with + 4));
  if (!ntext || *ntext < 1 || *ntext > 100) fail(path, 1, "line 1 does not say how many text lines follow ('with 13 text lines')");
  std::size_t at = static_cast<std::size_t>(*ntext);
  const BlockHeader ints = block_header(path, lines, at, "integer-header");
  const std::vector<double> ih = block(path, lines, at + 1, ints.count, ints.fields, "integer-header values");
  at += 1 + (ints.count + ints.fields.per_line - 1) / ints.fields.per_line;
  const std::size_t real_at = at;
  const BlockHeader reals = block_header(path, lines, at, "real-header");
  const std::vector<double> rh = block(path, lines, at + 1, reals.count, reals.fields, "real-header values");
  at += 1 + (reals.count + reals.fields.per_line - 1) / reals.fields.per_line;
  if (at >= lines.size() || find_word(lines[at].text, "COMMENT") == std::string::npos)
    fail(path, lines[std::min(at, lines.size() - 1)].number, "expected the 'N Comment line(s) follow' line");
  const std::optional<long> ncomments = leading_count(lines[at].text);
  if (!ncomments) fail(path, lines[at].number, "the comment line count is not a number");
  std::string channel;
  for (std::size_t c = at + 1; c < std::min(lines.size(), at + 1 + static_cast<std::size_t>(*ncomments)); ++c)
    if (const std::size_t scnl = lines[c].text.find("<SCNL>"); scnl != std::string::npos) {
      const std::string id = trim(lines[c].text.substr(scnl + 6));
      const std::size_t dot = id.find('.');
      if (dot != std::string::npos) channel = id.substr(dot + 1, id.find_first_of(". ", dot + 1) - dot - 1);
    }
  at += 1 + static_cast<std::size_t>(*ncomments);
  const BlockHeader data = block_header(path, lines, at, "data");
  const Line& data_line = lines[at];
  if (find_word(data_line.text, "ACCELERATION") == std::string::npos)
    fail(path, data_line.number, "the first data block is not acceleration");
  // The unit: "units=cm/sec2(04)".
  const std::size_t u = find_word(data_line.text, "UNITS=");
  const std::size_t code_at = u == std::string::npos ? u : data_line.text.find('(', u);
  const std::optional<long> code = code_at == std::string::npos ? std::nullopt : leading_count(data_line.text.substr(code_at + 1));
  const std::optional<Unit> unit = code ? cosmos_unit(static_cast<int>(*code)) : std::nullopt;
  if (!unit) fail(path, data_line.number, "the data line names no acceleration unit this program knows (units=...(02|04|07|10|11))");
  if (unit->unit) file_unit(path, data_line.number, *unit->unit, o);
  else if (o.unit) fail(path, data_line.number, fmt::format("--units {}: the file states its own units", unit_name(*o.unit)));
  // The time step: real field 62 [ms], else 34 [s]; the file's "unknown"
  // value (text line 13, "...unknown/unspecified: -999, -999.00") where not
  // given. A field that is given must be a time step. (They may differ: a V2
  // file's 34 can be the raw recording's step, its 62 the processed one's.)
  const double unknown = unknown_real(lines, static_cast<std::size_t>(*ntext));
  auto real = [&](std::size_t field) { return field <= rh.size() ? rh[field - 1] : unknown; };
  auto real_line = [&](std::size_t field) { return lines[real_at + 1 + (field - 1) / reals.fields.per_line].number; };
  const bool has62 = real(62) != unknown, has34 = real(34) != unknown;
  for (const auto& [field, value, unit] : {std::tuple{62, real(62), "ms"}, std::tuple{34, real(34), "s"}})
    if (value != unknown && !(value > 0) && (field == 62 || !has62))
      fail(path, real_line(static_cast<std::size_t>(field)),
           fmt::format("real header field {} (the time step) = {:g} {}: must be positive (or {:g}, unknown)", field,
                       value, unit, unknown));
  const double dt = has62 ? real(62) / 1000.0 : has34 ? real(34) : 0.0;
  if (!(dt > 0)) fail(path, data_line.number, "no time step in the real header (field 62 in ms or 34 in s)");
  refuse_dt(path, data_line.number, o, dt);
  // "42000 acceleration pts, approx 210 secs": the length stated in whole
  // seconds, checked against NPTS x dt within a second or 1 %.
  if (const std::size_t approx = find_word(data_line.text, "APPROX"); approx != std::string::npos)
    if (const std::optional<long> secs = leading_count(data_line.text.substr(approx + 6))) {
      const double length = dt * static_cast<double>(data.count), stated = static_cast<double>(*secs);
      if (std::abs(length - stated) > std::max(1.0, 1e-2 * stated))
        fail(path, data_line.number,
             fmt::format("{} points of {:g} s (the header's time step) last {:g} s, but the file states approx {} secs",
                         data.count, dt, length, *secs));
    }
  std::vector<double> values = block(path, lines, at + 1, data.count, data.fields, "accelerations");
  for (double& v : values) v *= unit->to_si;
  for (std::size_t i = 0; i < values.size(); ++i)
    check_acceleration(path, lines[at + 1 + i / data.fields.per_line].number, values[i]);
  RecordInfo info;
  auto after = [&](std::size_t line, std::string_view key) {
    if (line >= static_cast<std::size_t>(*ntext) || line >= lines.size()) return std::string();
    const std::size_t k = find_word(lines[line].text, key);
    return k == std::string::npos ? std::string() : trim(lines[line].text.substr(k + key.size()));
  };
  info.event = after(1, "RECORD OF");
  info.date = after(3, "ORIGIN:");
  info.station = collapse_spaces(after(4, "CODE:"));
  info.component = channel;
  info.units = trim(data_line.text.substr(u + 6, code_at - u - 6));
  double resolution = 0;
  if (const std::string max = after(10, "MAX ="); !max.empty()) {
    const std::string number = max.substr(0, max.find_first_of(" \t"));
    if (const std::optional<double> v = whole_number(number); v && std::isfinite(*v)) {
      info.stated_peak = std::abs(*v) * unit->to_si;
      resolution = printed_resolution(number) * unit->to_si;
    }
  } else if (real(64) != -999.0 && rh.size() >= 64) {
    info.stated_peak = std::abs(real(64)) * unit->to_si;
  }
  return evenly_sampled(path, data_line.number, std::move(values), dt, std::move(info), resolution);
}

// A V2c file: 13 text lines, 100 integer and 100 real header values (the
// time step in ms at field 62), a comment, then the data in cm/s2, 8F10.3.
std::string example() {
  const ExampleRecord e = example_record();
  std::vector<double> cm;
  double peak = 0;
  for (double g : e.values) {
    cm.push_back(std::round(g * 981000.0) / 1000.0);
    peak = std::abs(cm.back()) > std::abs(peak) ? cm.back() : peak;
  }
  std::string s = "Corrected acceleration    (Format v01.20 with 13 text lines)\n"
                  "Record of Example Earthquake of Sat Jan 1, 2000 00:00 UTC\nHypocenter: 0 0 H= 10km Mw=6.0\n"
                  "Origin: 2000/01/01 00:00:00 UTC\nStatn No: 01-00001 Code:XX-EXM  NET  Example Site\n"
                  "Coords: 0 0  Site geology:\nRecorder: example\nRcrd start time: 2000/01/01 00:00:01 UTC\n"
                  "Sta Chan   1:N00E\nRaw record length = 1.000 sec\n";
  s += fmt::format("Processed:2000-01-02, EXAMPLE, Max = {:10.3f} cm/sec2 at 0.060 sec\n", peak);
  s += "Record filtered below 0.1 Hz\nValues used when parameter or data value is unknown/unspecified:   -999, -999.00\n";
  s += " 100 Integer-header values follow on  10 lines, Format= (10I8)\n";
  for (int i = 0; i < 100; ++i) s += fmt::format("{:8}{}", -999, i % 10 == 9 ? "\n" : "");
  s += " 100 Real-header values follow on  20 lines, Format= (5F15.6)\n";
  for (int i = 0; i < 100; ++i) s += fmt::format("{:15.6f}{}", i == 61 ? 1000 * e.dt : -999.0, i % 5 == 4 ? "\n" : "");
  s += "   1 Comment line(s) follow, each starting with a \"|\":\n|<SCNL>EXM.HN1.XX.--\n";
  s += fmt::format("{:8} acceleration pts, approx   1 secs, units=cm/sec2(04),Format=(8F10.3)\n", cm.size());
  for (std::size_t i = 0; i < cm.size(); ++i) s += fmt::format("{:10.3f}{}", cm[i], i % 8 == 7 || i + 1 == cm.size() ? "\n" : "");
  s += "End-of-data for Chan  1 acceleration\n";
  return s;
}

}  // namespace

FormatReader cosmos_format() {
  return {"cosmos", "COSMOS V1/V2 (V2c; units and time step from its headers)", detect, read, example};
}

}  // namespace rocking::records
