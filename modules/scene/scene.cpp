module;
#include <rocking/eigen.hpp>
#include <toml++/toml.h>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <optional>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <ranges>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
#include <fmt/ranges.h>
module rocking.scene;
import rocking.errors;
import rocking.records;

namespace rocking {

namespace {

// The schema: every table and key a scene may hold. Anything else is an error,
// so that a typo never silently falls back to a default.
const std::map<std::string, std::set<std::string, std::less<>>, std::less<>> schema = {
    {"scene", {"name", "description"}},
    {"structure", {"half_width", "heights", "masses", "base_mass", "second_moments",
                   "youngs_modulus", "EI_scale", "damping_ratio", "rigid"}},
    {"contact", {"rocking", "restitution", "theta_dot_min", "overturn_angle", "friction"}},
    {"excitation", {"kind", "pulse", "amplitude_g", "period", "record", "component", "units", "dt", "scale", "duration",
                    "vertical", "vertical_component", "vertical_units"}},
    {"initial", {"theta", "theta_dot", "u", "u_dot"}},
    {"damper", {"enabled", "stiffness", "post_yield_ratio", "theta_y", "alpha", "beta", "n",
                "thickness", "capacity"}},
    {"output", {"history", "interval"}},
    {"columns", {"count", "half_width", "half_height", "mass", "spacing"}},
};

std::string where(const toml::source_region& src, std::string_view fallback) {
  if (!src.path) return std::string(fallback);
  return fmt::format("{}:{}", *src.path, src.begin.line);
}

// "table.key" -> "--set table.key=value" for every overridden key: toml++ does
// not keep a node's source when it is copied into the scene's table.
using Origins = std::map<std::string, std::string, std::less<>>;

// Reads typed values out of one table, failing with file:line and the key.
class TableReader {
 public:
  TableReader(const toml::table& root, std::string table, std::string file, const Origins& origins)
      : table_name_(std::move(table)), file_(std::move(file)), origins_(origins) {
    const toml::node* node = root.get(table_name_);
    if (node == nullptr) fail(nullptr, "", fmt::format("missing table [{}]", table_name_));
    table_ = node->as_table();
    if (table_ == nullptr) fail(node, "", "must be a table");
  }
  // One table of an array of tables, named e.g. "device[0]".
  TableReader(const toml::table* table, std::string name, std::string file, const Origins& origins)
      : table_name_(std::move(name)), file_(std::move(file)), origins_(origins), table_(table) {}

  const toml::table& table() const { return *table_; }

  bool has(std::string_view key) const { return table_->get(key) != nullptr; }

  [[noreturn]] void fail(const toml::node* node, std::string_view key, std::string_view what) const {
    throw InputError(fmt::format("{}: {}", origin(node, key), what));
  }

  // "where: table.key": the file and line of `node`, or the --set that gave it.
  std::string origin(const toml::node* node, std::string_view key) const {
    const std::string name = key.empty() ? table_name_ : fmt::format("{}.{}", table_name_, key);
    // The --set that gave the key, the array holding it, or its whole table.
    const auto bracket = name.rfind('['), dot = name.rfind('.');
    auto set = origins_.find(name);
    if (set == origins_.end() && bracket != std::string::npos && (dot == std::string::npos || bracket > dot))
      set = origins_.find(name.substr(0, bracket));
    if (set == origins_.end()) set = origins_.find(table_name_);
    const std::string at = set != origins_.end() ? set->second
                           : node                ? where(node->source(), file_)
                           : table_              ? where(table_->source(), file_)
                                                 : file_;
    return fmt::format("{}: {}", at, name);
  }

  const toml::node& required(std::string_view key) const {
    const toml::node* node = table_->get(key);
    if (node == nullptr) fail(nullptr, key, "missing key");
    return *node;
  }

  double number(std::string_view key, const std::function<bool(double)>& ok,
                std::string_view rule) const {
    return checked_number(required(key), key, ok, rule);
  }

  double number_or(std::string_view key, double fallback, const std::function<bool(double)>& ok,
                   std::string_view rule) const {
    return has(key) ? number(key, ok, rule) : fallback;
  }

  Eigen::VectorXd numbers(std::string_view key, const std::function<bool(double)>& ok,
                          std::string_view rule) const {
    const toml::node& node = required(key);
    const toml::array* array = node.as_array();
    if (array == nullptr || array->empty()) fail(&node, key, "must be a non-empty array of numbers");
    Eigen::VectorXd out(static_cast<Eigen::Index>(array->size()));
    for (std::size_t i = 0; i < array->size(); ++i)
      out[static_cast<Eigen::Index>(i)] =
          checked_number((*array)[i], fmt::format("{}[{}]", key, i), ok, rule);
    return out;
  }

  bool boolean_or(std::string_view key, bool fallback) const {
    if (!has(key)) return fallback;
    const toml::node& node = required(key);
    if (!node.is_boolean()) fail(&node, key, "must be true or false");
    return *node.value<bool>();
  }

  std::string string(std::string_view key) const {
    const toml::node& node = required(key);
    if (!node.is_string()) fail(&node, key, "must be a string");
    return *node.value<std::string>();
  }

  std::string string_or(std::string_view key, std::string fallback) const {
    if (!has(key)) return fallback;
    const toml::node& node = required(key);
    if (!node.is_string()) fail(&node, key, "must be a string");
    return *node.value<std::string>();
  }

 private:
  double checked_number(const toml::node& node, std::string_view key,
                        const std::function<bool(double)>& ok, std::string_view rule) const {
    if (!node.is_number()) fail(&node, key, "must be a number");
    // toml++ gives an integer as a double only when the double holds it
    // exactly (an empty optional otherwise): take the nearest double.
    const double v = node.is_integer() ? static_cast<double>(*node.value<std::int64_t>()) : *node.value<double>();
    if (!std::isfinite(v)) fail(&node, key, "must be a finite number");
    if (!ok(v)) fail(&node, key, fmt::format("must be {} (got {})", rule, v));
    return v;
  }

  std::string table_name_;
  std::string file_;
  const Origins& origins_;
  const toml::table* table_ = nullptr;
};

const auto positive = [](double v) { return v > 0; };
// (low, high] or [low, high]: bounds beyond which a value is a typo, not a structure.
auto in_range(double low, double high, bool low_included) {
  return [=](double v) { return (low_included ? v >= low : v > low) && v <= high; };
}
constexpr double max_mass = 1e12;      // [kg], a mountain
constexpr double max_length = 1e4;     // [m] (and m^4 for second moments)
constexpr double max_modulus = 1e13;   // [Pa], ten times diamond
constexpr double max_duration = 1e5;   // [s], about 28 hours
constexpr double min_pulse_period = 1e-3, max_pulse_period = 1e3;  // [s]
// The fastest an initial condition may move any point of the structure:
// a hundred times the fastest ground (about 1 m/s).
constexpr double max_initial_speed = 100;  // [m/s]
// Lower bounds that keep K and M within the range of doubles and the
// eigenproblems well posed, far below any structure: a gram, a millimetre.
constexpr double min_mass = 1e-3;      // [kg]
constexpr double min_length = 1e-3;    // [m], and between consecutive heights
constexpr double min_second_moment = 1e-16;  // [m^4]
constexpr double min_modulus = 1e3;    // [Pa], softer than any rubber
// Nodes of a structure: its eigenproblems are O(N^3) (1000 nodes: seconds).
constexpr std::size_t max_nodes = 1000;
const auto non_negative = [](double v) { return v >= 0; };

void check_known_keys(const toml::table& root, const std::string& file) {
  for (auto&& [table_key, node] : root) {
    if (table_key.str() == "device") {  // read_devices checks each table's keys against its law's
      if (!node.is_array())
        throw InputError(fmt::format("{}: device: devices are [[device]] tables (an array of tables)",
                                     where(table_key.source(), file)));
      continue;
    }
    if (table_key.str() == "joint") {  // read_joints checks each table's keys
      if (!node.is_array())
        throw InputError(fmt::format("{}: joint: joints are [[joint]] tables (an array of tables)",
                                     where(table_key.source(), file)));
      continue;
    }
    const auto known = schema.find(table_key.str());
    if (known == schema.end())
      throw InputError(fmt::format("{}: unknown table [{}] (known: {}, [[device]], [[joint]])", where(table_key.source(), file),
                                   table_key.str(), fmt::join(schema | std::views::keys, ", ")));
    if (const toml::table* table = node.as_table())
      for (auto&& [key, value] : *table)
        if (!known->second.contains(key.str()))
          throw InputError(fmt::format("{}: {}.{}: unknown key (known: {})",
                                       where(key.source(), file), table_key.str(), key.str(),
                                       fmt::join(known->second, ", ")));
  }
}

// "table.key=value": the value is parsed as TOML; a bare word becomes a string.
// The value of "key=value" as TOML (in the table returned, under "v").
toml::table parse_override_value(const std::string& value, const std::string& origin) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value, origin);
  } catch (const toml::parse_error&) {
    if (value.find_first_of("'\n") != std::string::npos)
      throw InputError(fmt::format("{}: value is neither TOML nor a plain word", origin));
    parsed = toml::parse("v = '" + value + "'", origin);
  }
  return parsed;
}

