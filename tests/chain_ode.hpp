// A generic integrator for the chain tests: GSL's rk8pd (Prince-Dormand 8(9))
// with tight tolerances, independent of the project's integrators, and the
// first sign change of a guard located by Brent's method on re-integration
// from the last accepted step.
#pragma once
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_roots.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <vector>

namespace chain_ode {

using Rhs = std::function<void(double t, const double* y, double* f)>;
using Guard = std::function<double(double t, const double* y)>;
using Observe = std::function<void(double t, const double* y)>;

struct System {
  Rhs rhs;
  static int call(double t, const double* y, double* f, void* p) {
    static_cast<System*>(p)->rhs(t, y, f);
    return GSL_SUCCESS;
  }
};

struct Crossing {
  bool found = false;
  double t = 0;
  std::vector<double> y;
};

// From (t0, y0) to t_end or the first time guard turns negative (guards are
// written positive while the phase lasts; one that starts at zero, as a joint
// that has just opened, is watched from there).
inline Crossing integrate(const Rhs& rhs, double t0, std::vector<double> y0, double t_end, const Guard& guard,
                          const Observe& observe = {}, double rtol = 1e-13, double atol = 1e-15,
                          double max_step = 0.01) {
  System sys{rhs};
  const std::size_t n = y0.size();
  gsl_odeiv2_system ode{&System::call, nullptr, n, &sys};
  gsl_odeiv2_step* step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, n);
  gsl_odeiv2_control* control = gsl_odeiv2_control_y_new(atol, rtol);
  gsl_odeiv2_evolve* evolve = gsl_odeiv2_evolve_alloc(n);
  double t = t0, h = 1e-4;
  std::vector<double> y = y0, y_prev;
  Crossing out;
  while (t < t_end) {
    const double t_prev = t;
    y_prev = y;
    const double target = std::min(t_end, t + max_step);
    if (gsl_odeiv2_evolve_apply(evolve, control, step, &ode, &t, target, &h, y.data()) != GSL_SUCCESS)
      throw std::runtime_error("rk8pd failed");
    if (guard && guard(t, y.data()) < 0) {
      // Brent on g(tau) = guard(y(tau)), y from (t_prev, y_prev)
      struct Locate {
        gsl_odeiv2_system* ode;
        double t0;
        const std::vector<double>* y0;
        const Guard* guard;
        std::vector<double> y;
        double rtol, atol;
        static double f(double tau, void* p) {
          auto* l = static_cast<Locate*>(p);
          l->y = *l->y0;
          double tt = l->t0;
          if (tau > tt) {
            gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(l->ode, gsl_odeiv2_step_rk8pd, (tau - tt) / 4, l->atol, l->rtol);
            gsl_odeiv2_driver_apply(d, &tt, tau, l->y.data());
            gsl_odeiv2_driver_free(d);
          }
          return (*l->guard)(tau, l->y.data());
        }
      } loc{&ode, t_prev, &y_prev, &guard, {}, rtol, atol};
      gsl_function F{&Locate::f, &loc};
      gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
      double lo = t_prev, hi = t;
      const bool at_start = guard(t_prev, y_prev.data()) <= 0;  // back at once
      if (!at_start) gsl_root_fsolver_set(s, &F, t_prev, t);
      for (int it = 0; it < 200 && !at_start; ++it) {
        gsl_root_fsolver_iterate(s);
        lo = gsl_root_fsolver_x_lower(s);
        hi = gsl_root_fsolver_x_upper(s);
        if (gsl_root_test_interval(lo, hi, 0.0, 1e-15) == GSL_SUCCESS) break;
      }
      gsl_root_fsolver_free(s);
      out.found = true;
      out.t = at_start ? t_prev : 0.5 * (lo + hi);
      Locate::f(out.t, &loc);
      out.y = loc.y;
      break;
    }
    if (observe) observe(t, y.data());
  }
  if (!out.found) {
    out.t = t;
    out.y = y;
  }
  gsl_odeiv2_evolve_free(evolve);
  gsl_odeiv2_control_free(control);
  gsl_odeiv2_step_free(step);
  return out;
}

}  // namespace chain_ode
