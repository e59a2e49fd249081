module;
#include <cmath>
module rocking.hysteresis;

namespace rocking {

double plate_stiffness(const Damper& d) { return d.stiffness * d.thickness * d.thickness * d.thickness; }

double yield_displacement(const Damper& d, double B) { return 4.0 * B * std::sin(0.5 * d.theta_y) / d.thickness; }

double pre_yield_rotational_stiffness(const Damper& d, double B) {
  return d.stiffness * 4.0 * B * B;
}

double post_yield_rotational_stiffness(const Damper& d, double B) {
  return d.post_yield_ratio * pre_yield_rotational_stiffness(d, B);
}

double damper_elongation(double B, const Tilt& tilt) { return 4.0 * B * std::abs(tilt.sin_half); }

double damper_rate(double B, const Tilt& tilt, double theta_dot, Pivot p) {
  return 2.0 * B * tilt.cos_half * sign(p) * theta_dot;
}

}  // namespace rocking
