// rosw held to rk45's events on a scene, both at the default tolerances
// (rtol 1e-4, atol 1e-7), under the scene's pulse or a record file, with
// CVODE at rtol 1e-10 (atol 1e-13) as the judge of what the default
// tolerance resolves at all. Include after <rocking/eigen.hpp>, doctest and
// close.hpp, and before any import.
//
// What is held, and to what:
// - the first uplift and first impact, of the run and of each joint: the
//   integrators locate them to round-off on their dense output, so they
//   differ by the global error of the state the guard reads, over the rate at
//   which the guard changes. A step-size control that holds each step's error
//   to rtol leaves a global error of a small multiple of rtol relative to the
//   motion, accumulated since the start (an impact inherits the error of the
//   uplift before it); ten times rtol of the time since the start is allowed.
//   Where rk45 itself misses the judge by more than that, rosw is held to the
//   judge.
// - the sequence of events (kind, joint, pivot) as far as rk45 agrees with
//   the judge: beyond that point the count depends on the tolerance (a joint
//   lifted by an impact to angles far below atol, a response so sensitive
//   that two integrations part) and is no standard for another integrator.
//   Where rk45 agrees with the judge to the end, the counts (the run's and
//   each joint's) are rk45's.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>
#include "watched_run.hpp"

namespace rosw_events {

struct Run {
  rocking::RunResult result;
  std::vector<rocking::Event> events;
};

// The scene under its pulse (record empty) or a record file, by `integrator`
// at rtol (atol = rtol / 1000: the defaults' ratio, 1e-4 and 1e-7).
inline Run run(const rocking::Scene& scene, const std::string& integrator, const std::string& record, double rtol = 1e-4) {
  rocking::RunSpec spec{.scene = scene};
  spec.motion.record = record;
  spec.solver.integrator = integrator;
  spec.solver.rtol = rtol;
  spec.solver.atol = rtol * 1e-3;
  spec.history.every = 1e9;  // no rows but the phase changes' own
  const rocking::PreparedRun p = rocking::prepare_run(spec);
  EventsAndRows watch;
  Run out;
  out.result = rocking::simulate(p.model, p.motion, p.options, &watch);
  out.events = std::move(watch.events);
  return out;
}

inline bool same_event(const rocking::Event& a, const rocking::Event& b) {
  return a.kind == b.kind && a.joint == b.joint && a.pivot == b.pivot;
}

// How many leading events a and b share (kind, joint, pivot).
inline std::size_t common_prefix(const std::vector<rocking::Event>& a, const std::vector<rocking::Event>& b) {
  std::size_t k = 0;
  while (k < a.size() && k < b.size() && same_event(a[k], b[k])) ++k;
  return k;
}

// rosw's time of an event against rk45's, or the judge's where rk45 misses
// the judge's by more than the tolerance; none where the judge has none.
inline void check_time(double rosw, double rk45, double judge, double tolerance) {
  if (std::isnan(judge)) {
    CHECK(std::isnan(rosw));
    return;
  }
  const bool rk45_resolves = !std::isnan(rk45) && std::abs(rk45 - judge) <= tolerance;
  CHECK(rosw == within(rk45_resolves ? rk45 : judge, tolerance));
}

// rosw against rk45 at the default tolerances, CVODE at 1e-10 the judge.
inline void check(const rocking::Scene& scene, const std::string& record) {
  constexpr double rtol = 1e-4, allowance = 10 * rtol;
  const Run rk = run(scene, "rk45", record), judge = run(scene, "cvode", record, 1e-10), ro = run(scene, "rosw", record);
  REQUIRE(ro.result.integrator == "rosw");
  REQUIRE(ro.result.outcome == rk.result.outcome);
  const rocking::RunResult &a = ro.result, &b = rk.result, &c = judge.result;
  auto check_first = [&](double rosw, double rk45, double t) { check_time(rosw, rk45, t, allowance * t); };
  check_first(a.first_uplift, b.first_uplift, c.first_uplift);
  check_first(a.first_impact, b.first_impact, c.first_impact);
  REQUIRE(a.joints.size() == c.joints.size());
  REQUIRE(b.joints.size() == c.joints.size());
  for (std::size_t j = 0; j < c.joints.size(); ++j) {
    CAPTURE(j);
    check_first(a.joints[j].first_uplift, b.joints[j].first_uplift, c.joints[j].first_uplift);
    check_first(a.joints[j].first_impact, b.joints[j].first_impact, c.joints[j].first_impact);
  }
  // The events rk45 resolves, and then the counts.
  const std::size_t resolved = common_prefix(rk.events, judge.events);
  const bool converged = resolved == rk.events.size() && resolved == judge.events.size();
  CHECK(common_prefix(ro.events, rk.events) >= resolved);
  if (converged) {
    CHECK(a.counts.uplifts == b.counts.uplifts);
    CHECK(a.counts.impacts == b.counts.impacts);
    for (std::size_t j = 0; j < b.joints.size(); ++j) {
      CAPTURE(j);
      CHECK(a.joints[j].uplifts == b.joints[j].uplifts);
      CHECK(a.joints[j].impacts == b.joints[j].impacts);
    }
  }
  MESSAGE(scene.name << std::string(record.empty() ? " (pulse)" : " (record)") << ": rk45 " << b.counts.uplifts
                     << " uplifts, " << b.counts.impacts << " impacts (" << b.stats.rhs << " rhs, " << b.wall_s
                     << " s); rosw " << a.counts.uplifts << ", " << a.counts.impacts << " (" << a.stats.rhs << " rhs, "
                     << a.wall_s << " s); CVODE at 1e-10 " << c.counts.uplifts << ", " << c.counts.impacts
                     << "; rk45 resolves " << resolved << " of its " << rk.events.size() << " events, rosw shares "
                     << common_prefix(ro.events, rk.events) << "; first uplift " << a.first_uplift << " (rk45 "
                     << b.first_uplift << ", CVODE " << c.first_uplift << "), first impact " << a.first_impact
                     << " (rk45 " << b.first_impact << ", CVODE " << c.first_impact << ")");
}

}  // namespace rosw_events
