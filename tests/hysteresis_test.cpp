// rocking.hysteresis: damper kinematics and the tapered-plate thickness rule.
#include <doctest/doctest.h>
#include <cmath>
#include <initializer_list>
import rocking.hysteresis;

using namespace rocking;

namespace {
Damper chimney_damper() {
  Damper d;
  d.stiffness = 1.0e7;
  d.post_yield_ratio = 0.06;
  d.theta_y = 2.8e-3;
  return d;
}
constexpr double B = 3.3;
}  // namespace

TEST_CASE("the chimney damper yields at d_y = 4B sin(theta_y/2) = 18.48 mm (MODEL.md 5)") {
  CHECK(yield_displacement(chimney_damper(), B) == doctest::Approx(18.48e-3).epsilon(5e-4));
}

TEST_CASE("thickness x tau: stiffness x tau^3, yield force x tau^2, yield displacement x 1/tau") {
  const Damper base = chimney_damper();
  for (double tau : {0.5, 1.5, 2.0, 3.0}) {
    Damper thick = base;
    thick.thickness = tau;
    const Damper s = scaled_for_thickness(thick);
    CHECK(s.thickness == 1.0);
    CHECK(s.stiffness == doctest::Approx(base.stiffness * tau * tau * tau).epsilon(1e-14));
    const double dy = yield_displacement(s, B), dy0 = yield_displacement(base, B);
    CHECK(dy == doctest::Approx(dy0 / tau).epsilon(1e-12));
    CHECK(s.stiffness * dy == doctest::Approx(base.stiffness * dy0 * tau * tau).epsilon(1e-12));
  }
}

TEST_CASE("rotational stiffness of the damper about a pivot is k (2B)^2, eps k (2B)^2 after yield") {
  const Damper d = chimney_damper();
  CHECK(pre_yield_rotational_stiffness(d, B) == doctest::Approx(1e7 * 6.6 * 6.6));
  CHECK(post_yield_rotational_stiffness(d, B) == doctest::Approx(0.06 * 1e7 * 6.6 * 6.6));
}
