// Bare numeric columns: two (time [s], acceleration) or one (acceleration,
// with --dt), '#' comments and blank lines skipped; units g unless --units.
module;
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.ground_motion;
import rocking.errors;

namespace rocking::records {

namespace {

const Line* first_data_line(const std::vector<Line>& lines) {
  for (const Line& l : lines)
    if (!blank_or_comment(l)) return &l;
  return nullptr;
}

bool detect(const std::string& path, const std::vector<Line>& lines) {
  const Line* first = first_data_line(lines);
  if (!first) return false;
  try {
    return !numbers_of(path, *first).empty();
  } catch (const InputError&) {
    return false;
  }
}

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  refuse_component(path, o, "column");
  const Line* first = first_data_line(lines);
  if (!first) fail(path, 1, "the record is empty");
  const std::size_t columns = numbers_of(path, *first).size();
  if (columns > 2)
    fail(path, first->number, fmt::format("{} columns: a record has one (a, with --dt) or two (t, a)", columns));
  if (columns == 1 && !(o.dt > 0)) fail(path, 1, fmt::format("a one-column record needs --dt > 0 (got {})", o.dt));
  if (columns == 2 && o.dt > 0) fail(path, 1, fmt::format("--dt {:g}: a two-column record gives its own times", o.dt));
  const AccelerationUnit unit = o.unit.value_or(AccelerationUnit::g);
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
    values.push_back(row.back() * to_si(unit));
    check_acceleration(path, l.number, values.back());
  }
  if (values.size() < 2) fail(path, lines.back().number, "a record needs at least two samples");
  RecordInfo info;
  info.units = unit_name(unit);
  info.npts = values.size();
  GroundMotion g =
      GroundMotion::from_samples(std::filesystem::path(path).filename().string(), std::move(times), std::move(values));
  info.dt = g.sample_interval();
  g.set_info(std::move(info));
  return g;
}

}  // namespace

FormatReader columns_format() {
  return {"columns", "bare numbers: time and acceleration, or acceleration alone with --dt", detect, read};
}

}  // namespace rocking::records
