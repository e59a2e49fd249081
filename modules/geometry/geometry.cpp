module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <stdexcept>
#include <string>
module rocking.geometry;

namespace rocking {

Tilt::Tilt(double th) : theta(th) {
  if (th != 0) {  // full contact (theta = 0) needs no trig
    sin_half = std::sin(0.5 * th);
    cos_half = std::cos(0.5 * th);
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
