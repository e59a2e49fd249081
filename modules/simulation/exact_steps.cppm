// rocking.simulation:exact_steps, a partition of what the drivers that step
// full contact exactly share (simulation.cpp's, columns_run.cpp's): the
// shortest period of the fixed-base modes that oscillate (MODEL.md 8's modes
// with the Rayleigh damping of MODEL.md 1), which sets how densely guards and
// peaks are sampled, and a run's cost as the backend's and the exact steps'.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <numbers>
module rocking.simulation:exact_steps;
import rocking.contact;
import rocking.integrator;

namespace rocking {

// The shortest period among the fixed-base modes that oscillate, those with
// Rayleigh damping ratio a0 / (2 omega) + a1 omega / 2 below 1 [s]. An
// overdamped mode (omega above about 2 / a1: many of a finely meshed
// structure's) only relaxes and turns nothing inside its period; the modes
// that oscillate set how densely guards and peaks are sampled.
inline double shortest_period(const ContactModel& m) {
  const Rayleigh& ray = m.body.matrices.rayleigh;
  const Eigen::VectorXd& omega = m.body.matrices.fixed_base.omega;
  double fastest = 0;
  for (double w : omega)
    if (0.5 * (ray.a0 / w + ray.a1 * w) < 1.0) fastest = std::max(fastest, w);
  return 2 * std::numbers::pi / (fastest > 0 ? fastest : omega.maxCoeff());
}

// The backend's counts with the exact steps' added (none: the backend's).
inline ode::Stats run_stats(const ode::Integrator& backend, const ode::Integrator* exact) {
  ode::Stats s = backend.stats();
  if (exact == nullptr) return s;
  const ode::Stats e = exact->stats();
  s.rhs += e.rhs;
  s.steps += e.steps;
  s.rejected += e.rejected;
  s.events += e.events;
  s.guards += e.guards;
  return s;
}

}  // namespace rocking
