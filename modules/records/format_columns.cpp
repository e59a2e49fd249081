// Bare numeric columns: two (time [s], acceleration) or one (acceleration,
// with --dt), '#' comments and blank lines skipped; units g unless --units.
module;
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.records;
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
  TimedSamples samples;
  for (const Line& l : lines) {
    if (blank_or_comment(l)) continue;
    const std::vector<double> row = numbers_of(path, l);
    if (row.size() != columns)
      fail(path, l.number, fmt::format("expected {} column{}, found {}", columns, columns == 1 ? "" : "s", row.size()));
    const double t = columns == 1 ? static_cast<double>(samples.size()) * o.dt : row[0];
    samples.add(path, l.number, t, row.back() * to_si(unit));
  }
  RecordInfo info;
  info.units = unit_name(unit);
  return std::move(samples).record(path, lines.back().number, std::move(info));
}

// Time [s] and acceleration [g], a comment first.
std::string example() {
  const ExampleRecord e = example_record();
  std::string s = "# t [s]  a_g [g]\n";
  for (std::size_t i = 0; i < e.values.size(); ++i) s += fmt::format("{:.2f} {:.9f}\n", e.dt * static_cast<double>(i), e.values[i]);
  return s;
}

}  // namespace

FormatReader columns_format() {
  return {"columns", "bare numbers: time and acceleration, or acceleration alone with --dt", detect, read, example};
}

}  // namespace rocking::records
