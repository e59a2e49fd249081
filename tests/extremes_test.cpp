// The edges of the parameter space (issue 7): each run ends with a correct
// result or a clear diagnostic, never a hang or a silent NaN.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
#include <numbers>
#include <string>
#include <vector>
import rocking.simulation;
import rocking.scene;

using namespace rocking;

namespace {

Scene chimney(std::vector<std::string> overrides = {}) { return load_default_scene(overrides); }

GroundMotion pulse() { return default_ground_motion(chimney()); }

// A finished run: no NaN anywhere in what it reports.
void check_sound(const RunResult& r) {
  CAPTURE(r.failure);
  CHECK(r.outcome != Outcome::failed);
  for (double p : r.peaks) CHECK(std::isfinite(p));
  CHECK(r.final_state.allFinite());
}

// A sampled ground motion: a sum of two sines for `seconds`, every dt.
GroundMotion sampled(double seconds, double dt, double amplitude) {
  std::vector<double> t, a;
  const auto n = static_cast<std::size_t>(std::llround(seconds / dt));
  for (std::size_t i = 0; i <= n; ++i) {
    const double ti = static_cast<double>(i) * dt;
    t.push_back(ti);
    a.push_back(amplitude * (std::sin(2 * std::numbers::pi * 1.3 * ti) + 0.5 * std::sin(2 * std::numbers::pi * 3.1 * ti)));
  }
  return GroundMotion::from_samples("two sines", t, a);
}

RunResult run(const Scene& scene, const GroundMotion& g, double rtol = 1e-6, double duration = 8.0) {
  RunOptions o;
  o.tolerances.rtol = rtol;
  o.duration = duration;
  o.initial = {scene.initial.theta, scene.initial.theta_dot, scene.initial.u, scene.initial.u_dot};
  return simulate(make_contact_model(scene, true), g, o);
}

}  // namespace

TEST_CASE("r = 1 and r = 0: the chimney rocks on, or stops at its first impact") {
  const RunResult elastic = run(chimney({"contact.restitution=1.0"}), pulse());
  check_sound(elastic);
  const RunResult plastic = run(chimney({"contact.restitution=0.0"}), pulse());
  check_sound(plastic);
  // r = 0 takes all the rocking velocity at every impact: less rocking, fewer impacts.
  CHECK(elastic.counts.impacts > 2 * plastic.counts.impacts);
  CHECK(plastic.peak(Quantity::theta) < 0.5 * elastic.peak(Quantity::theta));
  // The rigid block with r = 1 loses no energy at its impacts.
  const Scene block = load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml",
                                 {"contact.restitution=1.0"});
  RunOptions o;
  o.tolerances.rtol = 1e-10;
  o.duration = 5;
  o.initial.theta = 0.1;
  const RunResult r = simulate(make_contact_model(block, true), GroundMotion::pulse(PulseShape::one_sine, 0, 1), o);
  CHECK(r.counts.impacts > 5);
  CHECK(std::abs(r.energy.impacts) < 1e-9 * r.energy.initial);
}

TEST_CASE("theta_dot_min = 0: the rigid block's chattering ends with a bounded number of events, reported") {
  // Without the Eq. 8 threshold the impacts never stop: the block chatters
  // about theta = 0 with ever smaller phases (measured: 72,000 impacts in 30 s).
  // The event limit turns that into a diagnostic instead of a hang.
  const Scene block = load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml",
                                 {"contact.theta_dot_min=0.0"});
  RunOptions o;
  o.duration = 30;
  o.initial.theta = 0.1;
  o.max_events = 5000;
  const RunResult r = simulate(make_contact_model(block, false), GroundMotion::pulse(PulseShape::one_sine, 0, 1), o);
  REQUIRE(r.outcome == Outcome::failed);
  CHECK(r.failure.find("phase change number 5001") != std::string::npos);
  CHECK(r.failure.find("chattering") != std::string::npos);
  CHECK(r.counts.impacts >= 4999);  // what it did is reported
  CHECK(r.t_end < 30.0);
  CHECK(r.final_state.allFinite());
  // With the threshold (the default 0.0015 rad/s) the same block settles.
  const RunResult settled =
      simulate(make_contact_model(load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml"), false),
               GroundMotion::pulse(PulseShape::one_sine, 0, 1), o);
  CHECK(settled.outcome == Outcome::completed);
  CHECK(settled.final_phase == Phase::full_contact());
  CHECK(settled.counts.impacts < 100);
}

TEST_CASE("scale factor 50 overturns the chimney, reported as an outcome") {
  const RunResult r = run(chimney(), pulse().scaled(50.0));
  check_sound(r);
  CHECK(r.outcome == Outcome::overturned);
  CHECK(r.peak(Quantity::theta_over_alpha) == close_to(1.0, 1e-6));
}

TEST_CASE("EI x 0.01 and x 100, and a damper five times thicker, run soundly") {
  for (const char* set : {"structure.EI_scale=0.01", "structure.EI_scale=100", "damper.thickness=5"}) {
    CAPTURE(set);
    const RunResult r = run(chimney({set}), pulse());
    check_sound(r);
    CHECK(std::abs(r.energy.residual()) < 1e-3 * r.energy.ground);
  }
}