// The [[device]] forms of --set: device+={...} appends a device, device-=NAME
// removes the one of that name, device=[...] replaces them all (device=[]
// removes them), device[I].KEY=VALUE sets one key of device I (from 0).
// Returns false for any other text.
bool apply_device_override(toml::table& root, const std::string& text, Origins& origins) {
  if (!text.starts_with("device")) return false;
  const std::string origin = "--set " + text;
  const auto eq = text.find('=');
  if (eq == std::string::npos) return false;
  const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
  toml::array* list = root.get_as<toml::array>("device");
  const auto ensure_list = [&] {
    if (list == nullptr) {
      root.insert_or_assign("device", toml::array{});
      list = root.get_as<toml::array>("device");
    }
  };
  if (key == "device-") {  // device-=NAME: removes the [[device]] tables of that name
    const std::size_t before = list == nullptr ? 0 : list->size();
    if (list != nullptr)
      for (std::size_t i = list->size(); i-- > 0;) {
        const toml::table* t = list->get_as<toml::table>(i);
        const auto* name = t != nullptr ? t->get_as<std::string>("name") : nullptr;
        if (name != nullptr && name->get() == value) list->erase(list->begin() + static_cast<std::ptrdiff_t>(i));
      }
    if (list == nullptr || list->size() == before) {
      // The paper's [damper] is a device like the others: device-=damper removes it.
      toml::table* damper = root.get_as<toml::table>("damper");
      const auto* enabled = damper != nullptr ? damper->get_as<bool>("enabled") : nullptr;
      if (value == "damper" && damper != nullptr && (enabled == nullptr || enabled->get())) {
        damper->insert_or_assign("enabled", false);
        origins["damper.enabled"] = origin;
        return true;
      }
      throw InputError(fmt::format("{}: no [[device]] named '{}'", origin, value));
    }
    return true;
  }
  if (key == "device+" || key == "device") {
    const toml::table parsed = parse_override_value(value, origin);
    const toml::node* node = parsed.get("v");
    if (key == "device+") {
      if (!node->is_table())
        throw InputError(fmt::format("{}: expected one device as an inline table, e.g. device+={{kind=\"elastic\", "
                                     "at=0, kinematics=\"vertical\", free_length=10, P0=1e6, k=1e8}}", origin));
      ensure_list();
      origins[fmt::format("device[{}]", list->size())] = origin;
      list->push_back(*node->as_table());
      return true;
    }
    if (!node->is_array() || !(node->as_array()->empty() || node->as_array()->is_array_of_tables()))
      throw InputError(fmt::format("{}: expected an array of inline tables (device=[] removes every device)", origin));
    root.insert_or_assign("device", *node->as_array());
    for (std::size_t i = 0; i < node->as_array()->size(); ++i) origins[fmt::format("device[{}]", i)] = origin;
    return true;
  }
  std::size_t index = 0, leaf_at = 0;
  if (std::sscanf(key.c_str(), "device[%zu].%zn", &index, &leaf_at) != 1 || leaf_at == 0 || leaf_at >= key.size())
    return false;
  const std::string leaf = key.substr(leaf_at);
  if (leaf.find_first_of(".[") != std::string::npos) return false;
  const std::size_t count = list == nullptr ? 0 : list->size();
  if (index >= count)
    throw InputError(fmt::format("{}: no device [{}]: the scene has {} device table{} (device+={{...}} adds one)",
                                 origin, index, count, count == 1 ? "" : "s"));
  toml::table* table = list->get_as<toml::table>(index);
  if (table == nullptr) throw InputError(fmt::format("{}: device[{}] is not a table", origin, index));
  table->insert_or_assign(leaf, *parse_override_value(value, origin).get("v"));
  origins[key] = origin;
  return true;
}

// The [[joint]] forms of --set: joint+={...} appends a joint, joint=[...]
// replaces them all (joint=[] removes them), joint[I].KEY=VALUE sets one key
// of joint I (from 0). Returns false for any other text.
bool apply_joint_override(toml::table& root, const std::string& text, Origins& origins) {
  if (!text.starts_with("joint")) return false;
  const std::string origin = "--set " + text;
  const auto eq = text.find('=');
  if (eq == std::string::npos) return false;
  const std::string key = text.substr(0, eq), value = text.substr(eq + 1);
  toml::array* list = root.get_as<toml::array>("joint");
  if (key == "joint+") {
    const toml::table parsed = parse_override_value(value, origin);
    const toml::node* node = parsed.get("v");
    if (!node->is_table())
      throw InputError(fmt::format("{}: expected one joint as an inline table, e.g. joint+={{node=3, half_width=1.5, "
                                   "base_mass=0}}", origin));
    if (list == nullptr) {
      root.insert_or_assign("joint", toml::array{});
      list = root.get_as<toml::array>("joint");
    }
    origins[fmt::format("joint[{}]", list->size())] = origin;
    list->push_back(*node->as_table());
    return true;
  }
  if (key == "joint") {
    const toml::table parsed = parse_override_value(value, origin);
    const toml::node* node = parsed.get("v");
    if (!node->is_array() || !(node->as_array()->empty() || node->as_array()->is_array_of_tables()))
      throw InputError(fmt::format("{}: expected an array of inline tables (joint=[] removes every joint)", origin));
    root.insert_or_assign("joint", *node->as_array());
    for (std::size_t i = 0; i < node->as_array()->size(); ++i) origins[fmt::format("joint[{}]", i)] = origin;
    return true;
  }
  std::size_t index = 0, leaf_at = 0;
  if (std::sscanf(key.c_str(), "joint[%zu].%zn", &index, &leaf_at) != 1 || leaf_at == 0 || leaf_at >= key.size())
    return false;
  const std::string leaf = key.substr(leaf_at);
  if (leaf.find_first_of(".[") != std::string::npos) return false;
  const std::size_t count = list == nullptr ? 0 : list->size();
  if (index >= count)
    throw InputError(fmt::format("{}: no joint [{}]: the scene has {} joint table{} (joint+={{...}} adds one)", origin,
                                 index, count, count == 1 ? "" : "s"));
  toml::table* table = list->get_as<toml::table>(index);
  if (table == nullptr) throw InputError(fmt::format("{}: joint[{}] is not a table", origin, index));
  table->insert_or_assign(leaf, *parse_override_value(value, origin).get("v"));
  origins[key] = origin;
  return true;
}

void apply_override(toml::table& root, const std::string& text, Origins& origins) {
  if (apply_device_override(root, text, origins)) return;
  if (apply_joint_override(root, text, origins)) return;
  const auto eq = text.find('=');
  const std::string key = eq == std::string::npos ? "" : text.substr(0, eq);
  const std::string value = eq == std::string::npos ? "" : text.substr(eq + 1);
  const auto dot = key.find('.');
  const bool shaped = !key.empty() && !value.empty() && dot != std::string::npos &&
                      dot > 0 && dot + 1 < key.size() && key.find('.', dot + 1) == std::string::npos;
  if (!shaped) throw InputError(fmt::format("--set {}: expected TABLE.KEY=VALUE, e.g. structure.EI_scale=0.5", text));
  const std::string table_name = key.substr(0, dot), leaf = key.substr(dot + 1);
  const auto known = schema.find(table_name);
  if (known == schema.end() || !known->second.contains(leaf))
    throw InputError(fmt::format("--set {}: unknown key '{}'", text, key));
  const std::string origin = "--set " + text;
  const toml::table parsed = parse_override_value(value, origin);
  if (!root.contains(table_name)) root.insert(table_name, toml::table{});
  toml::table* table = root.get_as<toml::table>(table_name);
  if (table == nullptr) throw InputError(fmt::format("{}: [{}] is not a table", origin, table_name));
  table->insert_or_assign(leaf, *parsed.get("v"));
  origins[key] = origin;
}

