// GeoNet V1A / V2A strong-motion files (GNS Science, New Zealand; "GNS
// accelerogram data file format", 2012). A file holds three components, each
// with its own header: 16 text lines (line 2 the site code, line 3 its name,
// line 7 the epicentre, line 8 the date, line 9 the magnitude, line 10
// "Number of points", line 13 "Component N28W", line 14 "Acceleration: peak
// ... mm/s/s"), then 4 integer and 6 real header lines of ten 8-character
// fields, then the values in ten 8-character fields a line, in mm/s^2.
// V2A (corrected) follows the accelerations with the velocity and the
// displacement, whose counts are integer-header fields (4,5) and (4,6); its
// time step is real-header field (3,6). V1A (uncorrected) has its sampling
// rate in real-header field (1,1) and its values "in units of X mm/s/s".
module;
#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking::records {

namespace {

constexpr std::size_t text_lines = 16, header_lines = 10, per_line = 10, field = 8;

bool starts_component(const Line& l) {
  const std::string t = trim(l.text);
  return find_word(t, "CORRECTED ACCELEROGRAM") == 0 || find_word(t, "UNCORRECTED ACCELEROGRAM") == 0;
}

bool detect(const std::string&, const std::vector<Line>& lines) {
  return !lines.empty() && starts_component(lines[0]);
}

// The number after `key` (upper case) on a line, with its printed resolution
// (half its last digit).
struct Stated {
  double value = 0, resolution = 0;
};
std::optional<Stated> number_after(std::string_view text, std::string_view key) {
  const std::size_t at = find_word(text, key);
  if (at == std::string_view::npos) return std::nullopt;
  const std::vector<std::string> w = split_fields(text.substr(at + key.size()), ' ');
  if (w.empty()) return std::nullopt;
  const std::optional<double> v = whole_number(w[0]);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return Stated{*v, printed_resolution(w[0])};
}

struct Component {
  std::size_t start;  // index of its first text line
  std::string name;
};

std::size_t rows_for(std::size_t count) { return (count + per_line - 1) / per_line; }

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  std::vector<Component> comps;
  for (std::size_t i = 0; i < lines.size(); ++i)
    if (starts_component(lines[i])) {
      if (i + text_lines + header_lines > lines.size())
        fail(path, lines[i].number, "a component header cut short (16 text and 10 numeric header lines)");
      const std::vector<std::string> w = split_fields(lines[i + 12].text, ' ');
      if (w.size() < 2 || find_word(w[0], "COMPONENT") != 0)
        fail(path, lines[i + 12].number, "no 'Component' line (line 13 of the component's header)");
      comps.push_back({i, w[1]});
    }
  if (comps.size() != 3)
    fail(path, lines.back().number,
         fmt::format("a GeoNet file holds three components, each with its header; this one holds {}", comps.size()));
  // The component asked for: by 1-based index or by name.
  std::size_t pick = 0;
  if (!o.component.empty()) {
    const std::optional<double> index = whole_number(o.component);
    auto same = [&](const Component& c) { return lower(c.name) == lower(o.component); };
    const auto named = std::find_if(comps.begin(), comps.end(), same);
    if (named != comps.end()) pick = static_cast<std::size_t>(named - comps.begin());
    else if (index && *index >= 1 && *index <= 3 && *index == std::floor(*index)) pick = static_cast<std::size_t>(*index) - 1;
    else
      throw InputError(fmt::format("{}: --component {}: the file's components are 1 {}, 2 {}, 3 {}", path, o.component,
                                   comps[0].name, comps[1].name, comps[2].name));
  }
  const Component& c = comps[pick];
  const std::size_t s = c.start;
  const bool corrected = find_word(trim(lines[s].text), "CORRECTED") == 0;
  const int head = lines[s].number;
  // The numeric header: 10 lines of ten 8-character fields.
  std::vector<std::vector<double>> hdr;
  for (std::size_t r = 0; r < header_lines; ++r) {
    hdr.push_back(fixed_fields(path, lines[s + text_lines + r], field));
    if (hdr.back().size() < per_line)
      fail(path, lines[s + text_lines + r].number,
           fmt::format("a numeric header line holds {} of its 10 fields", hdr.back().size()));
  }
  const std::optional<Stated> npts_text = number_after(lines[s + 9].text, "NUMBER OF POINTS");
  if (!npts_text || !(npts_text->value >= 2) || npts_text->value != std::floor(npts_text->value) || npts_text->value > 1e9)
    fail(path, lines[s + 9].number, "no 'Number of points' count (line 10 of the component's header)");
  const auto npts = static_cast<std::size_t>(npts_text->value);
  double dt = 0, unit_scale = 1;
  if (corrected) {
    dt = hdr[6][5];
  } else {
    dt = hdr[4][0] > 0 ? 1.0 / hdr[4][0] : 0.0;
    if (const std::optional<Stated> u = number_after(lines[s + 10].text, "UNITS OF")) unit_scale = u->value;
  }
  if (!(dt > 0)) fail(path, lines[s + text_lines + (corrected ? 6 : 4)].number,
                      fmt::format("the time step in the numeric header is not positive ({})", dt));
  refuse_dt(path, head, o, dt);
  // "Number of points 8192 Duration 163.82 sec": (NPTS - 1) x dt, to a step
  // and the last digit printed.
  if (const std::optional<Stated> duration = number_after(lines[s + 9].text, "DURATION")) {
    const double length = dt * static_cast<double>(npts - 1);
    if (!(std::abs(length - duration->value) <= dt + duration->resolution))
      fail(path, lines[s + 9].number,
           fmt::format("{} points of {:g} s (the numeric header's time step) last {:g} s, but the file states a "
                       "Duration of {:g} sec", npts, dt, length, duration->value));
  }
  const AccelerationUnit unit = file_unit(path, lines[s + 13].number, AccelerationUnit::mm_per_s2, o);
  // The data lines of this component: up to the next component's header.
  const std::size_t data = s + text_lines + header_lines;
  const std::size_t end = pick + 1 < comps.size() ? comps[pick + 1].start : lines.size();
  std::size_t rows = rows_for(npts);
  if (corrected) {
    const double nvel = hdr[3][4], ndisp = hdr[3][5];
    if (!(nvel >= 0 && ndisp >= 0 && nvel < 1e9 && ndisp < 1e9))
      fail(path, lines[s + text_lines + 3].number, "the velocity and displacement counts are not counts");
    const std::size_t expected = rows + rows_for(static_cast<std::size_t>(nvel)) + rows_for(static_cast<std::size_t>(ndisp));
    if (end - data != expected)
      fail(path, end > data ? lines[end - 1].number : lines[s].number,
           fmt::format("component {}: {} accelerations, {} velocities and {} displacements take {} lines, found {}",
                       c.name, npts, nvel, ndisp, expected, end - data));
  } else if (end - data < rows) {
    fail(path, lines[end - 1].number,
         fmt::format("component {}: {} accelerations take {} lines, found {}", c.name, npts, rows, end - data));
  }
  std::vector<double> values;
  values.reserve(npts);
  const double to_m = unit_scale * to_si(unit);
  for (std::size_t r = 0; r < rows; ++r) {
    const Line& l = lines[data + r];
    const std::vector<double> row = fixed_fields(path, l, field);
    if (row.size() != std::min(per_line, npts - values.size()))
      fail(path, l.number, fmt::format("expected {} values on this line, found {}", std::min(per_line, npts - values.size()),
                                       row.size()));
    for (double v : row) {
      values.push_back(v * to_m);
      check_acceleration(path, l.number, values.back());
    }
  }
  RecordInfo info;
  info.units = unit_name(unit);
  info.station = split_fields(lines[s + 1].text, ' ').size() > 1 ? split_fields(lines[s + 1].text, ' ')[1] : "";
  if (const std::string name = trim(lines[s + 2].text); !name.empty())
    info.station = info.station.empty() ? name : fmt::format("{} ({})", info.station, name);
  info.component = c.name;
  info.date = collapse_spaces(trim(lines[s + 7].text));
  std::string magnitude;
  if (const std::size_t m = find_word(lines[s + 8].text, "MW"); m != std::string::npos)
    magnitude = trim(lines[s + 8].text.substr(m));
  const std::string place = trim(lines[s + 6].text);
  info.event = magnitude.empty() ? place : place.empty() ? magnitude : fmt::format("{} ({})", magnitude, place);
  double resolution = 0;
  if (const std::optional<Stated> peak = number_after(lines[s + 13].text, "PEAK")) {
    // In mm/s/s, whatever the size of a raw reading.
    info.stated_peak = std::abs(peak->value) * to_si(unit);
    resolution = peak->resolution * to_si(unit);
  }
  return evenly_sampled(path, lines[s + 13].number, std::move(values), dt, std::move(info), resolution);
}