TEST_CASE("a record sampled every 1e-4 s and a 10-minute record run soundly, every sample a breakpoint") {
  const RunResult fine = run(chimney(), sampled(5.0, 1e-4, 2.0), 1e-6, 0.0);
  check_sound(fine);
  CHECK(fine.stats.steps >= 50000);  // never steps across a sample
  const RunResult coarse = run(chimney(), sampled(5.0, 1e-2, 2.0), 1e-6, 0.0);
  // The same two sines at 1e-4 s and at 1e-2 s: linear interpolation of the
  // coarse samples departs from the 3.1 Hz sine by up to (2 pi 3.1 0.01)^2 / 8
  // = 0.5 % of its amplitude, the bound stated here.
  CHECK(fine.peak(Quantity::delta_t) == close_to(coarse.peak(Quantity::delta_t), 5e-3));
  const RunResult long_record = run(chimney(), sampled(600.0, 0.01, 2.0), 1e-6, 0.0);
  check_sound(long_record);
  CHECK(long_record.t_end == close_to(600.0, 1e-12));
}

TEST_CASE("rtol 1e-12 runs to the end and agrees with rtol 1e-9") {
  const RunResult tight = run(chimney(), pulse(), 1e-12);
  check_sound(tight);
  const RunResult loose = run(chimney(), pulse(), 1e-9);
  CHECK(tight.counts.impacts == loose.counts.impacts);
  CHECK(tight.peak(Quantity::delta_t) == close_to(loose.peak(Quantity::delta_t), 1e-6));
}

TEST_CASE("released beyond its overturning angle, a structure has overturned at t = 0") {
  // The rigid block's alpha is 0.269 rad; the chimney's alpha_cg 0.216 rad.
  // A tilt past it never crosses the overturning guard: the run must say so
  // at once, not integrate a body falling through the floor.
  const std::string block_file = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  for (const Scene& scene : {load_scene(block_file, {"initial.theta=0.3", "excitation.kind=none"}),
                             load_scene(block_file, {"initial.theta=-0.28", "initial.theta_dot=-1", "excitation.kind=none"}),
                             chimney({"initial.theta=0.5", "excitation.kind=none", "excitation.duration=4"})}) {
    CAPTURE(scene.initial.theta);
    const RunResult r = run(scene, default_ground_motion(scene), 1e-6, 4.0);
    CHECK(r.outcome == Outcome::overturned);
    CHECK(r.t_end == 0.0);
    CHECK(r.final_theta == scene.initial.theta);
  }
  // Just inside the angle, released from rest, the block rocks back and completes.
  const Scene inside = load_scene(block_file, {"initial.theta=0.2", "excitation.kind=none"});
  const RunResult r = run(inside, default_ground_motion(inside), 1e-6, 4.0);
  CHECK(r.outcome == Outcome::completed);
  CHECK(r.counts.impacts > 0);
}

TEST_CASE("plates thin enough to vanish leave the chimney rocking as it does without them") {
  // thickness 1e-3: stiffness x 1e-9 (0.01 N/m), yield elongation x 1e3
  // (beyond any chord): the plates carry no force worth the name, so the run
  // is the run without dampers (same events; peaks to 1e-5 of their size).
  const RunResult thin = run(chimney({"damper.thickness=1e-3"}), pulse(), 1e-8);
  const RunResult none = run(chimney({"damper.enabled=false"}), pulse(), 1e-8);
  check_sound(thin);
  CHECK(none.counts.uplifts > 0);
  CHECK(thin.counts.uplifts == none.counts.uplifts);
  CHECK(thin.counts.impacts == none.counts.impacts);
  for (Quantity q : {Quantity::theta, Quantity::delta_t, Quantity::delta_e, Quantity::base_moment})
    CHECK(thin.peak(q) == close_to(none.peak(q), 1e-5));
  CHECK(thin.peak(Quantity::damper_F) < 1e-3);  // [N]: 0.01 N/m over a few centimetres
}

TEST_CASE("[excitation] scale scales a pulse as it scales a record") {
  // The scene's factor on its pulse is the same run as the pulse scaled by
  // the program's --scale (GroundMotion::scaled): x2, and x-1 (the pulse
  // reversed, which rocks the chimney about the other pivot as far).
  const RunResult scene_x2 = run(chimney({"excitation.scale=2"}), default_ground_motion(chimney({"excitation.scale=2"})));
  const RunResult pulse_x2 = run(chimney(), pulse().scaled(2));
  CHECK(scene_x2.peaks == pulse_x2.peaks);
  CHECK(scene_x2.counts.uplifts == pulse_x2.counts.uplifts);
  CHECK(excitation_scale(chimney({"excitation.scale=2"})) == 2);
  const RunResult x1 = run(chimney(), pulse());
  CHECK(scene_x2.peak(Quantity::theta) > 1.5 * x1.peak(Quantity::theta));  // not the unscaled run
  const RunResult reversed = run(chimney({"excitation.scale=-1"}), default_ground_motion(chimney({"excitation.scale=-1"})));
  CHECK(reversed.peak(Quantity::theta) == close_to(x1.peak(Quantity::theta), 1e-9));
  // The mirror image throughout: the same events at the same times, and a
  // final state whose every component is the other run's, of the opposite
  // sign (tilt, elastic displacements and rates, the devices' state) or of
  // the same (the energy balance's work terms). Not a final tilt of 0 against
  // -0: the chimney comes to rest in full contact, its elastic state moving.
  CHECK(reversed.counts.impacts == x1.counts.impacts);
  CHECK(reversed.first_uplift == close_to(x1.first_uplift, 1e-9));
  REQUIRE(x1.final_state.size() == reversed.final_state.size());
  int opposite = 0;
  for (Eigen::Index i = 0; i < x1.final_state.size(); ++i) {
    CAPTURE(i);
    const double a = x1.final_state[i], b = reversed.final_state[i];
    const bool odd = std::abs(a + b) <= 1e-9 * std::abs(a), even = std::abs(a - b) <= 1e-9 * std::abs(a);
    CHECK((odd || even));
    opposite += odd && a != 0;
  }
  CHECK(opposite >= 4);  // the elastic state, at least, moves and is mirrored
}