Structure read_structure(const toml::table& root, const std::string& file, const Origins& origins) {
  const TableReader t(root, "structure", file, origins);
  Structure s;
  const std::string length_range = fmt::format("in [{:g}, {:g}] m", min_length, max_length);
  s.half_width = t.number("half_width", in_range(min_length, max_length, true), length_range);
  s.heights = t.numbers("heights", in_range(min_length, max_length, true), length_range);
  if (static_cast<std::size_t>(s.heights.size()) > max_nodes)
    t.fail(&t.required("heights"), "heights", fmt::format("{} nodes (at most {})", s.heights.size(), max_nodes));
  s.masses = t.numbers("masses", in_range(min_mass, max_mass, true), fmt::format("in [{:g}, {:g}] kg", min_mass, max_mass));
  s.base_mass = t.number("base_mass", in_range(0, max_mass, true), fmt::format("non-negative and at most {:g} kg", max_mass));
  s.rigid = t.boolean_or("rigid", false);
  const auto n = s.heights.size();
  if (s.masses.size() != n) t.fail(&t.required("masses"), "masses", fmt::format("must have one entry per height ({})", n));
  s.EI_scale = t.number_or("EI_scale", 1.0, [](double v) { return v >= 1e-6 && v <= 1e6; }, "in [1e-6, 1e6]");
  if (!s.rigid || t.has("second_moments")) {  // a rigid block needs no sections
    const Eigen::VectorXd I = t.numbers("second_moments", in_range(min_second_moment, max_length, true),
                                        fmt::format("in [{:g}, {:g}] m^4", min_second_moment, max_length));
    if (I.size() != n) t.fail(&t.required("second_moments"), "second_moments", fmt::format("must have one entry per element ({})", n));
    s.EI = t.number("youngs_modulus", in_range(min_modulus, max_modulus, true),
                    fmt::format("in [{:g}, {:g}] Pa", min_modulus, max_modulus)) *
           I;
  }
  s.damping_ratio = s.rigid && !t.has("damping_ratio")
                        ? 0.0
                        : t.number("damping_ratio", [](double z) { return z >= 0 && z < 1; }, "in [0, 1)");
  const toml::array& h = *t.required("heights").as_array();
  for (Eigen::Index i = 1; i < n; ++i)
    if (!(s.heights[i] >= s.heights[i - 1] + min_length))
      t.fail(h.get(static_cast<std::size_t>(i)), fmt::format("heights[{}]", i),
             fmt::format("heights must increase by at least {:g} m (got {} after {})", min_length, s.heights[i],
                         s.heights[i - 1]));
  return s;
}

// The rocking base the devices of a scene stand on (MODEL.md 11): the
// structure's own, or on [columns] one column as a rigid block (half-width b,
// its mass at mid-height), every device standing at the base of each column
// alike (MODEL.md 16: the columns rock in unison).
Structure device_base(const Scene& scene) {
  if (!scene.columns) return scene.structure;
  Structure column;
  column.rigid = true;
  column.half_width = scene.columns->half_width;
  column.heights = Eigen::VectorXd::Constant(1, scene.columns->half_height);
  column.masses = Eigen::VectorXd::Constant(1, scene.columns->mass);
  column.base_mass = 0;
  return column;
}

// [columns] (MODEL.md 16): n identical rigid columns under the structure's
// foundation beam. spacing (between the outer columns' axes) is needed from
// two columns on, and must leave room for the columns' width.
std::optional<ColumnGroup> read_columns(const toml::table& root, const std::string& file, const Origins& origins) {
  if (!root.contains("columns")) return std::nullopt;
  const TableReader t(root, "columns", file, origins);
  constexpr double max_columns = 1000;
  ColumnGroup c;
  c.count = static_cast<int>(t.number("count", [](double v) { return v >= 1 && v <= max_columns && v == std::floor(v); },
                                      fmt::format("a whole number from 1 to {:g}", max_columns)));
  const std::string length_range = fmt::format("in [{:g}, {:g}] m", min_length, max_length);
  c.half_width = t.number("half_width", in_range(min_length, max_length, true), length_range);
  c.half_height = t.number("half_height", in_range(min_length, max_length, true), length_range);
  c.mass = t.number("mass", in_range(min_mass, max_mass, true), fmt::format("in [{:g}, {:g}] kg", min_mass, max_mass));
  if (c.count >= 2 || t.has("spacing"))
    c.spacing = t.number("spacing", [&](double v) { return v >= 2 * c.half_width && v <= max_length; },
                         fmt::format("at least a column's width, 2 half_width = {:g} m, and at most {:g} m",
                                     2 * c.half_width, max_length));
  return c;
}

Contact read_contact(const toml::table& root, const std::string& file, const Origins& origins, Scene& scene) {
  Contact c;
  if (!root.contains("contact")) return c;
  const TableReader t(root, "contact", file, origins);
  c.rocking = t.boolean_or("rocking", true);
  c.theta_dot_min = t.number_or("theta_dot_min", c.theta_dot_min, non_negative, "non-negative");
  c.overturn_angle = t.number_or("overturn_angle", 0.0, [](double a) { return a > 0 && a < 1.5707963; },
                                 "in (0, pi/2) [rad]");
  scene.base_friction = t.number_or("friction", scene.base_friction, [](double v) { return v > 0 && v <= 100; },
                                    "a friction coefficient in (0, 100] (leave it out: not checked)");
  if (t.has("restitution")) {
    const toml::node& r = t.required("restitution");
    if (r.is_string()) {
      const std::string rule = *r.value<std::string>();
      if (rule == "eq10") c.restitution_rule = RestitutionRule::eq10;
      else if (rule == "eq9") c.restitution_rule = RestitutionRule::eq9;
      else if (rule == "momentum") scene.momentum_base = true;  // MODEL.md 15's law: the chain's (Eq. 10 for a rigid block)
      else t.fail(&r, "restitution", fmt::format("must be a number in [0, 1], eq10, eq9 or momentum (got '{}')", rule));
    } else {
      c.restitution_rule = RestitutionRule::constant;
      c.restitution = t.number("restitution", [](double v) { return v >= 0 && v <= 1; }, "in [0, 1], eq10 or eq9");
    }
  }
  return c;
}

Damper read_damper(const toml::table& root, const std::string& file, const Origins& origins, const Structure& st) {
  Damper d;
  if (!root.contains("damper")) {
    d.enabled = false;
    return d;
  }
  const TableReader t(root, "damper", file, origins);
  d.enabled = t.boolean_or("enabled", true);
  if (!d.enabled) return d;  // a disabled damper needs no properties (e.g. --set damper.enabled=false on a scene without one)
  d.stiffness = t.number("stiffness", in_range(0, 1e13, false), "positive and at most 1e+13 [N/m]");
  d.post_yield_ratio = t.number("post_yield_ratio", [](double e) { return e >= 0 && e < 1; }, "in [0, 1)");
  // The yield chord 4B sin(theta_y / 2) grows with theta_y up to pi; a
  // structure tilted by pi/2 lies on its side.
  // and its yield elongation d_y = 4B sin(theta_y / 2) is at least a micron,
  // as a Bouc-Wen device's (rocking.devices): below, z' = e' / d_y outruns any step.
  const double min_theta_y = 2 * std::asin(std::min(1.0, 1e-6 / (4 * st.half_width)));
  d.theta_y = t.number("theta_y", in_range(min_theta_y, 1.5707963, true),
                       fmt::format("in [{:.3g}, pi/2) [rad] (a yield elongation 4B sin(theta_y/2) of 1 um to the "
                                   "structure on its side)", min_theta_y));
  d.alpha = t.number_or("alpha", 1.0, in_range(0, 100, true), "in [0, 100]");
  d.beta = t.number_or("beta", 0.0, [](double b) { return std::abs(b) <= 100; }, "in [-100, 100]");
  d.n = t.number_or("n", 1.0, [](double n) { return n >= 1 && n <= 50; }, "in [1, 50]");
  d.thickness = t.number_or("thickness", 1.0, in_range(0, 100, false), "in (0, 100]");
  d.capacity = t.number_or("capacity", 0.0, positive, "positive [m] (leave it out: never breaks)");
  if (!(d.alpha + d.beta > 0)) t.fail(nullptr, "beta", "alpha + beta must be positive (bounded hysteresis)");
  return d;
}