// A V2A file of three components (N10E: the example; N80W: its negative;
// Up: half of it), each its 16 text lines, the integer and real headers and
// acceleration, velocity and displacement in ten 8.1 fields a line (mm/s2).
std::string example() {
  const ExampleRecord e = example_record();
  auto rows = [](const std::vector<double>& v, const char* format) {
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i)
      out += fmt::format(fmt::runtime(format), v[i]) + (i % 10 == 9 || i + 1 == v.size() ? "\n" : "");
    return out;
  };
  auto component = [&](const char* name, double factor) {
    std::vector<double> mm;
    double peak = 0;
    for (double g : e.values) {
      mm.push_back(std::round(factor * g * 98100.0) / 10.0);
      peak = std::abs(mm.back()) > std::abs(peak) ? mm.back() : peak;
    }
    const std::size_t n = mm.size();
    std::string s = "Corrected accelerogram 20000101_000000_EXMS_20 GNS Science\n"
                    "Site EXMS      41 00 00S  174 00 00E     Cusp file:  20000101_000000_EXMS\n"
                    "Example Station Road\nInstrument Cusp_1\n"
                    "Resolution: 18-bit   Instr Period: 0.0050 s   Damping: 0.700\n"
                    "Accelerogram 20000101_000000_EXMS_20                 Processed 2000 January 02\n"
                    "10 km north of Example\n2000 January 01         00:00:00 UT\n"
                    "Epicentre  41 00 00S 174 00 00E  Bearing N00E  Dist   10km  Depth   10km Mw 6.10\n";
    s += fmt::format("Number of points  {}    Duration {:.2f} sec\n", n, e.dt * static_cast<double>(n));
    s += fmt::format("Instrument corrected data at {:.3f} sec intervals\n", e.dt);
    s += "Band-pass filter transition bands are .10-.25 Hz and 24.50-25.50 Hz\n";
    s += fmt::format("Component {}  Longitudinal Accelerometer Axis\n", name);
    s += fmt::format("Acceleration:  peak  {:.1f} mm/s/s at   0.06 sec     rms    1.0 mm/s/s\n", peak);
    s += "Velocity:      peak    1.00 mm/s   at   1.00 sec     rms    1.00 mm/s\n"
         "Displacement:  peak   1.000 mm     at   1.00 sec     rms    1.000 mm\n";
    std::vector<double> ints(40, 0.0), reals(60, 0.0);
    ints[33] = ints[34] = ints[35] = static_cast<double>(n);
    reals[0] = 1 / e.dt;
    reals[25] = e.dt;
    return s + rows(ints, "{:8.0f}") + rows(reals, "{:8.4f}") + rows(mm, "{:8.1f}") +
           rows(std::vector<double>(n, 0.0), "{:8.1f}") + rows(std::vector<double>(n, 0.0), "{:8.1f}");
  };
  return component("N10E", 1) + component("N80W", -1) + component("Up", 0.5);
}

}  // namespace

FormatReader geonet_format() {
  return {"geonet", "GeoNet V1A/V2A (New Zealand; three components, mm/s2; --component picks one)", detect, read, example};
}

}  // namespace rocking::records
