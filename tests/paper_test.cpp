// The paper's checks on the chimney with the real records (issue 4,
// MODEL.md 10): the three integrators agree on El Centro; El Centro's peak top
// displacement is of the order of the paper's ~160 mm; the Papanui stand-in
// for the Canterbury Aero Club record rocks modestly unscaled and appreciably
// at scale 3, where the damper changes the rocking angle but little the forces.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
#include <string>
#include <vector>
#include "records.hpp"
import rocking.simulation;
import rocking.scene;
import rocking.records;

using namespace rocking;

namespace {

RunResult run_chimney(const std::string& record, double scale, std::vector<std::string> overrides = {},
                      ode::Backend backend = ode::Backend::rk45, double rtol = 1e-8) {
  const Scene scene = load_default_scene(overrides);
  RecordOptions ro;
  ro.scale = scale;
  RunOptions o;
  o.backend = backend;
  o.tolerances.rtol = rtol;
  o.tolerances.atol = 1e-12;
  return simulate(make_contact_model(scene, false), read_record(record, ro), o);
}

}  // namespace

TEST_CASE("rk45, CVODE and ARKODE give the same El Centro chimney peaks to 1e-6 at tight tolerance") {
  // Each at rtol 1e-10 (CVODE 1e-11): their global errors, grown over 77
  // impacts that restart the motion from located events, stay within
  // 1e4 rtol, so two of them agree to 1e-6.
  const auto dir = records_dir();
  if (!dir) return;
  const std::string record = *dir + "/elcentro_1940_ns.at2";
  const RunResult rk45 = run_chimney(record, 1.0, {}, ode::Backend::rk45, 1e-10);
  const RunResult arkode = run_chimney(record, 1.0, {}, ode::Backend::arkode, 1e-10);
  const RunResult cvode = run_chimney(record, 1.0, {}, ode::Backend::cvode, 1e-11);
  REQUIRE(rk45.outcome == Outcome::completed);
  CHECK(rk45.counts.impacts > 10);
  for (const RunResult* other : {&arkode, &cvode}) {
    CAPTURE(other->integrator);
    CHECK(other->counts.uplifts == rk45.counts.uplifts);
    CHECK(other->counts.impacts == rk45.counts.impacts);
    for (Quantity q : peak_quantities) {
      CAPTURE(info(q).name);
      CHECK(other->peak(q) == close_to(rk45.peak(q), 1e-6));
    }
  }
}

TEST_CASE("El Centro unscaled: a peak total top displacement of the order of the paper's ~160 mm") {
  const auto dir = records_dir();
  if (!dir) return;
  // Two versions of the same N-S record (SOURCES.md): 134 mm and 161 mm measured.
  // The paper states "~160 mm" for a version it does not name: the PEER
  // version within 5 % (the figure's reading), the classic one within 20 %
  // (its own processing lowers the peak).
  const RunResult classic = run_chimney(*dir + "/elcentro_1940_ns.at2", 1.0);
  const RunResult peer = run_chimney(*dir + "/elcentro_1940_ns_peer_ielc180.at2", 1.0);
  CHECK(classic.top_total_mm == close_to(160.0, 0.2));
  CHECK(peer.top_total_mm == close_to(160.0, 0.05));
  CHECK(classic.counts.uplifts > 0);
}

TEST_CASE("Papanui stand-in: modest rocking unscaled, appreciable at x3, where the damper acts on theta, not forces") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string record = *dir + "/christchurch2011_pphs_s57e.at2";
  const RunResult unscaled = run_chimney(record, 1.0);
  const RunResult damped = run_chimney(record, 3.0);
  const RunResult undamped = run_chimney(record, 3.0, {"damper.enabled=false"});
  CHECK(unscaled.counts.uplifts > 0);
  CHECK(unscaled.peak(Quantity::theta_over_alpha) < 0.02);
  CHECK(damped.peak(Quantity::theta_over_alpha) > 0.05);
  // The damper cuts the rocking angle by more than half ...
  CHECK(damped.peak(Quantity::theta) < 0.5 * undamped.peak(Quantity::theta));
  // ... and changes the base and mid-height forces by less than 10 %.
  for (Quantity q : {Quantity::base_shear, Quantity::base_moment, Quantity::mid_shear, Quantity::mid_moment}) {
    CAPTURE(info(q).name);
    CHECK(damped.peak(q) == close_to(undamped.peak(q), 0.1));
  }
}