// [[device]] tables (MODEL.md 11): kind (a law of rocking.devices), at (x
// [m] from the centre line, or "edges" for one device at each edge, named
// NAME_left and NAME_right), kinematics (chord, or vertical with free_length
// [m]), capacity [m] (optional), name (optional), and the law's own keys;
// with [[joint]] tables, a tendon's segment and from_segment (its anchors'
// segments; the ground and the top by default), or another device's joint
// (the joint it stands across, 0 .. J; 0, the base, by default), whose half-width
// bounds its at.
// On [columns] (`columns` given) a device stands at each column's base (at
// from the column's axis), or with kinematics = "beam" joins the ground to the
// cap beam, once (MODEL.md 16): at is then its ground anchor's x and
// ground_height its height above the columns' bottoms (default 0), beam_at
// its anchor's x on the beam's underside (within the outer columns' outer
// faces), all from the frame's centre line; its elongation counts from the
// anchors' rest distance.
// A [[device]] table's keys: the common ones, a beam device's on [columns],
// and its law's parameters; any other fails naming the known ones.
void check_device_keys(const TableReader& t, const toml::table& table, const std::string& kind, const LawInfo& law,
                       bool on_columns) {
  std::set<std::string, std::less<>> known = {"name", "kind", "at", "kinematics", "free_length", "capacity",
                                              "segment", "from_segment", "joint"};
  if (on_columns) known.insert({"beam_at", "ground_height"});
  for (const LawParameter& p : law.parameters) known.insert(p.key);
  for (auto&& [key, value] : table)
    if (!known.contains(key.str()))
      t.fail(&value, key.str(), fmt::format("unknown key for a {} device (known: {})", kind, fmt::join(known, ", ")));
}

// A device's name (KIND_N, the table's number, unless given): it names output
// columns, so letters, digits, _ or - only.
std::string device_name(const TableReader& t, const std::string& kind, std::size_t i) {
  const std::string name = t.string_or("name", fmt::format("{}_{}", kind, i + 1));
  const bool plain = !name.empty() && std::ranges::all_of(name, [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-';
  });
  if (!plain) t.fail(&t.required("name"), "name", "must be letters, digits, _ or - (it names output columns)");
  return name;
}

// A device's kinematics: chord (default), vertical with its free_length, or
// on [columns] (`columns` given) beam, with its anchor on the beam (beam_at)
// and its ground anchor's height (ground_height); its x is placed_devices'.
DeviceGeometry device_geometry(const TableReader& t, const ColumnGroup* columns) {
  const bool on_columns = columns != nullptr;
  DeviceGeometry geometry;
  const std::string kinematics = t.string_or("kinematics", "chord");
  if (kinematics == "vertical") {
    geometry.kinematics = Kinematics::vertical;
    geometry.free_length = t.number("free_length", in_range(min_length, max_length, true),
                                    fmt::format("in [{:g}, {:g}] m", min_length, max_length));
  } else if (kinematics == "chord") {
    if (t.has("free_length")) t.fail(&t.required("free_length"), "free_length", "only a vertical device has a free length");
  } else if (kinematics == "beam") {
    if (!on_columns)
      t.fail(&t.required("kinematics"), "kinematics",
             "beam joins the ground to the cap beam of a structure on [columns]; this scene has none");
    geometry.kinematics = Kinematics::beam;
    if (t.has("free_length"))
      t.fail(&t.required("free_length"), "free_length",
             "a beam device's elongation counts from its anchors' rest distance (a prestress is its law's)");
    const double reach = columns->count >= 2 ? 0.5 * columns->spacing + columns->half_width : columns->half_width;
    geometry.beam_x = t.number("beam_at", [reach](double x) { return std::abs(x) <= reach; },
                               fmt::format("on the beam's underside over the columns, from the frame's centre "
                                           "line: |x| <= {:g} [m]", reach));
    geometry.ground_y = t.number_or("ground_height", 0.0, [](double y) { return std::abs(y) <= max_length; },
                                    fmt::format("the ground anchor's height above the columns' bottoms, in [{:g}, {:g}] m",
                                                -max_length, max_length));
  } else {
    t.fail(&t.required("kinematics"), "kinematics",
           fmt::format("must be chord or vertical{} (got '{}')", on_columns ? ", or beam" : "", kinematics));
  }
  if (geometry.kinematics != Kinematics::beam)
    for (const char* key : {"beam_at", "ground_height"})
      if (t.has(key)) t.fail(&t.required(key), key, "only a beam device (kinematics = \"beam\", on [columns]) has it");
  return geometry;
}

// Where a device stands on a structure with [[joint]] tables (-1: not given):
// a tendon's anchors' segments, or the joint another device stands across.
struct DevicePlace {
  int segment = -1;       // its upper anchor's segment (0 .. J; -1: the top)
  int from_segment = -1;  // its lower anchor's, below the upper one's (-1: the ground)
  int joint = -1;         // the joint it stands across (0: the base; -1: the base by default)
};
DevicePlace device_place(const TableReader& t, std::size_t joints, const DeviceGeometry& geometry) {
  DevicePlace place;
  if (t.has("segment")) {
    if (joints == 0)
      t.fail(&t.required("segment"), "segment", "only a structure with [[joint]] tables has segments above its base");
    place.segment = static_cast<int>(t.number("segment", [joints](double v) {
      return v >= 0 && v <= static_cast<double>(joints) && v == std::floor(v);
    }, fmt::format("a segment of the structure, an integer 0 to {} (one per [[joint]] above the base)", joints)));
  }
  if (t.has("from_segment")) {
    if (joints == 0)
      t.fail(&t.required("from_segment"), "from_segment",
             "only a structure with [[joint]] tables has segments above its base");
    const double upper = place.segment < 0 ? static_cast<double>(joints) : place.segment;
    place.from_segment = static_cast<int>(t.number("from_segment", [upper](double v) {
      return v >= 0 && v < upper && v == std::floor(v);
    }, fmt::format("a segment below the upper anchor's, an integer 0 to {}", static_cast<int>(upper) - 1)));
  }
  // A device that is not a tendon, anchored on the face below and the segment above.
  if (t.has("joint")) {
    if (joints == 0)
      t.fail(&t.required("joint"), "joint", "only a structure with [[joint]] tables has joints above its base");
    place.joint = static_cast<int>(t.number("joint", [joints](double v) {
      return v >= 0 && v <= static_cast<double>(joints) && v == std::floor(v);
    }, fmt::format("a joint of the structure, an integer 0 (the base) to {} (one per [[joint]])", joints)));
    if (t.has("segment") || t.has("from_segment"))
      t.fail(&t.required("joint"), "joint",
             "a device across one joint has no segment or from_segment (those place a tendon's anchors)");
    if (geometry.kinematics == Kinematics::beam)
      t.fail(&t.required("joint"), "joint", "a beam device joins the ground to the cap beam, across no joint");
  }
  return place;
}

// The device's law from the parameters given, each within its bounds.
DeviceLaw read_device_law(const TableReader& t, const std::string& kind, const LawInfo& law) {
  std::map<std::string, double, std::less<>> given;
  for (const LawParameter& p : law.parameters)
    if (t.has(p.key)) given[p.key] = t.number(p.key, [&p](double v) { return within(p, v); }, bounds_text(p));
  try {
    return make_law(kind, [&](std::string_view key) -> std::optional<double> {
      const auto v = given.find(key);
      return v == given.end() ? std::nullopt : std::optional<double>(v->second);
    });
  } catch (const InputError& e) {  // values each within bounds that the law refuses together
    t.fail(nullptr, "", e.what());
  }
}

// The devices a table makes from its `at`: a beam device's ground anchor x;
// "edges", one at each edge of the face (half-width B), NAME_left and
// NAME_right; or one at x, within the face.
std::vector<Device> placed_devices(const TableReader& t, const std::string& name, DeviceGeometry geometry,
                                   const DeviceLaw& law, double capacity, double B, const ColumnGroup* columns,
                                   int joint) {
  std::vector<Device> made;
  const toml::node& at = t.required("at");
  if (geometry.kinematics == Kinematics::beam) {
    geometry.x = t.number("at", [](double x) { return std::abs(x) <= max_length; },
                          fmt::format("the ground anchor's x [m] from the frame's centre line, in [{:g}, {:g}]",
                                      -max_length, max_length));
    if (!(std::hypot(geometry.beam_x - geometry.x, 2 * columns->half_height - geometry.ground_y) >= min_length))
      t.fail(t.has("ground_height") ? &t.required("ground_height") : &at, t.has("ground_height") ? "ground_height" : "at",
             fmt::format("the ground anchor meets the beam's at rest (they must be at least {:g} m apart)", min_length));
    made.push_back({name, geometry, law, capacity});
  } else if (at.is_string()) {
    if (t.string("at") != "edges") t.fail(&at, "at", "must be x [m] from the centre line, or \"edges\"");
    made.push_back({name + "_left", geometry, law, capacity});
    made.back().geometry.x = -B;
    made.push_back({name + "_right", geometry, law, capacity});
    made.back().geometry.x = B;
  } else {
    geometry.x = t.number("at", [B](double x) { return std::abs(x) <= B; },
                          columns != nullptr
                              ? fmt::format("on a column's base, from its axis: -b <= x <= b = {:g} [m]", B)
                              : joint > 0 ? fmt::format("on joint {}'s face, -B_{} <= x <= B_{} = {:g} [m]", joint, joint, joint, B)
                                          : fmt::format("on the base, -B <= x <= B = {:g} [m]", B));
    made.push_back({name, geometry, law, capacity});
  }
  return made;
}

