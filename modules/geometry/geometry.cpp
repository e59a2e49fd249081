module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
#include <string_view>
module rocking.geometry;

namespace rocking {

std::string_view pivot_name(Pivot p) { return p == Pivot::right ? "right" : "left"; }

std::string_view phase_name(Phase p) {
  if (!p.is_rocking()) return "full_contact";
  return *p.pivot() == Pivot::right ? "rocking(+1)" : "rocking(-1)";
}

namespace {

// sin x and cos x for |x| <= small_angle_limit by their Taylor series to x^17
// and x^16, evaluated by Estrin's scheme in x^2 (a short dependency chain:
// this is the start of every rocking right-hand side). The first omitted
// terms, x^19/19! and x^18/18!, are below 2e-19 and 3e-18 there, so the error
// is the evaluation's round-off, a few units in the last place (tests check
// it against the library over and beyond the range).
constexpr double small_angle_limit = 0.8;
void small_sincos(double x, double& sine, double& cosine) {
  const double x2 = x * x, x4 = x2 * x2, x8 = x4 * x4;
  // sin x / x = s0 + s1 x2 + ... + s8 x16;  cos x = c0 + c1 x2 + ... + c8 x16
  constexpr double s0 = 1, s1 = -1.0 / 6, s2 = 1.0 / 120, s3 = -1.0 / 5040, s4 = 1.0 / 362880,
                   s5 = -1.0 / 39916800, s6 = 1.0 / 6227020800, s7 = -1.0 / 1307674368000,
                   s8 = 1.0 / 355687428096000;
  constexpr double c0 = 1, c1 = -1.0 / 2, c2 = 1.0 / 24, c3 = -1.0 / 720, c4 = 1.0 / 40320, c5 = -1.0 / 3628800,
                   c6 = 1.0 / 479001600, c7 = -1.0 / 87178291200, c8 = 1.0 / 20922789888000;
  const double sl = (s0 + s1 * x2) + x4 * (s2 + s3 * x2), sh = (s4 + s5 * x2) + x4 * (s6 + s7 * x2);
  const double cl = (c0 + c1 * x2) + x4 * (c2 + c3 * x2), ch = (c4 + c5 * x2) + x4 * (c6 + c7 * x2);
  sine = x * (sl + x8 * (sh + x8 * s8));
  cosine = cl + x8 * (ch + x8 * c8);
}

}  // namespace

Tilt::Tilt(double th) : theta(th) {
  if (th == 0) return;  // full contact: sin 0 = 0, cos 0 = 1
  const double half = 0.5 * th;
  if (std::abs(half) <= small_angle_limit) {
    small_sincos(half, sin_half, cos_half);
  } else {
    sin_half = std::sin(half);
    cos_half = std::cos(half);
  }
}

void check(const Structure& s) {
  const auto n = s.heights.size();
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (!(s.half_width > 0)) fail("half_width must be positive");
  if (n < 1) fail("heights must hold at least one node");
  if (s.masses.size() != n) fail("masses must have one entry per height");
  if (!s.rigid && s.EI.size() != n) fail("EI must have one entry per element (one per height)");
  if (!(s.base_mass >= 0)) fail("base_mass must be non-negative");
  if (!(s.EI_scale > 0)) fail("EI_scale must be positive");
  if (!(s.damping_ratio >= 0 && s.damping_ratio < 1)) fail("damping_ratio must be in [0, 1)");
  for (Eigen::Index i = 0; i < n; ++i) {
    const double below = i == 0 ? 0.0 : s.heights[i - 1];
    if (!(s.heights[i] > below)) fail("heights must increase from above 0");
    if (!(s.masses[i] > 0)) fail("masses must be positive");
    if (!s.rigid && !(s.EI[i] > 0)) fail("EI must be positive");
  }
}

Eigen::Index node_count(const Structure& s) { return s.heights.size(); }

double total_mass(const Structure& s) { return s.base_mass + s.masses.sum(); }

double pivot_inertia(const Structure& s) {
  const double b2 = s.half_width * s.half_width;
  return s.base_mass * b2 + s.masses.dot((s.heights.array().square() + b2).matrix());
}

double centre_of_gravity_height(const Structure& s) {
  return s.masses.dot(s.heights) / total_mass(s);
}

double slenderness(const Structure& s) {
  return std::atan(s.half_width / centre_of_gravity_height(s));
}

double restitution_eq10(const Structure& s) {
  return 1.0 - 2.0 * total_mass(s) * s.half_width * s.half_width / pivot_inertia(s);
}

}  // namespace rocking
