// The first impact of a rigid frame (or a single column) released at rest
// from a tilt (MODEL.md 16's closed form), by quadrature: what
// tests/columns_test.cpp and tests/columns_run_test.cpp hold the engine and
// the program's run to.
#pragma once
#include <gsl/gsl_integration.h>
#include <cmath>

// First impact of free rocking from rest at theta0 > 0 under
// theta'' = -p2 sin(alpha - theta): t = int_0^theta0 dth / sqrt(2 p2 (cos(alpha -
// theta0) - cos(alpha - th))); th = theta0 - w^2 removes the endpoint singularity:
// t = int_0^sqrt(theta0) 2 dw / sqrt(2 p2 sin(alpha - theta0 + w^2/2) sinc(w^2/2)).
inline double quadrature_impact_time(double alpha, double p2, double theta0) {
  struct P {
    double a, p2, t0;
  } par{alpha, p2, theta0};
  gsl_function F{[](double w, void* v) {
                   const P& p = *static_cast<P*>(v);
                   const double x = 0.5 * w * w;
                   const double sinc = x > 0 ? std::sin(x) / x : 1.0;
                   return 2.0 / std::sqrt(2.0 * p.p2 * std::sin(p.a - p.t0 + x) * sinc);
                 },
                 &par};
  gsl_integration_workspace* ws = gsl_integration_workspace_alloc(1000);
  double t = 0, err = 0;
  gsl_integration_qag(&F, 0.0, std::sqrt(theta0), 0.0, 1e-13, 1000, GSL_INTEG_GAUSS61, ws, &t, &err);
  gsl_integration_workspace_free(ws);
  return t;
}
