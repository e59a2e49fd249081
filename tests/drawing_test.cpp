// rocking.drawing: the drawn structure is the model's geometry: the active
// pivot stays put, the lifted corner and the nodes are where the rotation puts
// them, and the damper's drawn length is the chord of MODEL.md 5. On rocking
// columns, each column turns about its pivot and the beam moves by MODEL.md
// 16's (dx, dy) onto their far top corners; in a chain, each segment stands
// on the corner the segment below carries, as a hand computation and the
// engine's kinematics (rocking.chain) place it.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <array>
#include <cmath>
#include <complex>
#include <string>
#include <utility>
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

namespace {

// Both coordinates of a drawn point within `tol` metres of the expected place.
void check_point(const Point& drawn, double x, double y, double tol) {
  CHECK(drawn.first == within(x, tol));
  CHECK(drawn.second == within(y, tol));
}

// p turned clockwise by theta about c, as a complex rotation: (p - c) e^(-i theta) + c.
Point turned(double px, double py, double cx, double cy, double theta) {
  const std::complex<double> z = std::complex<double>(px - cx, py - cy) * std::polar(1.0, -theta);
  return {cx + z.real(), cy + z.imag()};
}

// Three piers 1 m wide and 6 m tall, 8 m apart, under a deck of two nodes.
Columns three_columns() {
  Structure s;
  s.half_width = 1.0;  // not used on columns
  s.heights = Eigen::Vector2d(2.0, 3.5);
  s.masses = Eigen::Vector2d(4.0e4, 2.0e4);
  s.base_mass = 3.0e4;
  s.rigid = true;
  return make_columns({.count = 3, .half_width = 0.5, .half_height = 3.0, .mass = 1.0e4, .spacing = 8.0}, s);
}

}  // namespace

TEST_CASE("columns at rest: each column a 2b x 2h rectangle on its axis, the beam on their tops, the deck above its centre") {
  const Columns c = three_columns();
  Eigen::VectorXd u(2);
  u << 0.01, -0.02;
  const ColumnsOutline o = columns_outline(c, 0.0, u, 10.0);
  REQUIRE(o.columns.size() == 3);
  for (std::size_t k = 0; k < 3; ++k) {
    const double x = -4.0 + 4.0 * static_cast<double>(k);
    check_point(o.columns[k][0], x - 0.5, 0.0, 0.0);
    check_point(o.columns[k][1], x + 0.5, 0.0, 0.0);
    check_point(o.columns[k][2], x + 0.5, 6.0, 0.0);
    check_point(o.columns[k][3], x - 0.5, 6.0, 0.0);
  }
  check_point(o.beam_left, -4.5, 6.0, 0.0);
  check_point(o.beam_right, 4.5, 6.0, 0.0);
  check_point(o.beam_shift, 0.0, 0.0, 0.0);
  REQUIRE(o.axis.size() == 3);
  check_point(o.axis[0], 0.0, 6.0, 0.0);
  check_point(o.axis[1], 10.0 * 0.01, 8.0, 1e-15);
  check_point(o.axis[2], 10.0 * -0.02, 9.5, 1e-15);
}

