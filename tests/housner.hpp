// Housner's closed form by quadrature (MODEL.md 6): the time a rigid block
// released at rest from theta0 takes to reach theta = 0, for the tests of free
// rocking. Include after <rocking/eigen.hpp> and before any import.
#pragma once
#include <gsl/gsl_integration.h>
#include <cmath>
import rocking.geometry;

namespace housner {

using rocking::Structure;
using rocking::pivot_inertia;

// Gravity potential of a rigid block tilted by theta about a pivot (u = 0):
// V = g (B (1'M1 + m0) sin(theta) + H'M1 (cos(theta) - 1)).
inline double rigid_potential(const Structure& s, double g, double theta) {
  const double BM = s.half_width * (s.masses.sum() + s.base_mass), HM = s.heights.dot(s.masses);
  return g * (BM * std::sin(theta) + HM * (std::cos(theta) - 1.0));
}

struct FallParams {
  const Structure* s;
  double g, theta0;
};

// Housner: released at rest from theta0, the block reaches theta = 0 after
// t = integral_0^theta0 dtheta / sqrt(2 (V(theta0) - V(theta)) / J_p).
// The 1/sqrt singularity at theta0 is the weight (theta0 - theta)^(-1/2) of GSL's QAWS.
inline double housner_quarter_period(const Structure& s, double g, double theta0) {
  FallParams p{&s, g, theta0};
  gsl_function f;
  f.function = [](double th, void* vp) {
    // V(theta0) - V(theta) = g 2 sin(x/2) (BM cos(m) - HM sin(m)), x = theta0 - theta,
    // m = (theta0 + theta) / 2, written without cancellation and divided by x.
    const auto* p = static_cast<FallParams*>(vp);
    const Structure& s = *p->s;
    const double BM = s.half_width * (s.masses.sum() + s.base_mass), HM = s.heights.dot(s.masses);
    const double x = p->theta0 - th, mid = 0.5 * (p->theta0 + th);
    const double sinc = x == 0 ? 1.0 : std::sin(0.5 * x) / (0.5 * x);
    const double drop_over_x = p->g * sinc * (BM * std::cos(mid) - HM * std::sin(mid));
    return std::sqrt(pivot_inertia(s) / (2.0 * drop_over_x));
  };
  f.params = &p;
  gsl_integration_qaws_table* table = gsl_integration_qaws_table_alloc(0.0, -0.5, 0, 0);
  gsl_integration_workspace* ws = gsl_integration_workspace_alloc(200);
  double result = 0, error = 0;
  gsl_integration_qaws(&f, 0.0, theta0, table, 1e-14, 1e-13, 200, ws, &result, &error);
  gsl_integration_workspace_free(ws);
  gsl_integration_qaws_table_free(table);
  return result;
}

}  // namespace housner

using housner::housner_quarter_period;
using housner::rigid_potential;
