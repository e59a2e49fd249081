// rocking.simulation:record_steps, a partition of how the drivers step along
// a record (simulation.cpp's, chain_run.cpp's and columns_run.cpp's, through
// drive.cpp): its samples as the steps' breakpoints (MODEL.md 10: piecewise
// linear between them); full contact of a flexible structure stepped exactly
// from sample to sample (MODEL.md 3's linear system), sampled by the
// shortest period of the fixed-base modes that oscillate (MODEL.md 8's modes
// with the Rayleigh damping of MODEL.md 1); and a run's cost as the backend's
// and the exact steps'.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <memory>
#include <numbers>
#include <optional>
module rocking.simulation:record_steps;
import rocking.contact;
import rocking.integrator;
import rocking.ground_motion;

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

// The records' samples as breakpoints, computed when asked: a run holds no
// list of them. A vertical record sampled as the horizontal one (the
// components of one file) and no longer than it adds no breakpoints of its own.
inline ode::NextBreakpoint record_samples(const GroundMotion& ground) {
  const GroundMotion* vertical = ground.vertical();
  const bool own = vertical && !(vertical->sample_interval() > 0 && vertical->sample_interval() == ground.sample_interval() &&
                                 vertical->duration() <= ground.duration());
  return [&ground, vertical, own](double t) {
    return own ? std::min(ground.next_breakpoint(t), vertical->next_breakpoint(t)) : ground.next_breakpoint(t);
  };
}

// Full contact of a flexible model stepped exactly under a piecewise-linear
// record: x' = A x + b a_g(t) on the block [u; u'] that starts at `first` of
// a state of `size` (the rest constant), from sample to sample (up to 16
// spacings), with guards and peaks sampled 8 times in the shortest
// oscillating period; with `works`, the ground's and the viscous work
// integrated with the steps there and at works + 1 (the work on the devices
// does not grow in full contact). The model's elastic coordinates are its own
// (nodal or modal) and `first` holds them in that form.
inline std::unique_ptr<ode::Integrator> exact_full_contact(const ContactModel& m, Eigen::Index size, Eigen::Index first,
                                                           std::optional<Eigen::Index> works, const GroundMotion& ground,
                                                           long max_steps) {
  LinearPhase phase = full_contact_matrices(m);
  ode::LinearSystem system{size, first, std::move(phase.A), std::move(phase.b),
                           [&ground](double t) { return ground.acceleration(t); }, {}};
  if (works) {
    system.quadratures.push_back({*works, Eigen::MatrixXd(), std::move(phase.ground)});
    system.quadratures.push_back({*works + 1, std::move(phase.viscous), Eigen::VectorXd()});
  }
  ode::Options exact;
  exact.sample_spacing = shortest_period(m) / 8;
  exact.max_steps = max_steps;
  std::unique_ptr<ode::Integrator> steps = ode::make_exact_linear(std::move(system), exact);
  steps->set_breakpoints(record_samples(ground));
  return steps;
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
