// The elastic law (MODEL.md 11): F = P0 + k e, tension only (F >= 0); a
// post-tensioned unbonded tendon of prestress P0 and axial stiffness k, or an
// elastic spring. No internal state. It stores P0 e + k e^2 / 2.
module;
#include <algorithm>
#include <vector>
export module rocking.devices:elastic;
import :parameters;

export namespace rocking {

struct ElasticLaw {
  static constexpr const char* name = "elastic";
  static constexpr const char* summary = "F = P0 + k e, tension only: a post-tensioned tendon or a spring";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = false;
  static constexpr const char* prestress_key = "P0";
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"P0", "N", "prestress: the force at zero elongation", R::force, 5e4, 0, 0, false, 1e10},
            {"k", "N/m", "stiffness (a tendon: E A / free length)", R::stiffness, 3e6, 0, 0, false, 1e13}};
  }
  static ElasticLaw make(const std::vector<double>& v) { return {v[0], v[1]}; }

  double P0 = 0, k = 0;
  static constexpr int states = 0;
  double force(double e, double /*e_dot*/, double /*z*/) const { return std::max(0.0, P0 + k * e); }
  double rate(double, double, double) const { return 0; }
  double stored_energy(double e, double /*z*/) const { return P0 * e + 0.5 * k * e * e; }
  double force_at_rest(double /*z*/) const { return P0; }
  double stiffness() const { return k; }
  double yielded_stiffness() const { return k; }
};

}  // namespace rocking