std::vector<Device> read_devices(const toml::table& root, const std::string& file, const Origins& origins,
                                 const Structure& st, const ColumnGroup* columns, const Damper& damper,
                                 const std::vector<JointTable>& joint_tables, std::vector<int>& segments,
                                 std::vector<int>& from_segments, std::vector<int>& device_joints) {
  const std::size_t joints = joint_tables.size();
  std::vector<Device> out;
  const toml::array* list = root.get_as<toml::array>("device");
  if (list == nullptr) return out;
  const std::vector<LawInfo> laws = device_laws();
  std::set<std::string, std::less<>> names;
  if (damper.enabled)
    for (const Device& d : edge_dampers(damper, st.half_width)) names.insert(d.name);
  for (std::size_t i = 0; i < list->size(); ++i) {
    const std::string table_name = fmt::format("device[{}]", i);
    const toml::table* table = list->get_as<toml::table>(i);
    if (table == nullptr)
      throw InputError(fmt::format("{}: {}: must be a table", where(list->get(i)->source(), file), table_name));
    const TableReader t(table, table_name, file, origins);
    const std::string kind = t.string("kind");
    const auto law = std::ranges::find(laws, kind, &LawInfo::name);
    if (law == laws.end())
      t.fail(&t.required("kind"), "kind",
             fmt::format("unknown law '{}' (laws: {})", kind, fmt::join(laws | std::views::transform(&LawInfo::name), ", ")));
    check_device_keys(t, *table, kind, *law, columns != nullptr);
    const std::string name = device_name(t, kind, i);
    const DeviceGeometry geometry = device_geometry(t, columns);
    const double capacity = t.number_or("capacity", 0.0, positive, "positive [m] (leave it out: never breaks)");
    const DevicePlace place = device_place(t, joints, geometry);
    const DeviceLaw device_law = read_device_law(t, kind, *law);
    // The face it stands on: joint K's, or the base's.
    const double B = place.joint > 0 ? joint_tables[static_cast<std::size_t>(place.joint - 1)].half_width : st.half_width;
    std::vector<Device> made = placed_devices(t, name, geometry, device_law, capacity, B, columns, place.joint);
    if (damper.enabled && name == "damper")
      t.fail(t.has("name") ? &t.required("name") : nullptr, "name",
             "'damper' names the scene's [damper] (its two edge dampers): choose another name");
    for (Device& d : made) {
      segments.push_back(place.segment);
      from_segments.push_back(place.from_segment);
      device_joints.push_back(place.joint);
      d.group = name;
      if (!names.insert(d.name).second)
        t.fail(t.has("name") ? &t.required("name") : nullptr, "name", fmt::format("'{}' names two devices", d.name));
      out.push_back(std::move(d));
    }
  }
  // Each device's state is a slot of a fixed array (rocking.contact).
  const std::size_t edge = damper.enabled ? 2 : 0;
  if (out.size() + edge > static_cast<std::size_t>(max_device_states))
    throw InputError(fmt::format("{}: device: {} devices{}: a scene holds at most {}", file, out.size() + edge,
                                 edge > 0 ? " (with the damper's two)" : "", max_device_states));
  return out;
}

// [[joint]] tables (MODEL.md 15), from the ground up: node (1 .. N-1, above
// the previous joint's), half_width, base_mass, restitution ("momentum" or r),
// initial_theta, friction (a limit on |V| / N), rigid (the segment above).
std::vector<JointTable> read_joints(const toml::table& root, const std::string& file, const Origins& origins,
                                    const Structure& st, const Contact& contact) {
  std::vector<JointTable> out;
  const toml::array* list = root.get_as<toml::array>("joint");
  if (list == nullptr || list->empty()) return out;
  const std::size_t nodes = static_cast<std::size_t>(st.heights.size());
  const auto origin = [&](std::size_t i) {
    const auto set = origins.find(fmt::format("joint[{}]", i));
    return set != origins.end() ? set->second : where(list->get(i)->source(), file);
  };
  if (list->size() + 1 > nodes)
    throw InputError(fmt::format("{}: joint: {} joints for a structure of {} node{}: at most {} (one per node from 1 to "
                                 "N-1; the top node carries none)", origin(0), list->size(), nodes, nodes == 1 ? "" : "s",
                                 nodes - 1));
  const std::set<std::string, std::less<>> known = {"node", "half_width", "base_mass", "restitution",
                                                    "initial_theta", "friction", "rigid"};
  const std::string length_range = fmt::format("in [{:g}, {:g}] m", min_length, max_length);
  for (std::size_t i = 0; i < list->size(); ++i) {
    const std::string table_name = fmt::format("joint[{}]", i);
    const toml::table* table = list->get_as<toml::table>(i);
    if (table == nullptr) throw InputError(fmt::format("{}: {}: must be a table", origin(i), table_name));
    const TableReader t(table, table_name, file, origins);
    for (auto&& [key, value] : *table)
      if (!known.contains(key.str()))
        t.fail(&value, key.str(), fmt::format("unknown key for a joint (known: {})", fmt::join(known, ", ")));
    JointTable j;
    const double low = out.empty() ? 1.0 : out.back().node + 1.0, high = static_cast<double>(nodes - 1);
    const double node = t.number("node", [](double v) { return v == std::floor(v) && std::abs(v) <= 1e6; },
                                 "a node's number, an integer");
    if (!(node >= 1 && node <= high))
      t.fail(&t.required("node"), "node",
             fmt::format("must be a node of [structure] above the base and below the top, 1 to N-1 = {} (got {})",
                         nodes - 1, node));
    if (!(node >= low))
      t.fail(&t.required("node"), "node",
             fmt::format("joints go up the structure in order: above joint[{}] on node {}, so {} to {} (got {})", i - 1,
                         out.back().node, low, high, node));
    j.node = static_cast<int>(node);
    j.half_width = t.number("half_width", in_range(min_length, max_length, true), length_range);
    j.base_mass = t.number_or("base_mass", 0.0, in_range(0, max_mass, true),
                              fmt::format("non-negative and at most {:g} kg", max_mass));
    if (t.has("restitution")) {
      const toml::node& r = t.required("restitution");
      if (r.is_string()) {
        if (*r.value<std::string>() != "momentum")
          t.fail(&r, "restitution", fmt::format("must be \"momentum\" or a number in [0, 1] (got '{}')",
                                                *r.value<std::string>()));
      } else {
        j.restitution = t.number("restitution", [](double v) { return v >= 0 && v <= 1; },
                                 "\"momentum\" or a number in [0, 1]");
      }
    }
    j.initial_theta = t.number_or("initial_theta", 0.0, [](double v) { return std::abs(v) < 1.5707963; },
                                  "in (-pi/2, pi/2) [rad]");
    j.friction = t.number_or("friction", j.friction, [](double v) { return v > 0 && v <= 100; },
                             "a friction coefficient in (0, 100] (leave it out: not checked)");
    j.rigid = t.boolean_or("rigid", st.rigid);
    out.push_back(j);
  }
  return out;
}

