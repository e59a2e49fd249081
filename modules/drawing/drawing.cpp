module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>
#include <vector>
module rocking.drawing;

namespace rocking {

namespace {

// A point (x, y) turned clockwise by theta about (px, py).
struct Turn {
  double px = 0, py = 0, c = 1, s = 0;
  Turn(double pivot_x, double pivot_y, double theta)
      : px(pivot_x), py(pivot_y), c(std::cos(theta)), s(std::sin(theta)) {}
  Point operator()(double x, double y) const {
    const double dx = x - px, dy = y - py;
    return {px + dx * c + dy * s, py - dx * s + dy * c};
  }
};

int side(double theta) { return theta > 0 ? 1 : theta < 0 ? -1 : 0; }

double theta_of(std::span<const double> thetas, std::size_t j) { return j < thetas.size() ? thetas[j] : 0.0; }

}  // namespace

Outline outline(const Structure& s, Phase phase, double theta, const Eigen::VectorXd& u, double exaggeration) {
  const double B = s.half_width;
  const int pivot = phase.sign();
  const Turn place(pivot * B, 0.0, phase.is_rocking() ? theta : 0.0);
  Outline o;
  o.axis.push_back(place(0.0, 0.0));
  for (Eigen::Index i = 0; i < s.heights.size(); ++i) {
    const double ui = i < u.size() ? exaggeration * u[i] : 0.0;
    o.axis.push_back(place(ui, s.heights[i]));
  }
  o.left_corner = place(-B, 0.0);
  o.right_corner = place(B, 0.0);
  // Rocking about +1 lifts the left edge, about -1 the right one.
  o.damper_anchor = pivot > 0 ? Point{-B, 0.0} : Point{B, 0.0};
  o.damper_end = pivot > 0 ? o.left_corner : pivot < 0 ? o.right_corner : o.damper_anchor;
  if (pivot == 0) o.damper_anchor = o.damper_end = Point{B, 0.0};
  return o;
}

ColumnsOutline columns_outline(const Columns& c, double theta, const Eigen::VectorXd& u, double exaggeration) {
  const double b = c.group.half_width, top = 2.0 * c.group.half_height;
  const int s = side(theta);
  ColumnsOutline o;
  for (Eigen::Index k = 0; k < c.axes.size(); ++k) {
    const double x = c.axes[k];
    const Turn place(x + s * b, 0.0, theta);
    o.columns.push_back({place(x - b, 0.0), place(x + b, 0.0), place(x + b, top), place(x - b, top)});
  }
  const BeamMotion m = s == 0 ? BeamMotion{} : beam_motion(c, s > 0 ? Pivot::right : Pivot::left, Tilt(theta));
  o.beam_shift = {m.dx, m.dy};
  const double reach = (c.axes.size() > 0 ? c.axes.cwiseAbs().maxCoeff() : 0.0) + b;
  o.beam_left = {-reach + m.dx, top + m.dy};
  o.beam_right = {reach + m.dx, top + m.dy};
  const Structure& st = c.structure;
  o.axis.push_back({m.dx, top + m.dy});
  for (Eigen::Index i = 0; i < st.heights.size(); ++i) {
    const double ui = i < u.size() ? exaggeration * u[i] : 0.0;
    o.axis.push_back({m.dx + ui, top + m.dy + st.heights[i]});
  }
  return o;
}

double segment_top(const ChainData& d, int segment) {
  const auto j = static_cast<std::size_t>(segment);
  if (j + 1 < d.segments.size()) return d.segments[j + 1].base_height;
  const ChainSegment& g = d.segments[j];
  const Eigen::Index n = g.heights.size();
  if (n == 0) return g.base_height;
  const double first = g.heights[0] - g.base_height, last = g.heights[n - 1] - g.base_height;
  const bool slices = std::abs(last - static_cast<double>(2 * n - 1) * first) <= 1e-9 * std::max(1.0, last);
  return slices ? g.heights[n - 1] + first : g.heights[n - 1];
}

Point chain_point(const ChainData& d, std::span<const double> thetas, int segment, double x, double z) {
  // Turn about each joint's corner from the segment's own down to the ground's:
  // the rotation of joint k carries everything above it.
  Point p{x, z};
  for (int k = segment; k >= 0; --k) {
    const ChainSegment& g = d.segments[static_cast<std::size_t>(k)];
    const double th = theta_of(thetas, static_cast<std::size_t>(k));
    p = Turn(side(th) * g.half_width, g.base_height, th)(p.first, p.second);
  }
  return p;
}

ChainOutline chain_outline(const ChainData& d, std::span<const double> thetas) {
  ChainOutline o;
  double angle = 0;
  for (std::size_t j = 0; j < d.segments.size(); ++j) {
    const ChainSegment& g = d.segments[j];
    const int k = static_cast<int>(j);
    const double B = g.half_width, h = g.base_height, top = segment_top(d, k);
    angle += theta_of(thetas, j);
    SegmentOutline s{.base_left = chain_point(d, thetas, k, -B, h),
                     .base_right = chain_point(d, thetas, k, B, h),
                     .top_right = chain_point(d, thetas, k, B, top),
                     .top_left = chain_point(d, thetas, k, -B, top),
                     .axis = {chain_point(d, thetas, k, 0.0, h)},
                     .angle = angle};
    for (Eigen::Index i = 0; i < g.heights.size(); ++i) s.axis.push_back(chain_point(d, thetas, k, 0.0, g.heights[i]));
    o.segments.push_back(std::move(s));
  }
  // An anchor's z is its height above its segment's slab (the ground's: above the ground).
  auto anchor = [&](const ChainAnchor& a) {
    const double base = a.segment >= 0 ? d.segments[static_cast<std::size_t>(a.segment)].base_height : 0.0;
    return chain_point(d, thetas, a.segment, a.x, base + a.z);
  };
  for (const ChainTendon& t : d.tendons) o.tendons.emplace_back(anchor(t.from), anchor(t.to));
  return o;
}

}  // namespace rocking
