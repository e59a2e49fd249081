// The order of an integrator's dense output, measured on the harmonic
// oscillator y0' = y1, y1' = -y0 from (1, 0): the worst error of the
// interpolant at 0.2 to 0.8 of a first step of length h shrinks as h^(p+1)
// for an interpolant of order p. Include after <rocking/eigen.hpp> and before
// any import.
#pragma once
#include <algorithm>
#include <cmath>
import rocking.integrator;

namespace dense_order {

inline void oscillator(double, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> f) {
  f[0] = y[1];
  f[1] = -y[0];
}

// make(h) returns an integrator of `oscillator` whose steps are h long; the
// order p from the errors of steps 2h and h.
template <class Make>
double measured(Make make, double h) {
  const auto worst_error = [&](double step) {
    auto integrator = make(step);
    integrator->reset(0.0, Eigen::Vector2d(1.0, 0.0), {});
    integrator->step(10.0);
    Eigen::VectorXd y(2);
    double worst = 0;
    for (double s : {0.2, 0.4, 0.6, 0.8}) {
      integrator->dense(s * step, y);
      worst = std::max(worst, std::hypot(y[0] - std::cos(s * step), y[1] + std::sin(s * step)));
    }
    return worst;
  };
  return std::log2(worst_error(2 * h) / worst_error(h)) - 1.0;
}

}  // namespace dense_order