TEST_CASE("columns rocking: every column turned about its pivot corner, the beam moved by beam_motion onto their far top corners") {
  const Columns c = three_columns();
  const double b = 0.5, h = 3.0, R = std::hypot(b, h), alpha = std::atan(b / h);
  Eigen::VectorXd u(2);
  u << 0.01, -0.02;
  for (const double theta : {0.07, -0.07, 0.3, -1e-4}) {
    CAPTURE(theta);
    const Pivot p = theta > 0 ? Pivot::right : Pivot::left;
    const int s = sign(p);
    const ColumnsOutline o = columns_outline(c, theta, u, 10.0);
    REQUIRE(o.columns.size() == 3);
    for (std::size_t k = 0; k < 3; ++k) {
      const double x = -4.0 + 4.0 * static_cast<double>(k), px = x + s * b;
      const std::array<Point, 4> rest{Point{x - b, 0.0}, Point{x + b, 0.0}, Point{x + b, 2 * h}, Point{x - b, 2 * h}};
      for (std::size_t i = 0; i < 4; ++i) {
        const Point want = turned(rest[i].first, rest[i].second, px, 0.0, theta);
        check_point(o.columns[k][i], want.first, want.second, 1e-12);
      }
      // The pivot corner stays on the ground where it was.
      check_point(o.columns[k][s > 0 ? 1 : 0], px, 0.0, 1e-15);
    }
    // The beam's translation: beam_motion's, which is MODEL.md 16's formula.
    const BeamMotion m = beam_motion(c, p, Tilt(theta));
    CHECK(m.dx == close_to(2 * R * s * (std::sin(alpha) - std::sin(alpha - s * theta)), 1e-12));
    CHECK(m.dy == close_to(2 * R * (std::cos(alpha - s * theta) - std::cos(alpha)), 1e-12));
    check_point(o.beam_shift, m.dx, m.dy, 0.0);
    check_point(o.beam_left, -4.5 + m.dx, 2 * h + m.dy, 1e-12);
    check_point(o.beam_right, 4.5 + m.dx, 2 * h + m.dy, 1e-12);
    // The beam rests on the top corner opposite each pivot: that corner, as
    // the column's rotation puts it, is the point of the beam above it.
    for (std::size_t k = 0; k < 3; ++k) {
      const double x = -4.0 + 4.0 * static_cast<double>(k);
      const Point far = o.columns[k][s > 0 ? 3 : 2];
      check_point(far, x - s * b + m.dx, 2 * h + m.dy, 1e-12);
    }
    // The deck translates with the beam, never tilting; u drawn x10 relative to it.
    check_point(o.axis[0], m.dx, 2 * h + m.dy, 1e-12);
    check_point(o.axis[1], m.dx + 0.1, 2 * h + m.dy + 2.0, 1e-12);
    check_point(o.axis[2], m.dx - 0.2, 2 * h + m.dy + 3.5, 1e-12);
  }
}

namespace {

// The stacked blocks of data/scenes: a plinth (B_0 = 0.4, 1 m) and an
// artefact on it (B_1 = 0.15, from 1 m to 1.9 m: three equal slices).
ChainData stacked_blocks() { return jointed_model(load_scene(std::string(ROCKING_SCENES) + "/stacked_blocks.toml")).chain.data; }

}  // namespace

TEST_CASE("a two-block stack at rest is drawn as it stands: the plinth 0.8 x 1 m, the artefact 0.3 x 0.9 m on it") {
  const ChainData d = stacked_blocks();
  REQUIRE(d.segments.size() == 2);
  const std::array<double, 2> zero{0.0, 0.0};
  const ChainOutline o = chain_outline(d, zero);
  REQUIRE(o.segments.size() == 2);
  check_point(o.segments[0].base_left, -0.4, 0.0, 0.0);
  check_point(o.segments[0].base_right, 0.4, 0.0, 0.0);
  check_point(o.segments[0].top_right, 0.4, 1.0, 0.0);
  check_point(o.segments[1].base_left, -0.15, 1.0, 0.0);
  check_point(o.segments[1].top_left, -0.15, 1.9, 1e-15);
  CHECK(segment_top(d, 1) == close_to(1.9, 1e-15));
  REQUIRE(o.segments[1].axis.size() == 4);  // the slab's centre and three nodes
  check_point(o.segments[1].axis[3], 0.0, 1.75, 0.0);
  CHECK(o.tendons.empty());
}

