module;
#include <cmath>
module rocking.hysteresis;

namespace rocking {

Damper scaled_for_thickness(const Damper& d) {
  Damper out = d;
  const double tau = d.thickness;
  out.stiffness = d.stiffness * tau * tau * tau;
  // d_y / tau = 4B sin(theta_y'/2): B cancels.
  out.theta_y = 2.0 * std::asin(std::sin(0.5 * d.theta_y) / tau);
  out.thickness = 1.0;
  return out;
}

double yield_displacement(const Damper& d, double B) { return 4.0 * B * std::sin(0.5 * d.theta_y); }

double pre_yield_rotational_stiffness(const Damper& d, double B) {
  return d.stiffness * 4.0 * B * B;
}

double post_yield_rotational_stiffness(const Damper& d, double B) {
  return d.post_yield_ratio * pre_yield_rotational_stiffness(d, B);
}

double damper_elongation(double B, const Tilt& tilt) { return 4.0 * B * std::abs(tilt.sin_half); }

double damper_rate(double B, const Tilt& tilt, double theta_dot, int s) {
  return 2.0 * B * tilt.cos_half * s * theta_dot;
}

}  // namespace rocking
