// The Kelvin-Voigt law: a spring and a linear dashpot side by side,
// F = k e + c e' (a viscoelastic damper of polymer layers, idealised at its
// working frequency; k = 0 is a linear dashpot, c = 0 a linear spring that
// also pushes). No internal state; it stores k e^2 / 2, holds nothing at
// rest and dissipates c e'^2. Its slope is k at rest and throughout (it never
// yields).
module;
#include <vector>
export module rocking.devices:kelvin;
import :parameters;

export namespace rocking {

struct KelvinLaw {
  static constexpr const char* name = "kelvin";
  static constexpr const char* summary = "F = k e + c e': a spring and a dashpot side by side (a viscoelastic damper)";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = true;
  static constexpr const char* prestress_key = nullptr;
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"k", "N/m", "stiffness of the spring", R::stiffness, 2e6, 0, 0, false, 1e13},
            {"c", "N s/m", "damping coefficient of the dashpot", R::rate_coefficient, 3e5, 0, 0, false, 1e12}};
  }
  static KelvinLaw make(const std::vector<double>& v) { return {v[0], v[1]}; }

  double k = 0, c = 0;
  static constexpr int states = 0;
  double force(double e, double e_dot, double /*z*/) const { return k * e + c * e_dot; }
  double rate(double, double, double) const { return 0; }
  double stored_energy(double e, double /*z*/) const { return 0.5 * k * e * e; }
  double force_at_rest(double /*z*/) const { return 0; }
  double stiffness() const { return k; }
  double yielded_stiffness() const { return k; }
};

}  // namespace rocking