// [excitation]: either record = "file" (+ units, dt, scale) or a pulse.
Excitation read_excitation(const toml::table& root, const std::string& file, const Origins& origins) {
  Excitation e;
  if (!root.contains("excitation")) return e;
  const TableReader t(root, "excitation", file, origins);
  e.duration = t.number_or("duration", 0.0, in_range(0, max_duration, false),
                           fmt::format("positive and at most {:g} [s]", max_duration));
  const std::string kind = t.string_or("kind", t.has("record") ? "record" : "pulse");
  if (kind != "none" && kind != "record" && kind != "pulse")
    t.fail(&t.required("kind"), "kind", fmt::format("must be pulse, record or none (got '{}')", kind));
  if (kind == "none") {  // the other keys may stay (--set excitation.kind=none on a scene with a pulse)
    if (!t.has("duration")) t.fail(nullptr, "duration", "kind = \"none\" needs the simulated time, duration [s]");
    e.none = true;
    return e;
  }
  if (kind == "record" && !t.has("record")) t.fail(nullptr, "record", "missing key (kind = \"record\")");
  // A factor on the record or the pulse; its product with the motion's peak
  // is checked where the motion is built (at most max_acceleration_g).
  const auto scale = [&t] {
    return t.number_or("scale", 1.0, [](double v) { return v != 0 && std::abs(v) <= max_scale_factor; },
                       fmt::format("non-zero and within +-{:g} (kind = \"none\" for no motion)", max_scale_factor));
  };
  if (t.has("record")) {
    e.record = t.string_or("record", "");
    const std::filesystem::path path(e.record);
    const bool embedded = file.starts_with("embedded:");
    if (path.is_relative() && !embedded)
      e.record = (std::filesystem::path(file).parent_path() / path).string();
    // A unit key, when given: g, m/s2, cm/s2 or mm/s2.
    const auto unit = [&t](const char* key) -> std::optional<AccelerationUnit> {
      if (!t.has(key)) return std::nullopt;
      const toml::node& u = t.required(key);
      try {
        return parse_acceleration_unit(t.string_or(key, ""));
      } catch (const InputError& err) {
        t.fail(&u, key, err.what());
      }
    };
    e.record_options.unit = unit("units");
    e.record_options.dt = t.number_or("dt", 0.0, positive, "positive [s]");
    e.record_options.scale = scale();
    e.record_options.component = t.string_or("component", "");
    if (t.has("vertical")) {
      e.vertical = t.string_or("vertical", "");
      if (e.vertical.empty()) t.fail(&t.required("vertical"), "vertical", "a record file or a component name, not empty");
      const std::filesystem::path vpath(e.vertical);
      const std::filesystem::path beside = std::filesystem::path(file).parent_path() / vpath;
      std::error_code ec;
      if (vpath.is_relative() && !embedded && std::filesystem::exists(beside, ec)) e.vertical = beside.string();
      e.vertical_options.component = t.string_or("vertical_component", "");
      e.vertical_options.unit = unit("vertical_units");
      e.vertical_options.dt = e.record_options.dt;
      e.vertical_options.scale = e.record_options.scale;
      e.vertical_options.read_as = ReadAs::vertical;
    } else {
      for (const char* key : {"vertical_component", "vertical_units"})
        if (t.has(key)) t.fail(&t.required(key), key, "describes the vertical record; vertical = ... names none");
    }
    return e;
  }
  for (const char* key : {"vertical", "vertical_component", "vertical_units", "component"})
    if (t.has(key)) t.fail(&t.required(key), key, "belongs to a record excitation (record = \"file\")");
  e.record_options.scale = scale();
  const toml::node& shape = t.required("pulse");
  try {
    e.pulse = parse_pulse_shape(t.string_or("pulse", ""));
  } catch (const InputError& err) {
    t.fail(&shape, "pulse", err.what());
  }
  e.amplitude = t.number("amplitude_g", [](double a) { return std::abs(a) <= max_acceleration_g; },
                         fmt::format("within +-{:g} [g]", max_acceleration_g)) *
                to_si(AccelerationUnit::g);
  // From a millisecond (1 kHz, beyond any ground motion and below the steps
  // a run can resolve) to a thousand seconds (longer than any earthquake).
  e.period = t.number("period", in_range(min_pulse_period, max_pulse_period, true),
                      fmt::format("in [{:g}, {:g}] [s]", min_pulse_period, max_pulse_period));
  return e;
}

// [initial]: a release from a tilt and initial velocities; u and u_dot have
// one entry per node.
Initial read_initial(const toml::table& root, const std::string& file, const Origins& origins, const Structure& s,
                     const Contact& c) {
  Initial init;
  if (!root.contains("initial")) return init;
  const TableReader t(root, "initial", file, origins);
  init.theta = t.number_or("theta", 0.0, [](double v) { return std::abs(v) < 1.5707963; }, "in (-pi/2, pi/2) [rad]");
  // Bounds from the structure: no point faster than max_initial_speed, no
  // elastic displacement beyond the height.
  const double H = s.heights.size() > 0 ? s.heights.maxCoeff() : 1.0;
  const double max_theta_dot = max_initial_speed / std::hypot(H, 2 * s.half_width);
  init.theta_dot = t.number_or("theta_dot", 0.0, [&](double v) { return std::abs(v) <= max_theta_dot; },
                               fmt::format("within +-{:.3g} [rad/s] (the structure's far corner at {:g} m/s)",
                                           max_theta_dot, max_initial_speed));
  if ((init.theta != 0 || init.theta_dot != 0) && !c.rocking)
    t.fail(&t.required(t.has("theta") ? "theta" : "theta_dot"), t.has("theta") ? "theta" : "theta_dot",
           "a fixed base (contact.rocking = false) cannot tilt");
  for (const char* key : {"u", "u_dot"}) {
    if (!t.has(key)) continue;
    const bool speed = std::string_view(key) == "u_dot";
    Eigen::VectorXd v = speed ? t.numbers(key, [](double x) { return std::abs(x) <= max_initial_speed; },
                                          fmt::format("within +-{:g} [m/s]", max_initial_speed))
                              : t.numbers(key, [H](double x) { return std::abs(x) <= H; },
                                          fmt::format("within +-{:g} [m] (the height)", H));
    if (s.rigid) {  // zeros say nothing (a flexible scene made rigid with --set)
      if (!v.isZero(0.0)) t.fail(&t.required(key), key, "a rigid block has no elastic displacements");
      continue;
    }
    if (v.size() != s.heights.size())
      t.fail(&t.required(key), key, fmt::format("must have one entry per node ({})", s.heights.size()));
    (std::string_view(key) == "u" ? init.u : init.u_dot) = std::move(v);
  }
  return init;
}

// [output]: the history's columns by name (rocking.quantities) and its row
// interval. A name must be a quantity of the schema, a device's or a node's
// or element's of this structure; whether the scene reports it is checked
// where the columns are made (report's history_columns), naming `origin`.
Output read_output(const toml::table& root, const std::string& file, const Origins& origins, const Structure& s) {
  Output out;
  if (!root.contains("output")) return out;
  const TableReader t(root, "output", file, origins);
  out.interval = t.number_or("interval", 0.0, [](double v) { return v >= 1e-6 && v <= 1e4; }, "in [1e-6, 1e4] [s]");
  if (!t.has("history")) return out;
  const toml::node& node = t.required("history");
  const toml::array* array = node.as_array();
  if (array == nullptr || array->empty())
    t.fail(&node, "history", "must be a non-empty array of quantity names (rocking simulate --list-quantities)");
  for (std::size_t i = 0; i < array->size(); ++i) {
    const std::string key = fmt::format("history[{}]", i);
    const toml::node& name = (*array)[i];
    if (!name.is_string()) t.fail(&name, key, "must be a quantity's name (a string)");
    const std::string text = *name.value<std::string>();
    const auto member = parse_member_quantity(text);
    if (!member && !parse_quantity_name(text))
      t.fail(&name, key, fmt::format("'{:.60}': unknown quantity (rocking simulate --list-quantities lists them)", text));
    if (member && (member->index < 1 || member->index > s.heights.size()))
      t.fail(&name, key, fmt::format("{}: this structure's nodes and elements are 1 to {}", text, s.heights.size()));
    out.history.push_back(text);
  }
  out.origin = t.origin(&node, "history");
  return out;
}

Scene read_scene(toml::table root, const std::string& file, const std::vector<std::string>& overrides) {
  Origins origins;
  for (const std::string& o : overrides) apply_override(root, o, origins);
  if (root.contains("columns") && root.contains("joint"))
    throw InputError(fmt::format("{}: [columns] with [[joint]]: a structure on rocking columns that also rocks at "
                                 "its own joints is not supported", file));
  check_known_keys(root, file);
  Scene scene;
  scene.source = file;
  scene.name = std::filesystem::path(file).stem().string();
  if (root.contains("scene")) {
    const TableReader meta(root, "scene", file, origins);
    scene.name = meta.string_or("name", scene.name);
    scene.description = meta.string_or("description", "");
  }
  scene.structure = read_structure(root, file, origins);
  scene.contact = read_contact(root, file, origins, scene);
  scene.columns = read_columns(root, file, origins);
  // The devices stand on the rocking base: the structure's, or each column's.
  const Structure base = device_base(scene);
  scene.damper = read_damper(root, file, origins, base);
  scene.joints = read_joints(root, file, origins, scene.structure, scene.contact);
  scene.devices = read_devices(root, file, origins, base, scene.columns ? &*scene.columns : nullptr, scene.damper,
                               scene.joints, scene.device_segments, scene.device_from_segments, scene.device_joints);
  scene.excitation = read_excitation(root, file, origins);
  scene.initial = read_initial(root, file, origins, scene.structure, scene.contact);
  scene.output = read_output(root, file, origins, scene.structure);
  if (std::isfinite(scene.base_friction) && !scene.jointed() && scene.contact.rocking)
    throw InputError(fmt::format("{}: contact.friction: the friction demand is checked for a structure with joints "
                                 "([[joint]] tables or contact.restitution = \"momentum\")", file));
  if (scene.jointed()) (void)jointed_model(scene);  // what the chain cannot model is refused here, before any run
  if (scene.structure.rigid && !scene.contact.rocking && scene.joints.empty())
    throw InputError(fmt::format("{}: structure.rigid = true with contact.rocking = false: a rigid "
                                 "block on a fixed base has no motion to compute", file));
  return scene;
}

