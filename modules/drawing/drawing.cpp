module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <vector>
module rocking.drawing;

namespace rocking {

Outline outline(const Structure& s, Phase phase, double theta, const Eigen::VectorXd& u, double exaggeration) {
  const double B = s.half_width;
  const int pivot = phase.sign();
  const double th = phase.is_rocking() ? theta : 0.0;
  const double px = pivot * B;  // rotation centre
  const double c = std::cos(th), sn = std::sin(th);
  // A body point (x, y) rotated clockwise by theta about (px, 0).
  auto place = [&](double x, double y) -> Point {
    const double dx = x - px;
    return {px + dx * c + y * sn, -dx * sn + y * c};
  };
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

}  // namespace rocking
