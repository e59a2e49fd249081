module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.integrator;

namespace rocking::ode {

namespace {
std::string describe(IntegrationError::Kind kind) {
  switch (kind) {
    case IntegrationError::Kind::step_size_underflow: return "step size underflow";
    case IntegrationError::Kind::max_steps: return "maximum number of steps reached";
    case IntegrationError::Kind::non_finite_state: return "non-finite state";
    case IntegrationError::Kind::backend: return "integrator failure";
  }
  return "integrator failure";
}
}  // namespace

IntegrationError::IntegrationError(Kind kind, double t, const std::string& detail)
    : RunError(fmt::format("{} at t = {:.9g} s{}{}", describe(kind), t, detail.empty() ? "" : ": ", detail)),
      kind_(kind),
      time_(t) {}

NextBreakpoint breakpoint_list(std::vector<double> times) {
  std::sort(times.begin(), times.end());
  return [times = std::move(times)](double t) {
    const auto it = std::upper_bound(times.begin(), times.end(), t);
    return it == times.end() ? std::numeric_limits<double>::infinity() : *it;
  };
}

int guard_samples(double h, double sample_spacing, int fewest, int most) {
  if (!std::isfinite(sample_spacing)) return 4;
  return static_cast<int>(std::clamp(std::ceil(h / sample_spacing - 1e-9), static_cast<double>(fewest),
                                     static_cast<double>(most)));
}

StepReport advance(Integrator& integrator, double t_end) {
  StepReport report{Stop::limit, integrator.time()};
  while (integrator.time() < t_end) {
    report = integrator.step(t_end);
    if (report.reason == Stop::event) return report;
  }
  report.reason = Stop::limit;
  report.t = integrator.time();
  return report;
}

}  // namespace rocking::ode
