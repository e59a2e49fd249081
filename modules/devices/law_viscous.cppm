// The viscous law (MODEL.md 11): F = c sign(e') |e'|^a; a = 1 a linear
// dashpot, 0.2-1 the fluid viscous dampers of practice. No internal state;
// it stores nothing and has no force at rest.
module;
#include <cmath>
#include <vector>
export module rocking.devices:viscous;
import :parameters;

export namespace rocking {

struct ViscousLaw {
  static constexpr const char* name = "viscous";
  static constexpr const char* summary = "F = c sign(e') |e'|^a: a fluid viscous damper (a = 1: a dashpot)";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = true;
  static constexpr const char* prestress_key = nullptr;
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"c", "N (s/m)^a", "damping coefficient", R::rate_coefficient, 2e5, 0, 0, false, 1e12},
            {"a", "-", "velocity exponent (1: linear)", R::rate_exponent, 0.4, 1, 0, true, 3}};
  }
  static ViscousLaw make(const std::vector<double>& v) { return {v[0], v[1]}; }

  double c = 0, a = 1;
  static constexpr int states = 0;
  double force(double /*e*/, double e_dot, double /*z*/) const {
    if (a == 1.0) return c * e_dot;
    return std::copysign(c * std::pow(std::abs(e_dot), a), e_dot);
  }
  double rate(double, double, double) const { return 0; }
  double stored_energy(double, double) const { return 0; }
  double force_at_rest(double) const { return 0; }
  double stiffness() const { return 0; }
  double yielded_stiffness() const { return 0; }
};

}  // namespace rocking
