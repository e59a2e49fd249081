// rocking.hysteresis: the metallic dampers at the rocking interface (MODEL.md 5;
// the paper's Eqs. 6-7, Bouc-Wen after Wen 1976). Each edge carries one damper,
// stretched when that edge lifts; its elongation is the chord of the lifted
// edge, d = 4B sin(|theta|/2), and it yields at d_y = 4B sin(theta_y/2).
// Damper thickness scale tau models a tapered plate in bending: stiffness
// scales with tau^3, yield force with tau^2, so d_y scales with 1/tau.
// SI units: N/m, m, rad.
module;
#include <cmath>
export module rocking.hysteresis;
export import rocking.geometry;

export namespace rocking {

struct Damper {
  bool enabled = true;
  double stiffness = 0;         // k_hd, pre-yield [N/m]
  double post_yield_ratio = 0;  // eps [-]
  double theta_y = 0;           // base rotation at full yield [rad] (as built)
  double alpha = 1, beta = 0, n = 1;  // Bouc-Wen shape parameters [-]
  double thickness = 1;         // tau, plate thickness scale (1 = as built)
  double capacity = 0;          // elongation at which a plate fractures [m] (MODEL.md 11); 0: never
};

// The plate's stiffness with its thickness scale: k tau^3 [N/m].
double plate_stiffness(const Damper& d);

// Its yield elongation, d_y = 4B sin(theta_y/2) / tau [m]: theta_y is the
// as-built plate's; a plate thin enough that d_y exceeds any chord (4B)
// never yields.
double yield_displacement(const Damper& d, double half_width);

// Rotational stiffness about a pivot of a damper at lever arm 2B, for the
// linearised rocking phase: pre-yield k (2B)^2, post-yield eps k (2B)^2.
double pre_yield_rotational_stiffness(const Damper& d, double half_width);
double post_yield_rotational_stiffness(const Damper& d, double half_width);

// Kinematics of the damper of the lifted edge while rocking about pivot p
// (theta > 0 about the right pivot, s = sign(p) = +1): elongation
// d = 4B sin(|theta|/2), rate v = 2B cos(theta/2) s theta'.
double damper_elongation(double half_width, const Tilt& tilt);
double damper_rate(double half_width, const Tilt& tilt, double theta_dot, Pivot p);

// F_hd = k eps d + k (1 - eps) d_y z (Eq. 6) [N]; inline, for the right-hand side.
inline double damper_force(const Damper& d, double d_y, double elongation, double z) {
  return d.stiffness * (d.post_yield_ratio * elongation + (1.0 - d.post_yield_ratio) * d_y * z);
}

// Bouc-Wen (Eq. 7 with its "= 0"): d_y z' = v - alpha |v| z |z|^(n-1) - beta v |z|^n.
// Returns z' [1/s]; z stays in [-1, 1] for alpha + beta = 1 when it starts there.
inline double bouc_wen_rate(const Damper& d, double d_y, double v, double z) {
  const double az = std::abs(z);
  const double zn1 = d.n == 1.0 ? 1.0 : std::pow(az, d.n - 1.0);  // |z|^(n-1)
  return (v - d.alpha * std::abs(v) * z * zn1 - d.beta * v * az * zn1) / d_y;
}

}  // namespace rocking
