module;
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <fmt/format.h>
module rocking.quantities;

namespace rocking {

std::optional<Quantity> find_quantity(std::string_view name) {
  for (const QuantityInfo& q : quantity_table)
    if (q.name == name) return q.id;
  return std::nullopt;
}

std::string quantity_names(Role role) {
  std::string names;
  for (const QuantityInfo& q : quantity_table)
    if (q.is(role)) names += fmt::format("{}{}", names.empty() ? "" : ", ", q.name);
  return names;
}

std::string device_quantity_name(std::string_view device, DeviceQuantity q) {
  return fmt::format("{}.{}", device, info(q).name);
}

std::string QuantityName::name() const {
  return scalar ? std::string(info(*scalar).name) : joint ? joint->name() : device_quantity_name(device, of);
}

std::string_view QuantityName::unit() const {
  return scalar ? info(*scalar).unit : joint ? info(joint->which).unit : info(of).unit;
}

std::string_view axis_words(std::string_view words) {
  const std::size_t note = words.find(" (");
  return note == std::string_view::npos ? words : words.substr(0, note);
}

std::string axis_label(const QuantityName& q) {
  if (q.scalar) {
    const QuantityInfo& i = info(*q.scalar);
    return fmt::format("{} {} [{}]", axis_words(i.words), i.symbol, i.figure_unit);
  }
  if (q.joint) {
    const JointQuantityInfo& i = info(q.joint->which);
    return fmt::format("joint {}: {} {}_{} [{}]", q.joint->joint, axis_words(i.words), i.symbol, q.joint->joint,
                       i.figure_unit);
  }
  const DeviceQuantityInfo& i = info(q.of);
  return fmt::format("{} {} {} [{}]", q.device, axis_words(i.words), i.symbol, i.figure_unit);
}

namespace {
// A field of the schema entry a name stands for: a scalar quantity's, a
// joint quantity's or a device quantity's.
template <class Field>
auto entry_of(const QuantityName& q, Field field) {
  return q.scalar ? field(info(*q.scalar)) : q.joint ? field(info(q.joint->which)) : field(info(q.of));
}
}  // namespace

double figure_factor(const QuantityName& q) {
  return entry_of(q, [](const auto& i) { return i.figure_factor; });
}

std::string plain_text(std::string_view enhanced) {
  // gnuplot's Symbol font: the Latin letter that stands for each Greek one.
  static constexpr std::string_view latin = "abcdefghiklmnopqrstuwxyzDFGLPQSW";
  static constexpr std::string_view greek[] = {"α", "β", "χ", "δ", "ε", "φ", "γ", "η", "ι", "κ", "λ", "μ", "ν",
                                               "ο", "π", "θ", "ρ", "σ", "τ", "υ", "ω", "ξ", "ψ", "ζ", "Δ", "Φ",
                                               "Γ", "Λ", "Π", "Θ", "Σ", "Ω"};
  static_assert(std::size(greek) == latin.size());
  static constexpr std::string_view symbol = "{/Symbol ";
  std::string out;
  for (std::size_t i = 0; i < enhanced.size();) {
    if (enhanced.substr(i).starts_with(symbol)) {
      const std::size_t close = enhanced.find('}', i);
      const std::string_view letters =
          enhanced.substr(i + symbol.size(), close == std::string_view::npos ? std::string_view::npos : close - i - symbol.size());
      for (char c : letters) {
        const std::size_t k = latin.find(c);
        if (k == std::string_view::npos) out += c;
        else out += greek[k];
      }
      i = close == std::string_view::npos ? enhanced.size() : close + 1;
      continue;
    }
    if (enhanced[i] != '{' && enhanced[i] != '}') out += enhanced[i];
    ++i;
  }
  return out;
}

std::string plain_symbol(const QuantityName& q) {
  if (q.scalar) return plain_text(info(*q.scalar).symbol);
  if (q.joint) return fmt::format("{}_{}", plain_text(info(q.joint->which).symbol), q.joint->joint);
  return fmt::format("{} {}", q.device, plain_text(info(q.of).symbol));
}

std::string_view plain_words(const QuantityName& q) {
  return axis_words(entry_of(q, [](const auto& i) { return i.words; }));
}

std::string_view figure_unit(const QuantityName& q) {
  return entry_of(q, [](const auto& i) { return i.figure_unit; });
}

LabUse lab_use(const QuantityName& q) {
  return entry_of(q, [](const auto& i) { return i.lab; });
}

std::optional<QuantityName> parse_quantity_name(std::string_view text) {
  if (const auto q = find_quantity(text)) return QuantityName(*q);
  if (const auto j = parse_joint_quantity(text)) return QuantityName(*j);
  const auto dot = text.rfind('.');
  if (dot == std::string_view::npos || dot == 0) return std::nullopt;
  const std::string_view what = text.substr(dot + 1);
  for (const DeviceQuantityInfo& d : device_quantity_table)
    if (d.name == what) return QuantityName(std::string(text.substr(0, dot)), d.id);
  return std::nullopt;
}

const MemberQuantityInfo& MemberQuantityName::info() const {
  return of == Of::node ? rocking::info(node_quantity()) : rocking::info(element_quantity());
}

std::string MemberQuantityName::name() const {
  return fmt::format("{}{}.{}", of == Of::node ? "node" : "element", index, info().name);
}

std::optional<MemberQuantityName> parse_member_quantity(std::string_view text) {
  MemberQuantityName q;
  std::string_view rest;
  for (const auto& [word, of] : {std::pair{std::string_view("node"), MemberQuantityName::Of::node},
                                 std::pair{std::string_view("element"), MemberQuantityName::Of::element}})
    if (text.starts_with(word)) {
      q.of = of;
      rest = text.substr(word.size());
    }
  const auto dot = rest.find('.');
  if (rest.empty() || dot == 0 || dot == std::string_view::npos || dot > 4 || (rest[0] == '0' && dot > 1)) return std::nullopt;
  int index = 0;
  for (char c : rest.substr(0, dot)) {
    if (c < '0' || c > '9') return std::nullopt;
    index = 10 * index + (c - '0');
  }
  if (index > 1000) return std::nullopt;
  q.index = index;
  const std::string_view what = rest.substr(dot + 1);
  const auto find = [&](const auto& table) -> bool {
    for (std::size_t k = 0; k < table.size(); ++k)
      if (table[k].name == what) {
        q.which = static_cast<unsigned char>(k);
        return true;
      }
    return false;
  };
  if (!(q.of == MemberQuantityName::Of::node ? find(node_quantity_table) : find(element_quantity_table)))
    return std::nullopt;
  return q;
}

std::string JointQuantityName::name() const { return fmt::format("joint{}.{}", joint, info(which).name); }

std::optional<JointQuantityName> parse_joint_quantity(std::string_view text) {
  if (!text.starts_with("joint")) return std::nullopt;
  const std::string_view rest = text.substr(5);
  const auto dot = rest.find('.');
  if (rest.empty() || dot == 0 || dot == std::string_view::npos || dot > 4 || rest[0] == '0') return std::nullopt;
  int joint = 0;
  for (char c : rest.substr(0, dot)) {
    if (c < '0' || c > '9') return std::nullopt;
    joint = 10 * joint + (c - '0');
  }
  if (joint > 1000) return std::nullopt;
  const std::string_view what = rest.substr(dot + 1);
  for (std::size_t k = 0; k < joint_quantity_table.size(); ++k)
    if (joint_quantity_table[k].name == what) return JointQuantityName{joint, static_cast<JointQuantity>(k)};
  return std::nullopt;
}

std::string_view value_label(Quantity q, double v) {
  if (q != Quantity::phase) return {};
  return v == 0 ? "contact" : v > 0 ? "rock+" : "rock-";
}

std::string column_header(std::string_view name, std::string_view unit) {
  return unit.empty() ? std::string(name) : fmt::format("{} [{}]", name, unit);
}

}  // namespace rocking
