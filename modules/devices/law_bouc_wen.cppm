// The Bouc-Wen law (MODEL.md 5; the paper's Eqs. 6-7, Wen 1976): a metallic
// yielding damper, F = k eps e + k (1 - eps) d_y z with
// d_y z' = e' - alpha |e'| z |z|^(n-1) - beta e' |z|^n; one state, z. It is
// rocking.hysteresis's damper, computed by the same functions, so a device of
// this law gives the numbers of the paper's damper bit for bit. It stores
// k eps e^2 / 2 + k (1 - eps) d_y^2 z^2 / 2 (the recoverable part) and holds
// the force k (1 - eps) d_y z at rest.
module;
#include <vector>
export module rocking.devices:bouc_wen;
import :parameters;
import rocking.hysteresis;

export namespace rocking {

struct BoucWenLaw {
  static constexpr const char* name = "bouc-wen";
  static constexpr const char* summary = "Bouc-Wen hysteresis: a yielding metallic damper (the paper's plates)";
  // Traits (rocking.devices' law_dissipates, law_prestress_key).
  static constexpr bool dissipates = true;
  static constexpr const char* prestress_key = nullptr;
  static std::vector<LawParameter> parameters() {
    using R = ParameterRole;
    return {{"k", "N/m", "pre-yield stiffness", R::stiffness, 2e7, 0, 0, true, 1e13},
            {"eps", "-", "post-yield stiffness ratio", R::hardening_ratio, 0.05, 0, 0, false, 1},
            // A micron at least: below it z' = e' / d_y outruns any step the run can take.
            {"d_y", "m", "yield elongation", R::yield_elongation, 0.004, 0, 1e-6, false, 10},
            // (d_y, alpha, beta) and (c d_y, c^n alpha, c^n beta) give the same
            // force for every c > 0 (z scales by 1/c): a fit holds alpha + beta = 1,
            // which makes d_y the yield elongation and |z| <= 1.
            {"alpha", "-", "Bouc-Wen shape", R::shape, 0.7, 0.5, 0, false, 100, "beta"},
            {"beta", "-", "Bouc-Wen shape", R::shape, 0.3, 0.5, 0, false, 100},
            {"n", "-", "Bouc-Wen sharpness of yield", R::shape, 1.5, 1, 0, true, 50}};
  }
  // alpha + beta = 0 leaves z' = e' / d_y unbounded: a spring, not a damper.
  static LawProblem problem(const std::vector<double>& v) {
    if (!(v[3] + v[4] > 0)) return {"beta", "alpha + beta must be positive (bounded hysteresis)"};
    return {};
  }
  static BoucWenLaw make(const std::vector<double>& v) {
    BoucWenLaw law;
    law.damper.stiffness = v[0];
    law.damper.post_yield_ratio = v[1];
    law.d_y = v[2];
    law.damper.alpha = v[3];
    law.damper.beta = v[4];
    law.damper.n = v[5];
    return law;
  }

  Damper damper;  // stiffness, post_yield_ratio, alpha, beta, n (theta_y and thickness unused)
  double d_y = 0;
  static constexpr int states = 1;
  double force(double e, double /*e_dot*/, double z) const { return damper_force(damper, d_y, e, z); }
  double rate(double /*e*/, double e_dot, double z) const { return bouc_wen_rate(damper, d_y, e_dot, z); }
  double stored_energy(double e, double z) const {
    const double k = damper.stiffness, eps = damper.post_yield_ratio;
    return 0.5 * k * eps * e * e + 0.5 * k * (1 - eps) * d_y * d_y * z * z;
  }
  double force_at_rest(double z) const { return damper_force(damper, d_y, 0.0, z); }
  double stiffness() const { return damper.stiffness; }
  double yielded_stiffness() const { return damper.stiffness * damper.post_yield_ratio; }
};

}  // namespace rocking
