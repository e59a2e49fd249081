module;
#include <optional>
#include <string>
#include <string_view>
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
  return scalar ? std::string(info(*scalar).name) : device_quantity_name(device, of);
}

std::string_view QuantityName::unit() const { return scalar ? info(*scalar).unit : info(of).unit; }

std::string axis_label(const QuantityName& q) {
  if (q.scalar) {
    const QuantityInfo& i = info(*q.scalar);
    return fmt::format("{} {} [{}]", i.words, i.symbol, i.figure_unit);
  }
  const DeviceQuantityInfo& i = info(q.of);
  return fmt::format("{} {} {} [{}]", q.device, i.words, i.symbol, i.figure_unit);
}

double figure_factor(const QuantityName& q) { return q.scalar ? info(*q.scalar).figure_factor : info(q.of).figure_factor; }

std::optional<QuantityName> parse_quantity_name(std::string_view text) {
  if (const auto q = find_quantity(text)) return QuantityName(*q);
  const auto dot = text.rfind('.');
  if (dot == std::string_view::npos || dot == 0) return std::nullopt;
  const std::string_view what = text.substr(dot + 1);
  for (const DeviceQuantityInfo& d : device_quantity_table)
    if (d.name == what) return QuantityName(std::string(text.substr(0, dot)), d.id);
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
