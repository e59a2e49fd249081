// The friction law: a slotted-bolted or rotational friction damper, Coulomb
// friction of slip force F_s regularised over a reference velocity v_r so
// that the force is a smooth function of the elongation rate,
//   F = F_s tanh(e' / v_r)
// (|e'| >> v_r: F = F_s sign(e'), rigid-plastic; v_r -> 0 is exact Coulomb
// friction). No internal state; it stores nothing, holds nothing at rest and
// dissipates F_s per unit of slip once sliding.
module;
#include <cmath>
#include <vector>
export module rocking.devices:friction;
import :parameters;

export namespace rocking {

struct FrictionLaw {
  static constexpr const char* name = "friction";
  static constexpr const char* summary = "F = F_s tanh(e'/v_r): a friction damper slipping at F_s";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = true;
  static constexpr const char* prestress_key = nullptr;
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"F_s", "N", "slip force", R::force, 8e4, 0, 0, false, 1e10},
            {"v_r", "m/s", "regularising velocity: the force reaches 76 % of F_s at e' = v_r", R::reference_rate, 0.004,
             1e-3, 0, true, 10}};
  }
  static FrictionLaw make(const std::vector<double>& v) { return {v[0], v[1]}; }

  double F_s = 0, v_r = 1e-3;
  static constexpr int states = 0;
  double force(double /*e*/, double e_dot, double /*z*/) const { return F_s * std::tanh(e_dot / v_r); }
  double rate(double, double, double) const { return 0; }
  double stored_energy(double, double) const { return 0; }
  double force_at_rest(double) const { return 0; }
  double stiffness() const { return 0; }
  double yielded_stiffness() const { return 0; }
};

}  // namespace rocking
