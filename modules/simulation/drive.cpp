// What the drivers of chain_run.cpp and columns_run.cpp share (declared in
// simulation.cppm): the ground's acceleration (MODEL.md 14), the
// integrator's limits and breakpoints from the motion, the run's end and the
// limit on phase changes, a stop on request and a failure's statement (MODEL.md 6).
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <functional>
#include <string>
#include <memory>
#include <utility>
#include <fmt/format.h>
module rocking.simulation;
import :record_steps;
import rocking.errors;

namespace rocking {

GroundAcceleration ground_at(const GroundMotion& ground, const GroundMotion* vertical, double t) {
  return vertical ? GroundAcceleration{ground.acceleration(t), vertical->acceleration(t)}
                  : GroundAcceleration{ground.acceleration(t)};
}

ode::Options motion_tolerances(const RunOptions& o, const GroundMotion& ground, Eigen::Index steering) {
  ode::Options t = o.tolerances;
  t.max_step = std::min(t.max_step, ground.max_step());
  if (const GroundMotion* v = ground.vertical()) t.max_step = std::min(t.max_step, v->max_step());
  t.error_components = steering;
  return t;
}

std::unique_ptr<ode::Integrator> motion_integrator(ode::Backend backend, const GroundMotion& ground, Eigen::Index size,
                                                   ode::Rhs rhs, const ode::Options& tolerances, ode::LinearSolve stiff) {
  std::unique_ptr<ode::Integrator> integrator =
      ode::make_integrator(backend, size, std::move(rhs), tolerances, std::move(stiff));
  integrator->set_breakpoints(record_samples(ground));
  return integrator;
}

double run_end(const RunOptions& o, const GroundMotion& ground) { return o.duration > 0 ? o.duration : ground.duration(); }

void count_phase_change(long& events, const RunOptions& o, double t) {
  if (++events > o.max_events)
    throw RunError(fmt::format("phase change number {} at t = {:.9g} s exceeds the limit (chattering? raise "
                               "contact.theta_dot_min or the event limit)", events, t));
}

void check_stop(const RunOptions& o, double t) {
  if (o.stop && o.stop()) throw RunError(fmt::format("stopped at t = {:.6g} s on request", t));
}

void run_stated(RunResult& result, const std::function<void()>& body, const std::function<std::string()>& phase) {
  try {
    body();
  } catch (const ode::IntegrationError& e) {
    result.outcome = Outcome::failed;
    result.failure = fmt::format("{} ({})", e.what(), phase());
  } catch (const RunError& e) {
    result.outcome = Outcome::failed;
    result.failure = fmt::format("{} ({})", e.what(), phase());
  }
}

}  // namespace rocking
