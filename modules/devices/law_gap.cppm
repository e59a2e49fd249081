// The gap law: a spring that engages after a slack g0, F = k max(0, e - g0)
// (a restrainer cable with slack, a bumper or a hold-down with play). No
// internal state; it stores k max(0, e - g0)^2 / 2, holds nothing at rest
// and dissipates nothing. At rest (e = 0) its slope is k when there is no
// slack and 0 otherwise; once engaged, k.
module;
#include <algorithm>
#include <vector>
export module rocking.devices:gap;
import :parameters;

export namespace rocking {

struct GapLaw {
  static constexpr const char* name = "gap";
  static constexpr const char* summary = "F = k max(0, e - g0): a spring engaging after a slack g0";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = false;
  static constexpr const char* prestress_key = nullptr;
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"k", "N/m", "stiffness once engaged", R::stiffness, 5e6, 0, 0, true, 1e13},
            {"g0", "m", "slack: the elongation at which it engages", R::onset_elongation, 0.005, 0, 0, false, 10}};
  }
  static GapLaw make(const std::vector<double>& v) { return {v[0], v[1]}; }

  double k = 0, g0 = 0;
  static constexpr int states = 0;
  double force(double e, double /*e_dot*/, double /*z*/) const { return k * std::max(0.0, e - g0); }
  double rate(double, double, double) const { return 0; }
  double stored_energy(double e, double /*z*/) const {
    const double s = std::max(0.0, e - g0);
    return 0.5 * k * s * s;
  }
  double force_at_rest(double /*z*/) const { return 0; }
  double stiffness() const { return g0 > 0 ? 0.0 : k; }
  double yielded_stiffness() const { return k; }
};

}  // namespace rocking