std::string parse_error_line(const toml::parse_error& e, const std::string& file) {
  return fmt::format("{}: invalid TOML: {}", where(e.source(), file), e.description());
}

}  // namespace

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(fmt::format("{}: is a folder, not a scene file", path));
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError(fmt::format("{}: scene file not found", path));
  try {
    return read_scene(toml::parse_file(path), path, overrides);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_line(e, path));
  }
}

Scene load_default_scene(const std::vector<std::string>& overrides) {
  const std::string name = "embedded:christchurch_chimney.toml";
  try {
    return read_scene(toml::parse(default_scene_text(), name), name, overrides);
  } catch (const toml::parse_error& e) {
    throw InputError(parse_error_line(e, name));
  }
}

std::string scene_toml(const std::string& path, const std::vector<std::string>& overrides) {
  const Scene checked = path.empty() ? load_default_scene(overrides) : load_scene(path, overrides);
  const std::string& name = checked.source;
  toml::table root = path.empty() ? toml::parse(default_scene_text(), name) : toml::parse_file(path);
  Origins origins;
  for (const std::string& o : overrides) apply_override(root, o, origins);
  std::ostringstream out;
  out << "# " << name << (overrides.empty() ? "" : fmt::format(" with {}", fmt::join(overrides, ", "))) << "\n"
      << toml::toml_formatter(root) << "\n";
  return out.str();
}

namespace {

// On a structure with joints, scene device k is one of the chain's tendons
// (MODEL.md 15: from the ground to a segment) when it is elastic and
// vertical; any other device stands across the base joint.
// The joint device k stands across when it is not a tendon ([[device]] joint;
// -1: not given).
int device_joint(const Scene& scene, std::size_t k) {
  return k < scene.device_joints.size() ? scene.device_joints[k] : -1;
}

// An elastic, vertical device named across no joint is a tendon through the
// chain (from the ground or its from_segment to its segment).
bool is_tendon(const Scene& scene, std::size_t k) {
  const Device& d = scene.devices[k];
  return std::string_view(law_name(d.law)) == "elastic" && d.geometry.kinematics == Kinematics::vertical &&
         device_joint(scene, k) < 0;
}

}  // namespace

std::vector<Device> scene_devices(const Scene& scene) {
  std::vector<Device> all;
  if (scene.damper.enabled) all = edge_dampers(scene.damper, device_base(scene).half_width);
  all.insert(all.end(), scene.devices.begin(), scene.devices.end());
  return all;
}

std::vector<DeviceGroup> device_groups(const Scene& scene) {
  std::vector<DeviceGroup> out;
  std::size_t tables = 0;
  for (const Device& d : scene_devices(scene)) {
    const std::string& name = d.group.empty() ? d.name : d.group;
    if (out.empty() || out.back().name != name) {
      DeviceGroup g{name, {}, law_name(d.law), law_dissipates(d.law), law_prestress_key(d.law)};
      if (g.prestress_key != nullptr) g.prestress = law_force_at_rest(d.law, 0.0);
      if (!d.edge_damper) g.table = tables++;
      g.removal = "device-=" + name;
      out.push_back(std::move(g));
    }
    out.back().devices.push_back(d);
  }
  return out;
}

JointedModel jointed_model(const Scene& scene) {
  const std::string& file = scene.source;
  const Structure& st = scene.structure;
  if (!scene.momentum_base && scene.contact.restitution_rule == RestitutionRule::eq9)
    throw InputError(fmt::format("{}: contact.restitution = eq9: not modelled on a structure with joints (\"momentum\", "
                                 "eq10 or a number)", file));
  if (scene.initial.u.size() > 0 || scene.initial.u_dot.size() > 0)
    throw InputError(fmt::format("{}: initial.u, initial.u_dot: a structure with joints starts with its elastic "
                                 "displacements and velocities at zero", file));
  std::vector<ChainJointSpec> specs;
  for (const JointTable& j : scene.joints) specs.push_back({j.node, j.half_width, j.base_mass, j.rigid});
  ChainData data = split_structure(st, specs);
  data.base_held = !scene.contact.rocking;
  const int top = static_cast<int>(data.segments.size()) - 1;
  JointedModel out;
  out.base_devices = scene.damper.enabled ? 2 : 0;  // the [damper]'s pair stands at the base's edges
  // The devices across each joint above the base, by joint (their places
  // after the base's, joint by joint, in the scene's order).
  std::vector<std::vector<Device>> upper(data.segments.size());
  for (std::size_t k = 0; k < scene.devices.size(); ++k) {
    const Device& d = scene.devices[k];
    if (!is_tendon(scene, k)) {
      if (scene.device_segments[k] >= 0 || scene.device_from_segments[k] >= 0)
        throw InputError(fmt::format("{}: device '{}': segment: a device anchored on a segment is a tendon from the "
                                     "ground (kind = \"elastic\", kinematics = \"vertical\"); other devices stand "
                                     "across one joint (joint = 0 .. {}, the base by default)", file, d.name, top));
      const int j = std::max(0, device_joint(scene, k));
      if (j == 0)
        ++out.base_devices;
      else
        upper[static_cast<std::size_t>(j)].push_back(d);
      continue;
    }
    if (d.capacity > 0)
      throw InputError(fmt::format("{}: device '{}': capacity: a tendon through the joints does not break in this "
                                   "model (leave capacity out)", file, d.name));
    const int seg = scene.device_segments[k] < 0 ? top : scene.device_segments[k];
    const ChainSegment& sg = data.segments[static_cast<std::size_t>(seg)];
    // From the ground (or the base of its from_segment) at x to the top of its
    // segment, at the same x; e from the rest distance. It crosses the joints
    // between the two.
    const double z_top = sg.heights[sg.heights.size() - 1] - sg.base_height;
    data.tendons.push_back({.from = {.segment = scene.device_from_segments[k], .x = d.geometry.x, .z = 0.0},
                            .to = {.segment = seg, .x = d.geometry.x, .z = z_top},
                            .prestress = law_force_at_rest(d.law, 0.0),
                            .stiffness = law_stiffness(d.law),
                            .free_length = 0.0});
    out.tendons.push_back(d.name);
  }
  try {
    out.chain = make_chain(data);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: joint: {}", file, e.what()));
  }
  // Each joint's devices held as a rigid block on a base of half-width B_j
  // holds them (rocking.contact): everything above the joint as one rigid
  // body there (its mass at its centre of mass, which the acting lists,
  // levers and state slots do not read).
  std::size_t next = out.base_devices;
  for (std::size_t j = 1; j < upper.size(); ++j) {
    if (upper[j].empty()) continue;
    double m = 0, mz = 0;
    for (std::size_t k = j; k < data.segments.size(); ++k) {
      const ChainSegment& sg = data.segments[k];
      m += sg.base_mass + sg.masses.sum();
      mz += sg.base_mass * sg.base_height + sg.masses.dot(sg.heights);
    }
    Structure block;
    block.rigid = true;
    block.half_width = data.segments[j].half_width;
    block.heights = Eigen::VectorXd::Constant(1, std::max(mz / m - data.segments[j].base_height, 1e-3));
    block.masses = Eigen::VectorXd::Constant(1, m);
    block.base_mass = 0;
    Contact rocking = scene.contact;
    rocking.rocking = true;
    JointedModel::UpperDevices u;
    u.joint = static_cast<int>(j);
    for (std::size_t k = 0; k < upper[j].size(); ++k) u.devices.push_back(next++);
    u.block = std::make_shared<const ContactModel>(make_contact_model(block, rocking, upper[j], false));
    out.upper.push_back(std::move(u));
  }
  // Eq. 10 of the whole structure on its base, for restitution = "eq10".
  const double r_eq10 = make_contact_model(st, scene.contact, {}, false).r_eq10;
  out.restitution.push_back(scene.momentum_base ? -1.0
                            : scene.contact.restitution_rule == RestitutionRule::constant ? scene.contact.restitution
                                                                                           : r_eq10);
  out.initial_theta.push_back(scene.initial.theta);
  out.friction_limit.push_back(scene.base_friction);
  for (const JointTable& j : scene.joints) {
    out.restitution.push_back(j.restitution);
    out.initial_theta.push_back(j.initial_theta);
    out.friction_limit.push_back(j.friction);
  }
  // Each joint's overturning angle: the slenderness about its corner of
  // everything above it, atan(B_j / (H_cg,j - h_j)) (MODEL.md 15's threshold);
  // the base's is contact.overturn_angle when given.
  for (int j = 0; j <= top; ++j) {
    double m = 0, mz = 0;
    for (int k = j; k <= top; ++k) {
      const ChainSegment& sg = data.segments[static_cast<std::size_t>(k)];
      m += sg.base_mass;
      mz += sg.base_mass * sg.base_height;
      m += sg.masses.sum();
      mz += sg.masses.dot(sg.heights);
    }
    const ChainSegment& sg = data.segments[static_cast<std::size_t>(j)];
    out.overturn_angle.push_back(j == 0 && scene.contact.overturn_angle > 0
                                     ? scene.contact.overturn_angle
                                     : std::atan(sg.half_width / (mz / m - sg.base_height)));
  }
  out.theta_dot_min = scene.contact.theta_dot_min;
  return out;
}

