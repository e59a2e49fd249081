// Mass, first moment (sum m z) and pivot inertia about joint j's corner of
// everything above joint j of a chain (rocking.chain's ChainData): the
// closed forms' ingredients (MODEL.md 15). A template on the data type
// because headers come before module imports (TOOLCHAIN.md pitfall 2).
#pragma once
#include <gsl/gsl_integration.h>
#include <cmath>
#include <cstddef>

struct SegmentSums {
  double J = 0, mass = 0, first = 0;
};

template <class Data>
SegmentSums sums_above(const Data& d, int j) {
  SegmentSums out;
  const auto& base = d.segments[static_cast<std::size_t>(j)];
  const double h = base.base_height, B = base.half_width;
  for (std::size_t k = static_cast<std::size_t>(j); k < d.segments.size(); ++k) {
    const auto& s = d.segments[k];
    out.mass += s.base_mass + s.masses.sum();
    out.first += s.base_mass * (s.base_height - h) + s.masses.dot((s.heights.array() - h).matrix());
    out.J += s.base_mass * (std::pow(s.base_height - h, 2) + B * B) +
             (s.masses.array() * ((s.heights.array() - h).square() + B * B)).sum();
  }
  return out;
}

// The time from a release at rest at th0 to the first impact of what stands
// above a joint (rigid, rocking about a corner B from its centre line) by
// quadrature: 1/2 J_p th'^2 = V(th0) - V(th), V = g (M B sin th + S cos th),
// t = int_0^th0 dth / sqrt(2 (V0 - V) / J_p); th = th0 - x^2 removes the
// endpoint singularity, and V0 - V = 2 g sin(x^2/2) (M B cos(th0 - x^2/2) -
// S sin(th0 - x^2/2)). GSL QAG (Gauss 61) to a relative 1e-13.
inline double release_to_impact_time(double th0, const SegmentSums& above, double B, double g) {
  struct Params {
    double th0, M, S, B, J, g;
  } prm{th0, above.mass, above.first, B, above.J, g};
  gsl_function F{[](double x, void* p) {
                   const auto& q = *static_cast<Params*>(p);
                   const double half = 0.5 * x * x, mid = q.th0 - half;
                   const double sinc = half > 0 ? std::sin(half) / half : 1.0;  // sin(x^2/2) / (x^2/2)
                   const double bracket = q.M * q.B * std::cos(mid) - q.S * std::sin(mid);
                   return 2.0 / std::sqrt(2.0 * q.g * sinc * bracket / q.J);
                 },
                 &prm};
  gsl_integration_workspace* iw = gsl_integration_workspace_alloc(1000);
  double t = 0, err = 0;
  gsl_integration_qag(&F, 0.0, std::sqrt(th0), 0.0, 1e-13, 1000, GSL_INTEG_GAUSS61, iw, &t, &err);
  gsl_integration_workspace_free(iw);
  return t;
}
