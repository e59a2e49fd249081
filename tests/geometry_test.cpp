// rocking.geometry: derived quantities against hand-computed closed forms.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
import rocking.geometry;

using namespace rocking;

namespace {
Structure two_masses() {
  Structure s;
  s.half_width = 2.0;
  s.heights = Eigen::Vector2d(3.0, 6.0);
  s.masses = Eigen::Vector2d(100.0, 50.0);
  s.base_mass = 50.0;
  s.EI = Eigen::Vector2d(1e9, 1e9);
  s.damping_ratio = 0.05;
  return s;
}
}  // namespace

TEST_CASE("pivot inertia is the sum of m r^2 about the pivot") {
  const Structure s = two_masses();
  // m0 B^2 + m1 (H1^2 + B^2) + m2 (H2^2 + B^2) = 50*4 + 100*13 + 50*40
  CHECK(pivot_inertia(s) == close_to(200.0 + 1300.0 + 2000.0, 1e-15));
}

TEST_CASE("centre of gravity counts the foundation mass at height zero") {
  const Structure s = two_masses();
  CHECK(total_mass(s) == close_to(200.0, 1e-12));
  CHECK(centre_of_gravity_height(s) == close_to((300.0 + 300.0) / 200.0, 1e-12));
  CHECK(slenderness(s) == close_to(std::atan(2.0 / 3.0), 1e-12));
}

TEST_CASE("Eq. 10 restitution: 1 - 2 m_total B^2 / J_p") {
  const Structure s = two_masses();
  CHECK(restitution_eq10(s) == close_to(1.0 - 2.0 * 200.0 * 4.0 / 3500.0, 1e-12));
}

TEST_CASE("a rigid block of one mass at its centre reproduces Housner's r for a point mass") {
  // One mass m at height h, no foundation mass: J_p = m (h^2 + B^2), and
  // r = 1 - 2 B^2 / (h^2 + B^2) = cos(2 alpha), the point-mass limit.
  Structure s;
  s.half_width = 1.0;
  s.heights = Eigen::VectorXd::Constant(1, 4.0);
  s.masses = Eigen::VectorXd::Constant(1, 10.0);
  s.EI = Eigen::VectorXd::Constant(1, 1.0);
  const double alpha = std::atan(1.0 / 4.0);
  CHECK(restitution_eq10(s) == close_to(std::cos(2 * alpha), 1e-14));
}

TEST_CASE("a tilt's half-angle sine and cosine agree with the library to a few ulps, inside and beyond the polynomial range") {
  // Tilt evaluates Taylor polynomials for |theta/2| <= 0.8 and calls std::sin
  // and std::cos beyond; both must agree with the library to round-off.
  double worst = 0;
  for (double th = -3.0; th <= 3.0; th += 1.0 / 4096) {
    const Tilt t(th);
    worst = std::max({worst, std::abs(t.sin_half - std::sin(0.5 * th)), std::abs(t.cos_half - std::cos(0.5 * th))});
    // the full angle's from the half angle's: absolute round-off (cos theta crosses 0)
    CHECK(std::abs(t.sin() - std::sin(th)) <= 8 * std::numeric_limits<double>::epsilon());
    CHECK(std::abs(t.cos() - std::cos(th)) <= 8 * std::numeric_limits<double>::epsilon());
  }
  CHECK(worst <= 4 * std::numeric_limits<double>::epsilon());
  for (double th : {1.6, -1.6, 1.6 * (1 - 1e-15), 1.6 * (1 + 1e-15)}) {  // either side of the switch
    const Tilt t(th);
    CHECK(std::abs(t.sin_half - std::sin(0.5 * th)) <= 2 * std::numeric_limits<double>::epsilon());
    CHECK(std::abs(t.cos_half - std::cos(0.5 * th)) <= 2 * std::numeric_limits<double>::epsilon());
  }
  const Tilt zero(0.0);
  CHECK((zero.sin_half == 0.0 && zero.cos_half == 1.0 && zero.sin() == 0.0 && zero.cos() == 1.0));
}

TEST_CASE("check names the field that breaks an invariant") {
  Structure s = two_masses();
  CHECK_NOTHROW(check(s));
  s.masses[1] = -1;
  CHECK_THROWS_WITH_AS(check(s), "masses must be positive", std::invalid_argument);
  s = two_masses();
  s.heights[1] = 3.0;
  CHECK_THROWS_WITH_AS(check(s), "heights must increase from above 0", std::invalid_argument);
  s = two_masses();
  s.EI[0] = 0;
  CHECK_THROWS_WITH_AS(check(s), "EI must be positive", std::invalid_argument);
}