namespace {

// The devices (their acting lists, fracture guards and state slots) as a
// rigid block on `block`'s base holds them (rocking.contact), into m: the
// columns' run and the chain's base joint keep the states in a rigid block's
// slots, from 2 after theta and theta'.
void devices_as_on_block(ContactModel& m, const Structure& block, const Contact& contact, std::vector<Device> devices) {
  Contact rocking = contact;
  rocking.rocking = true;
  ContactModel on = make_contact_model(block, rocking, std::move(devices), false);
  m.devices = std::move(on.devices);
  m.acting = std::move(on.acting);
  m.breakable = std::move(on.breakable);
  m.damper = on.damper;
  m.idle_slots = on.idle_slots;
  m.has_damper = on.has_damper;
}

// A scene on [columns] (MODEL.md 16): the structure on the cap beam as on a
// fixed base (its outputs), carrying the columns' frame and impact rule. Its
// devices (devices, acting, breakable, damper, idle_slots) are those of one
// column as a rigid block (device_base): each device stands at the base of
// every column alike, its lever arms taken about the column's corners (b), and
// its state slots counted as a rigid block's, from 2 after theta and theta'
// (the columns' run keeps its state in that order).
ContactModel columns_contact_model(const Scene& scene, bool track_energy, std::vector<Device> extra) {
  const std::string& file = scene.source;
  std::vector<Device> devices = scene_devices(scene);
  for (Device& d : extra) devices.push_back(std::move(d));
  if (scene.contact.restitution_rule == RestitutionRule::eq9 && !scene.momentum_base)
    throw InputError(fmt::format("{}: contact.restitution = eq9: not modelled for rocking columns (\"momentum\", "
                                 "eq10, the same law here, or a number)", file));
  auto on = std::make_shared<ColumnsModel>();
  try {
    on->columns = make_columns(*scene.columns, scene.structure);
  } catch (const std::invalid_argument& e) {
    throw InputError(fmt::format("{}: {}", file, e.what()));
  }
  on->restitution = !scene.momentum_base && scene.contact.restitution_rule == RestitutionRule::constant
                        ? scene.contact.restitution
                        : -1.0;
  on->theta_dot_min = scene.contact.theta_dot_min;
  on->rocking = scene.contact.rocking;
  on->overturn_angle = scene.contact.overturn_angle > 0 ? scene.contact.overturn_angle : on->columns.alpha;
  Contact fixed = scene.contact;
  fixed.rocking = false;
  ContactModel m = make_contact_model(scene.structure, fixed, {}, track_energy);
  if (!devices.empty()) {
    // The column devices as one column's (their acting entries renumbered to
    // the scene's order); the beam devices after them, each with its state slot.
    std::vector<Device> at_columns;
    std::vector<int> column_index;
    for (std::size_t k = 0; k < devices.size(); ++k)
      if (devices[k].geometry.kinematics != Kinematics::beam) {
        at_columns.push_back(devices[k]);
        column_index.push_back(static_cast<int>(k));
      }
    devices_as_on_block(m, device_base(scene), scene.contact, std::move(at_columns));
    Eigen::Index next_slot = 2;
    for (auto& acting : m.acting)
      for (ContactModel::Acting& a : acting) {
        a.device = column_index[static_cast<std::size_t>(a.device)];
        if (a.slot) next_slot = std::max(next_slot, *a.slot + 1);
      }
    const Columns& c = on->columns;
    for (std::size_t k = 0; k < devices.size(); ++k) {
      const DeviceGeometry& g = devices[k].geometry;
      if (g.kinematics != Kinematics::beam) continue;
      ColumnsModel::BeamDevice d{.device = static_cast<int>(k),
                                 .slot = law_states(devices[k].law) > 0 ? std::optional<Eigen::Index>(next_slot++)
                                                                        : std::nullopt,
                                 .ground_x = g.x,
                                 .ground_y = g.ground_y,
                                 .beam_x = g.beam_x};
      for (Pivot p : pivots)
        d.lever[index(p)] =
            beam_device_stretch(c, g.x, g.ground_y, g.beam_x, 2 * c.group.half_height, 0.0, p, Tilt(0.0)).de_dtheta;
      on->beam_devices.push_back(d);
    }
    m.devices = std::move(devices);
  }
  m.on_columns = std::move(on);
  return m;
}

// A structure with joints (MODEL.md 15): the structure as one piece on its
// base (its outputs), carrying the chain. Its devices are those across the
// base joint, held as a rigid block on the same base holds them
// (devices_as_on_block: the chain's run keeps their states from 2), `extra`
// with them, then those across each joint above (JointedModel::upper), then the
// chain's tendons (JointedModel::base_devices and upper tell them apart).
ContactModel jointed_contact_model(const Scene& scene, bool track_energy, std::vector<Device> extra) {
  JointedModel jointed = jointed_model(scene);
  jointed.base_devices += extra.size();
  for (JointedModel::UpperDevices& u : jointed.upper)
    for (std::size_t& k : u.devices) k += extra.size();
  std::vector<Device> base, tendons;
  std::vector<std::vector<Device>> upper(jointed.chain.data.segments.size());
  if (scene.damper.enabled) base = edge_dampers(scene.damper, scene.structure.half_width);
  for (std::size_t k = 0; k < scene.devices.size(); ++k) {
    const int j = std::max(0, device_joint(scene, k));
    (is_tendon(scene, k) ? tendons : j == 0 ? base : upper[static_cast<std::size_t>(j)]).push_back(scene.devices[k]);
  }
  for (Device& d : extra) base.push_back(std::move(d));  // added devices stand at the base
  Contact contact = scene.contact;
  contact.rocking = true;  // the structure's own model: a fixed base's is the chain's with its base joint held
  ContactModel m = make_contact_model(scene.structure, contact, {}, track_energy);
  if (!base.empty()) {
    const Structure& st = scene.structure;
    Structure block;  // the whole structure as a rigid block on the same base
    block.rigid = true;
    block.half_width = st.half_width;
    const double mass = st.masses.sum() + st.base_mass;
    block.heights = Eigen::VectorXd::Constant(1, std::max(st.masses.dot(st.heights) / mass, 1e-3));
    block.masses = Eigen::VectorXd::Constant(1, mass);
    block.base_mass = 0;
    devices_as_on_block(m, block, scene.contact, std::move(base));
  }
  for (std::vector<Device>& at : upper)
    for (Device& d : at) m.devices.push_back(std::move(d));
  for (Device& d : tendons) m.devices.push_back(std::move(d));
  m.jointed = std::make_shared<const JointedModel>(std::move(jointed));
  return m;
}

}  // namespace

ContactModel make_contact_model(const Scene& scene, bool track_energy, std::vector<Device> extra) {
  if (scene.columns) return columns_contact_model(scene, track_energy, std::move(extra));
  if (scene.jointed()) return jointed_contact_model(scene, track_energy, std::move(extra));
  std::vector<Device> devices = scene_devices(scene);
  for (Device& d : extra) devices.push_back(std::move(d));
  return make_contact_model(scene.structure, scene.contact, std::move(devices), track_energy);
}

double excitation_scale(const Scene& scene) { return scene.excitation.none ? 1.0 : scene.excitation.record_options.scale; }

GroundMotion default_ground_motion(const Scene& scene) {
  const Excitation& e = scene.excitation;
  if (e.none) return GroundMotion::from_samples("no ground motion", {0.0, e.duration}, {0.0, 0.0});
  if (!e.record.empty()) {
    const GroundMotion horizontal = read_record(e.record, e.record_options);
    if (e.vertical.empty()) return horizontal;
    std::error_code ec;
    if (std::filesystem::exists(e.vertical, ec)) return horizontal.with_vertical(read_record(e.vertical, e.vertical_options));
    RecordOptions both = e.record_options;  // a component of the record's own file
    both.vertical_component = e.vertical;
    return read_record(e.record, both);
  }
  if (e.period > 0) return GroundMotion::pulse(e.pulse, e.amplitude, e.period).scaled(e.record_options.scale);
  throw InputError(fmt::format("{}: the scene has no [excitation]; give a record with --record FILE", scene.source));
}

}  // namespace rocking
