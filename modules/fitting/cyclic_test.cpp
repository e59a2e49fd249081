// Reading a cyclic test: a header row of "name [unit]" columns, then numbers.
module;
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>
#include <fmt/format.h>
module rocking.fitting;
import rocking.errors;

namespace rocking {

namespace {

std::string trimmed(std::string_view s) {
  const auto a = s.find_first_not_of(" \t\r\"");
  if (a == std::string_view::npos) return {};
  const auto b = s.find_last_not_of(" \t\r\"");
  return std::string(s.substr(a, b - a + 1));
}

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::vector<std::string> fields(std::string_view line, char separator) {
  std::vector<std::string> out;
  if (separator == ' ') {
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      if (i >= line.size()) break;
      // A bracketed unit belongs to the name before it ("force [kN]").
      std::size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      std::size_t k = j;
      while (k < line.size() && (line[k] == ' ' || line[k] == '\t')) ++k;
      if (k < line.size() && (line[k] == '[' || line[k] == '(')) {
        j = line.find_first_of("])", k);
        j = j == std::string_view::npos ? line.size() : j + 1;
      }
      out.push_back(trimmed(line.substr(i, j - i)));
      i = j;
    }
    return out;
  }
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(separator, start);
    out.push_back(trimmed(line.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start)));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return out;
}

struct Column {
  std::string name, unit;  // lower case
};
Column column_of(const std::string& field) {
  const std::string t = lowercase(field);
  const auto open = t.find_first_of("([");
  if (open == std::string::npos) return {trimmed(t), ""};
  const auto close = t.find_first_of(")]", open);
  return {trimmed(t.substr(0, open)), trimmed(t.substr(open + 1, close == std::string::npos ? std::string::npos : close - open - 1))};
}

struct Quantity {
  const char* what;
  std::vector<std::pair<const char*, double>> units;  // name, factor to SI
};
const Quantity time_q{"time", {{"s", 1.0}, {"sec", 1.0}, {"ms", 1e-3}}};
const Quantity length_q{"elongation", {{"m", 1.0}, {"cm", 1e-2}, {"mm", 1e-3}, {"in", 0.0254}}};
const Quantity force_q{"force", {{"n", 1.0}, {"kn", 1e3}, {"mn", 1e6}, {"lbf", 4.4482216152605}, {"kip", 4448.2216152605}}};

double factor_of(const std::string& path, int line, const Column& c, const Quantity& q) {
  std::string known;
  for (const auto& [name, f] : q.units) {
    if (c.unit == name) return f;
    known += (known.empty() ? "" : ", ") + std::string(name);
  }
  if (c.unit.empty())
    throw InputError(fmt::format("{}:{}: column '{}' ({}) states no unit: write it as '{} [unit]' ({})", path, line,
                                 c.name, q.what, c.name, known));
  throw InputError(fmt::format("{}:{}: column '{}': unit '{}' is not a {} unit ({})", path, line, c.name, c.unit,
                               q.what, known));
}

bool named_like(const std::string& name, std::initializer_list<const char*> exact,
                std::initializer_list<const char*> prefixes) {
  for (const char* e : exact)
    if (name == e) return true;
  for (const char* p : prefixes)
    if (name.starts_with(p)) return true;
  return false;
}

// The column a --time/--elongation/--force option names, or the one found by name; -1: none.
int pick(const std::string& path, int line, const std::vector<Column>& cols, const std::string& given,
         const char* option, const auto& by_name) {
  if (!given.empty()) {
    int number = 0;
    const auto [end, ec] = std::from_chars(given.data(), given.data() + given.size(), number);
    if (ec == std::errc() && end == given.data() + given.size()) {
      if (number < 1 || number > static_cast<int>(cols.size()))
        throw InputError(fmt::format("{} {}: {} has {} columns", option, given, path, cols.size()));
      return number - 1;
    }
    const std::string want = lowercase(given);
    for (std::size_t i = 0; i < cols.size(); ++i)
      if (cols[i].name == want) return static_cast<int>(i);
    throw InputError(fmt::format("{} {}: no such column in {}:{}", option, given, path, line));
  }
  for (std::size_t i = 0; i < cols.size(); ++i)
    if (by_name(cols[i].name)) return static_cast<int>(i);
  return -1;
}

}  // namespace

