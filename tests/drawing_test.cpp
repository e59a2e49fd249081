// rocking.drawing: the drawn structure is the model's geometry: the active
// pivot stays put, the lifted corner and the nodes are where the rotation puts
// them, and the damper's drawn length is the chord of MODEL.md 5.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
import rocking.drawing;
import rocking.hysteresis;
import rocking.scene;

using namespace rocking;

TEST_CASE("the drawn chimney at rest has its pivots at +-B and its nodes at the heights H") {
  const Structure s = load_default_scene().structure;
  const Outline o = outline(s, Phase::full_contact(), 0.3, Eigen::VectorXd::Zero(4), 100.0);
  CHECK(o.left_corner == Point{-3.3, 0.0});
  CHECK(o.right_corner == Point{3.3, 0.0});
  REQUIRE(o.axis.size() == 5);
  for (int i = 0; i < 4; ++i) {
    CHECK(o.axis[static_cast<std::size_t>(i + 1)].first == 0.0);
    CHECK(o.axis[static_cast<std::size_t>(i + 1)].second == s.heights[i]);
  }
}

TEST_CASE("rocking about the right pivot: the pivot stays, the top moves by Eq. 11, the damper spans the chord") {
  const Structure s = load_default_scene().structure;
  const double th = 0.1, B = s.half_width;
  Eigen::VectorXd u(4);
  u << 0.001, 0.002, 0.003, 0.004;
  const double k = 50.0;
  const Outline o = outline(s, Phase::rocking(Pivot::right), th, u, k);
  CHECK(o.right_corner.first == close_to(B, 1e-12));
  CHECK(o.right_corner.second == within(0.0, 1e-15 * B));  // the pivot stays on the ground, to round-off
  CHECK(o.left_corner.first == close_to(B - 2 * B * std::cos(th), 1e-12));
  CHECK(o.left_corner.second == close_to(2 * B * std::sin(th), 1e-12));
  // Top node: MODEL.md 7, Eq. 11 with the drawn (exaggerated) u_N.
  const double H = s.heights[3], uN = k * u[3];
  CHECK(o.axis[4].first == close_to(B * (1 - std::cos(th)) + uN * std::cos(th) + H * std::sin(th), 1e-12));
  CHECK(o.axis[4].second == close_to(B * std::sin(th) - uN * std::sin(th) + H * std::cos(th), 1e-12));
  const double dx = o.damper_end.first - o.damper_anchor.first, dy = o.damper_end.second - o.damper_anchor.second;
  CHECK(std::hypot(dx, dy) == close_to(damper_elongation(B, th), 1e-12));
  // About the left pivot, the mirror image.
  const Outline m = outline(s, Phase::rocking(Pivot::left), -th, Eigen::VectorXd::Zero(4), k);
  CHECK(m.left_corner.first == close_to(-B, 1e-12));
  CHECK(m.right_corner.first == close_to(-B + 2 * B * std::cos(th), 1e-12));
  CHECK(m.right_corner.second == close_to(2 * B * std::sin(th), 1e-12));
}
