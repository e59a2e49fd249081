// Records kept as a table with a header row: "time (s), acc (g)",
// "t,a_g", "time_s;acceleration_m_s2", tab- or space-separated as well.
// The time column is named t or time (seconds, or ms when it says so); an
// acceleration column by a name starting acc, a or ag; its unit from brackets
// "(g)", "[m/s^2]", "(cm/s/s)", "(gal)" or a suffix "_g", "_m_s2", "_cm_s2",
// "_mm_s2", "_gal". Without a time column the samples are --dt apart. A file
// with several acceleration columns picks one with --component (its name or
// its 1-based column number).
module;
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
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

const Line* data_line(const std::vector<Line>& lines, std::size_t skip) {
  for (const Line& l : lines)
    if (!blank_or_comment(l) && skip-- == 0) return &l;
  return nullptr;
}

char separator_of(std::string_view header) {
  for (char c : {',', ';', '\t'})
    if (header.find(c) != std::string_view::npos) return c;
  return ' ';
}

// A column name split into its name and its unit text ("acc (g)" -> acc, g;
// "acc_m_s2" -> acc, m/s2).
struct Name {
  std::string base, unit;
};
Name parse_name(std::string_view raw) {
  std::string t = lower(trim(raw));
  if (t.size() >= 2 && t.front() == '"' && t.back() == '"') t = t.substr(1, t.size() - 2);
  Name n;
  const std::size_t open = t.find_first_of("([");
  if (open != std::string::npos) {
    const std::size_t close = t.find_first_of(")]", open);
    n.unit = t.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1);
    n.base = trim(t.substr(0, open));
  } else {
    n.base = t;
    for (const char* suffix : {"_m_s2", "_cm_s2", "_mm_s2", "_gal", "_g", "_ms", "_s"})
      if (t.size() > std::string_view(suffix).size() && t.ends_with(suffix)) {
        n.base = t.substr(0, t.size() - std::string_view(suffix).size());
        n.unit = std::string(suffix + 1);
        std::replace(n.unit.begin(), n.unit.end(), '_', '/');
        break;
      }
  }
  // Spellings of one unit: m/s^2, m/s/s, m/sec2, m s-2.
  std::string u;
  for (char c : n.unit)
    if (c != ' ' && c != '^' && c != '*') u += c;
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"/s/s", "/s2"}, {"/sec2", "/s2"}, {"/sec/sec", "/s2"},
                                 {"s-2", "/s2"}, {"//", "/"}})
    for (std::size_t at = u.find(from); at != std::string::npos; at = u.find(from)) u.replace(at, from.size(), to);
  n.unit = u;
  return n;
}

bool is_time(const Name& n) { return n.base == "t" || n.base == "time"; }
bool is_acceleration(const Name& n) {
  return n.base.starts_with("acc") || n.base == "a" || n.base.starts_with("a_") || n.base.starts_with("ag");
}