constexpr double max_test_elongation = 10;  // [m]
constexpr double max_test_force = 1e10;     // [N]

CyclicTest read_cyclic_test(const std::string& path, const CyclicColumns& columns) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open the cyclic test", path));
  CyclicTest test;
  test.source = path;
  std::string text;
  int number = 0, header_line = 0;
  std::vector<Column> cols;
  char separator = ' ';
  int t_col = -1, e_col = -1, f_col = -1;
  double t_factor = 1, e_factor = 1, f_factor = 1;
  while (std::getline(in, text)) {
    ++number;
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.erase(hash);
    if (trimmed(text).empty()) continue;
    if (cols.empty()) {
      for (char c : {',', ';', '\t'})
        if (text.find(c) != std::string::npos) {
          separator = c;
          break;
        }
      for (const std::string& f : fields(text, separator)) cols.push_back(column_of(f));
      header_line = number;
      t_col = pick(path, number, cols, columns.time, "--time",
                   [](const std::string& n) { return named_like(n, {"t", "time"}, {}); });
      e_col = pick(path, number, cols, columns.elongation, "--elongation", [](const std::string& n) {
        return named_like(n, {"e", "d", "u", "x", "delta"}, {"disp", "elong", "stroke", "deform"});
      });
      f_col = pick(path, number, cols, columns.force, "--force", [](const std::string& n) {
        return named_like(n, {"f", "p"}, {"force", "load"});
      });
      if (e_col < 0 || f_col < 0)
        throw InputError(fmt::format("{}:{}: the header names no {} column (name it e.g. 'displacement [mm]' and "
                                     "'force [kN]', or pick with --elongation / --force)",
                                     path, number, e_col < 0 ? "elongation" : "force"));
      if (t_col >= 0) t_factor = factor_of(path, number, cols[static_cast<std::size_t>(t_col)], time_q);
      e_factor = factor_of(path, number, cols[static_cast<std::size_t>(e_col)], length_q);
      f_factor = factor_of(path, number, cols[static_cast<std::size_t>(f_col)], force_q);
      continue;
    }
    const std::vector<std::string> row = fields(text, separator);
    if (row.size() != cols.size())
      throw InputError(fmt::format("{}:{}: {} fields; the header has {}", path, number, row.size(), cols.size()));
    auto value = [&](int c, double factor) {
      const std::string& f = row[static_cast<std::size_t>(c)];
      double v = 0;
      const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
      if (ec != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
        throw InputError(fmt::format("{}:{}: '{}' in column '{}' is not a number", path, number, f,
                                     cols[static_cast<std::size_t>(c)].name));
      return v * factor;
    };
    // Within what the device laws take (rocking.devices: forces P0, F_s up to
    // 1e10 N; elongations d_y, g0 up to 10 m): beyond, a unit or a typo.
    auto bounded = [&](int c, double v, double bound, const char* unit) {
      if (!(std::abs(v) <= bound))
        throw InputError(fmt::format("{}:{}: {:g} {} in column '{}' is beyond {:g} {}, more than any device takes",
                                     path, number, v, unit, cols[static_cast<std::size_t>(c)].name, bound, unit));
      return v;
    };
    if (t_col >= 0) test.t.push_back(value(t_col, t_factor));
    test.e.push_back(bounded(e_col, value(e_col, e_factor), max_test_elongation, "m"));
    test.F.push_back(bounded(f_col, value(f_col, f_factor), max_test_force, "N"));
  }
  if (cols.empty()) throw InputError(fmt::format("{}: empty: a cyclic test needs a header row and samples", path));
  if (test.e.empty()) throw InputError(fmt::format("{}:{}: a header and no samples", path, header_line));
  // A test that never moves or never loads the device determines no law.
  for (const auto& [values, c, unit] : {std::tuple{&test.e, e_col, "m"}, std::tuple{&test.F, f_col, "N"}}) {
    const auto [low, high] = std::minmax_element(values->begin(), values->end());
    if (!(*high > *low))
      throw InputError(fmt::format("{}: column '{}' holds {:g} {} in every row: a cyclic test must move and load the "
                                   "device", path, cols[static_cast<std::size_t>(c)].name, *low, unit));
  }
  return test;
}

}  // namespace rocking
