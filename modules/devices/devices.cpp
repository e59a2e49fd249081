module;
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>
#include <fmt/format.h>
module rocking.devices;
import rocking.errors;
import rocking.hysteresis;

namespace rocking {

namespace {

template <class Law>
LawInfo info_of() {
  return {Law::name, Law::summary, Law::parameters()};
}

template <class Law>
DeviceLaw make_one(const std::function<std::optional<double>(std::string_view)>& value) {
  std::vector<double> values;
  for (const LawParameter& p : Law::parameters()) {
    const double v = value(p.key).value_or(p.default_value);
    if (!within(p, v))
      throw InputError(fmt::format("{} law: {} = {}: must be {}", Law::name, p.key, v, bounds_text(p)));
    values.push_back(v);
  }
  if constexpr (requires { Law::problem(values); })
    if (const LawProblem why = Law::problem(values); !why.key.empty())
      throw InputError(fmt::format("{} law: {}: {}", Law::name, why.key, why.why));
  return Law::make(values);
}

template <std::size_t... I>
std::vector<LawInfo> all_infos(std::index_sequence<I...>) {
  return {info_of<std::variant_alternative_t<I, DeviceLaw>>()...};
}

template <std::size_t I = 0>
std::optional<DeviceLaw> make_named(std::string_view name,
                                    const std::function<std::optional<double>(std::string_view)>& value) {
  if constexpr (I == std::variant_size_v<DeviceLaw>) {
    return std::nullopt;
  } else {
    using Law = std::variant_alternative_t<I, DeviceLaw>;
    if (name == Law::name) return make_one<Law>(value);
    return make_named<I + 1>(name, value);
  }
}

}  // namespace

std::vector<Device> edge_dampers(const Damper& damper, double half_width) {
  BoucWenLaw law;
  law.damper = damper;
  law.damper.stiffness = plate_stiffness(damper);
  law.d_y = yield_displacement(damper, half_width);
  return {Device{"damper_left", {-half_width, Kinematics::chord, 0}, law, damper.capacity, true, "damper"},
          Device{"damper_right", {half_width, Kinematics::chord, 0}, law, damper.capacity, true, "damper"}};
}

RockingStiffness rocking_stiffness(const std::vector<Device>& devices, double half_width, Pivot p) {
  RockingStiffness out;
  for (const Device& d : devices) {
    const double l = lever_arm(d.geometry, half_width, p);
    if (!(l > 0)) continue;
    const double slope = stretch(d.geometry, half_width, p, Tilt(0.0)).de_dtheta;
    out.at_rest += law_stiffness(d.law) * slope * slope;
    out.yielded += law_yielded_stiffness(d.law) * slope * slope;
    out.held_moment += law_force_at_rest(d.law, 0.0) * l;
    out.any = true;
  }
  return out;
}

bool within(const LawParameter& p, double v) {
  return std::isfinite(v) && (p.minimum_exclusive ? v > p.minimum : v >= p.minimum) && v <= p.maximum;
}

std::string bounds_text(const LawParameter& p) {
  return fmt::format("{} {:g} and <= {:g} [{}]", p.minimum_exclusive ? ">" : ">=", p.minimum, p.maximum, p.unit);
}

std::vector<LawInfo> device_laws() { return all_infos(std::make_index_sequence<std::variant_size_v<DeviceLaw>>()); }

DeviceLaw make_law(std::string_view name, const std::function<std::optional<double>(std::string_view)>& value) {
  if (auto law = make_named(name, value)) return *law;
  std::string names;
  for (const LawInfo& l : device_laws()) names += (names.empty() ? "" : ", ") + l.name;
  throw InputError(fmt::format("device law '{}': unknown (laws: {})", name, names));
}

}  // namespace rocking