TEST_CASE("a two-block stack rocking: the artefact's base corners are where the plinth puts its joint's corner, as a hand computation places them") {
  const ChainData d = stacked_blocks();
  const double B0 = 0.4, B1 = 0.15, h1 = 1.0, top = 1.9;
  for (const auto& [t0, t1] : {std::pair{0.05, -0.12}, std::pair{-0.08, -0.03}, std::pair{0.0, 0.2}, std::pair{0.1, 0.0}}) {
    CAPTURE(t0);
    CAPTURE(t1);
    const std::array<double, 2> thetas{t0, t1};
    const ChainOutline o = chain_outline(d, thetas);
    // By hand: the plinth turns clockwise by t0 about its corner (s0 B0, 0)
    // (s0 = sign t0); the artefact's corner (s1 B1, h1) goes with it, and the
    // artefact turns by t0 + t1 in all about that point.
    const double s0 = t0 > 0 ? 1 : t0 < 0 ? -1 : 0, s1 = t1 > 0 ? 1 : t1 < 0 ? -1 : 0;
    const double c0 = std::cos(t0), n0 = std::sin(t0), c = std::cos(t0 + t1), n = std::sin(t0 + t1);
    const double qx = s0 * B0 + (s1 * B1 - s0 * B0) * c0 + h1 * n0, qy = -(s1 * B1 - s0 * B0) * n0 + h1 * c0;
    auto artefact = [&](double x, double z) {  // a point of the artefact at rest (x, z)
      const double dx = x - s1 * B1, dz = z - h1;
      return Point{qx + dx * c + dz * n, qy - dx * n + dz * c};
    };
    const SegmentOutline& a = o.segments[1];
    const Point want_left = artefact(-B1, h1), want_right = artefact(B1, h1);
    check_point(a.base_left, want_left.first, want_left.second, 1e-12);
    check_point(a.base_right, want_right.first, want_right.second, 1e-12);
    const Point want_top = artefact(B1, top);
    check_point(a.top_right, want_top.first, want_top.second, 1e-12);
    CHECK(a.angle == close_to(t0 + t1, 1e-15, 1e-300));
    // The pivot corner (the left one at rest) is the plinth's point there.
    const Point corner = chain_point(d, thetas, 0, s1 != 0 ? s1 * B1 : -B1, h1);
    const Point base = s1 > 0 ? a.base_right : a.base_left;
    check_point(base, corner.first, corner.second, 1e-12);
    // The plinth: turned by t0 about its own corner.
    const Point p = turned(-B0, 1.0, s0 * B0, 0.0, t0);
    check_point(o.segments[0].top_left, p.first, p.second, 1e-12);
    // The engine's kinematics (rocking.chain) put the artefact's points where the drawing does.
    const Chain chain = make_chain(d);
    ChainWorkspace w = make_workspace(chain);
    const std::array<Phase, 2> phases{s0 > 0 ? Phase::rocking(Pivot::right) : s0 < 0 ? Phase::rocking(Pivot::left) : Phase{},
                                      s1 > 0 ? Phase::rocking(Pivot::right) : s1 < 0 ? Phase::rocking(Pivot::left) : Phase{}};
    Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size);
    q[0] = t0;
    q[1] = t1;
    for (const auto& [x, z] : {std::pair{-B1, 0.0}, std::pair{B1, 0.9}, std::pair{0.0, 0.75}}) {
      const Eigen::Vector2d e = anchor_position(chain, phases, {.segment = 1, .x = x, .z = z}, q, w);
      const Point drawn = chain_point(d, thetas, 1, x, h1 + z);
      check_point(drawn, e.x(), e.y(), 1e-12);
    }
  }
}

TEST_CASE("the segmental pier's tendon is drawn from the footing to the pier's top, as long as the engine stretches it") {
  const ChainData d = jointed_model(load_scene(std::string(ROCKING_SCENES) + "/segmental_pier.toml")).chain.data;
  REQUIRE(d.segments.size() == 4);
  REQUIRE(d.tendons.size() == 1);
  const std::array<double, 4> thetas{0.004, -0.002, 0.003, 0.001};
  const ChainOutline o = chain_outline(d, thetas);
  REQUIRE(o.tendons.size() == 1);
  const auto& [from, to] = o.tendons[0];
  check_point(from, 0.0, 0.0, 0.0);
  // Its end is the top segment's point (0, 8 m) at rest: the top segment's slab turned with all four joints.
  const Point top = chain_point(d, thetas, 3, 0.0, 8.0);
  check_point(to, top.first, top.second, 0.0);
  const Chain chain = make_chain(d);
  ChainWorkspace w = make_workspace(chain);
  std::array<Phase, 4> phases;
  for (std::size_t j = 0; j < 4; ++j) phases[j] = Phase::rocking(thetas[j] > 0 ? Pivot::right : Pivot::left);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(chain.size);
  for (int j = 0; j < 4; ++j) q[j] = thetas[static_cast<std::size_t>(j)];
  const double e = tendon_elongation(chain, phases, 0, q, w);
  CHECK(e > 0);  // every joint open stretches it
  CHECK(std::hypot(to.first - from.first, to.second - from.second) - 8.0 == close_to(e, 1e-9));
}
