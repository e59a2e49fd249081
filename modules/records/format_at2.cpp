// PEER .AT2 records (shared/data/records/SOURCES.md, styles F1-F3): a few
// header lines, the line holding NPTS and DT, then every number after it.
// NGA-West2 files name "event, date, station, component" on line 2, the old
// PEER database "event date, station, component"; units are g unless --units.
module;
#include <charconv>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking::records {

namespace {

bool detect(const std::string& path, const std::vector<Line>& lines) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  bool has_npts = false;
  for (std::size_t i = 0; i < lines.size() && i < 10; ++i) has_npts |= lines[i].text.find("NPTS") != std::string::npos;
  return ext == ".at2" || has_npts;
}

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  refuse_component(path, o, "PEER .AT2");
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
  refuse_dt(path, at, o, dt);
  const AccelerationUnit unit = o.unit.value_or(AccelerationUnit::g);
  // The values, counted before anything is reserved: a header may claim more
  // than the file holds.
  std::vector<double> values;
  for (std::size_t i = h + 1; i < lines.size(); ++i)
    for (double v : numbers_of(path, lines[i])) {
      values.push_back(v * to_si(unit));
      check_acceleration(path, lines[i].number, values.back());
    }
  if (static_cast<long>(values.size()) != npts)
    fail(path, at, fmt::format("NPTS = {} but the file holds {} values", npts, values.size()));
  if (dt * static_cast<double>(npts) > max_record_duration)
    fail(path, at, fmt::format("DT x NPTS = {:g} s is beyond {:g} s: not a record's duration", dt * static_cast<double>(npts),
                               max_record_duration));
  RecordInfo info;
  info.units = unit_name(unit);
  // PEER files name the database on line 1 and the record on line 2; older
  // files describe the record on line 1 ("Data for El Centro 1940 ...").
  std::string what = h > 0 ? lines[0].text : "";
  if (what.starts_with("PEER") && h > 1) {
    std::vector<std::string> parts = split_fields(lines[1].text, ',');
    while (!parts.empty() && parts.back().empty()) parts.pop_back();
    if (parts.size() >= 4) {
      info.event = parts[0];
      info.date = parts[1];
      info.station = parts[2];
      info.component = parts[3];
    } else if (parts.size() == 3) {
      info.event = parts[0];
      info.station = parts[1];
      info.component = parts[2];
    } else {
      info.event = trim(lines[1].text);
    }
  } else {
    if (what.starts_with("Data for ")) what = what.substr(9);
    info.event = trim(what);
  }
  while (!info.event.empty() && info.event.back() == ',') info.event.pop_back();
  return evenly_sampled(path, at, std::move(values), dt, std::move(info));
}

// An NGA-West2 file: the database, the record, the units, NPTS and DT, then
// five values a line in g.
std::string example() {
  const ExampleRecord e = example_record();
  std::string s = "PEER NGA STRONG MOTION DATABASE RECORD\nExample Event, 1/1/2000, Example Station, 90\n"
                  "ACCELERATION TIME SERIES IN UNITS OF G\n";
  s += fmt::format("NPTS=  {}, DT=   .0100 SEC\n", e.values.size());
  for (std::size_t i = 0; i < e.values.size(); ++i)
    s += fmt::format("{:15.7E}{}", e.values[i], i % 5 == 4 || i + 1 == e.values.size() ? "\n" : "");
  return s;
}

}  // namespace

FormatReader at2_format() {
  return {"at2", "PEER .AT2 (NPTS and DT on a header line, values in g)", detect, read, example};
}

}  // namespace rocking::records