bool detect(const std::string&, const std::vector<Line>& lines) {
  const Line* head = data_line(lines, 0);
  if (!head) return false;
  const std::vector<std::string> names = split_fields(head->text, separator_of(head->text));
  if (!std::any_of(names.begin(), names.end(), [](const std::string& s) { return is_acceleration(parse_name(s)); }) ||
      std::any_of(names.begin(), names.end(), [](const std::string& s) { return whole_number(s).has_value(); }))
    return false;
  // A table of numbers follows its header (prose with a comma and an "a" in
  // its first line, such as a README, does not).
  const Line* row = data_line(lines, 1);
  if (!row) return false;
  const std::vector<std::string> cells = split_fields(row->text, separator_of(head->text));
  return cells.size() == names.size() && std::all_of(cells.begin(), cells.end(), [](const std::string& c) {
           const std::string t = trim(c);
           char* end = nullptr;
           std::strtod(t.c_str(), &end);
           return !t.empty() && end == t.c_str() + t.size();
         });
}

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  const Line* head = data_line(lines, 0);
  if (!head) fail(path, 1, "the record is empty");
  const char sep = separator_of(head->text);
  const std::vector<std::string> raw = split_fields(head->text, sep);
  std::vector<Name> names;
  for (const std::string& r : raw) names.push_back(parse_name(r));
  std::optional<std::size_t> time, acc;
  std::vector<std::size_t> accs;
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (is_time(names[i])) {
      if (time) fail(path, head->number, fmt::format("two time columns ('{}' and '{}')", raw[*time], raw[i]));
      time = i;
    } else if (is_acceleration(names[i])) {
      accs.push_back(i);
    }
  }
  if (!o.component.empty()) {
    const std::optional<double> index = whole_number(o.component);
    for (std::size_t i = 0; i < names.size(); ++i)
      if (lower(raw[i]) == lower(o.component) || names[i].base == lower(o.component)) acc = i;
    if (!acc && index && *index >= 1 && *index <= static_cast<double>(names.size()) && *index == std::floor(*index))
      acc = static_cast<std::size_t>(*index) - 1;
    if (!acc || acc == time)
      throw InputError(fmt::format("{}: --component {}: no acceleration column of that name or number (the header "
                                   "names {})", path, o.component, trim(head->text)));
  } else if (accs.size() == 1) {
    acc = accs[0];
  } else {
    std::string list;
    for (std::size_t i : accs) list += (list.empty() ? "'" : ", '") + raw[i] + "'";
    fail(path, head->number, accs.empty() ? "no acceleration column in the header (name one acc, a or ag)"
                                          : fmt::format("columns {} are all accelerations: choose one with --component", list));
  }
  // Units: the header's, or --units; both must agree.
  std::optional<AccelerationUnit> stated;
  if (!names[*acc].unit.empty()) {
    try {
      stated = parse_acceleration_unit(names[*acc].unit);
    } catch (const InputError&) {
      fail(path, head->number, fmt::format("column '{}': unknown acceleration unit '{}' (g, m/s2, cm/s2, gal or mm/s2)",
                                           raw[*acc], names[*acc].unit));
    }
  }
  if (!stated && !o.unit)
    fail(path, head->number, fmt::format("column '{}' names no unit: write it as 'acc (g)' or 'acc_m_s2', or give --units",
                                         raw[*acc]));
  const AccelerationUnit unit = stated ? file_unit(path, head->number, *stated, o) : *o.unit;
  double time_scale = 1;
  if (time) {
    const std::string& tu = names[*time].unit;
    if (tu == "ms") time_scale = 1e-3;
    else if (!tu.empty() && tu != "s" && tu != "sec")
      fail(path, head->number, fmt::format("column '{}': time unit '{}' (s or ms)", raw[*time], tu));
    if (o.dt > 0) fail(path, head->number, fmt::format("--dt {:g}: the file has a time column ('{}')", o.dt, raw[*time]));
  } else if (!(o.dt > 0)) {
    fail(path, head->number, "no time column (name one t or time), and no --dt");
  }
  TimedSamples samples;
  bool past_header = false;
  for (const Line& l : lines) {
    if (blank_or_comment(l)) continue;
    if (!past_header) {
      past_header = true;
      continue;
    }
    const std::vector<std::string> cells = split_fields(l.text, sep);
    if (cells.size() != names.size())
      fail(path, l.number, fmt::format("{} fields, the header names {}", cells.size(), names.size()));
    const double t = time ? number_at(path, l.number, cells[*time]) * time_scale : static_cast<double>(samples.size()) * o.dt;
    samples.add(path, l.number, t, number_at(path, l.number, cells[*acc]) * to_si(unit));
  }
  RecordInfo info;
  info.units = unit_name(unit);
  info.component = raw[*acc];
  return std::move(samples).record(path, lines.back().number, std::move(info));
}

// A header row naming time and acceleration with units, then the rows.
std::string example() {
  const ExampleRecord e = example_record();
  std::string s = "time (s),acc (g)\n";
  for (std::size_t i = 0; i < e.values.size(); ++i) s += fmt::format("{:.2f},{:.9f}\n", e.dt * static_cast<double>(i), e.values[i]);
  return s;
}

}  // namespace

FormatReader csv_format() {
  return {"csv", "a table with a header row naming the time and acceleration columns and units", detect, read, example};
}

}  // namespace rocking::records
