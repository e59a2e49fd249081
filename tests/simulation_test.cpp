// rocking.simulation: the acceptance physics of issue 4 that needs no record.
// Energy conservation and balance, the rigid block against Housner's closed
// form (GSL quadrature), decay by r per impact, overturning, and the stiff
// flexible structure converging to the rigid block; a peak that falls between
// samples, against the closed form of a damped mode.
#include <numbers>
#include <variant>
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <iomanip>
#include <string>
#include <vector>
#include "housner.hpp"
#include "records.hpp"
#include "spread_nodes.hpp"
#include "tight_run.hpp"
import rocking.simulation;
import rocking.scene;
import rocking.records;

using namespace rocking;

namespace {

Scene chimney(std::vector<std::string> overrides = {}) { return load_default_scene(overrides); }

Scene rigid_block(std::vector<std::string> overrides = {}) {
  return load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml", overrides);
}

GroundMotion still_ground() { return GroundMotion::pulse(PulseShape::one_sine, 0.0, 1.0); }

// --set text adding a central vertical tendon (P0 + k e) over the chimney's
// height, breaking at e_u (0: never).
std::string fmt_tendon(double P0, double k, double e_u) {
  std::string text = "device+={name=\"tendon\", kind=\"elastic\", at=0, kinematics=\"vertical\", free_length=33, P0=" +
                     std::to_string(P0) + ", k=" + std::to_string(k);
  if (e_u > 0) text += ", capacity=" + std::to_string(e_u);
  return text + "}";
}

// Keeps every response it is given.
struct Recorder : Observer {
  std::vector<Response> rows;
  void record(const Response& r) override { rows.push_back(r); }
};

}  // namespace

TEST_CASE("free undamped rocking with no damper conserves energy to 1e-8 over 10 s at rtol 1e-12") {
  // Released from alpha/2 with no damping: every loss is an impact, and the
  // impacts' losses are computed from the states on either side of the reset.
  const ContactModel m = make_contact_model(chimney({"structure.damping_ratio=0.0", "damper.enabled=false"}), true);
  const RunResult r = simulate(m, still_ground(), tight(10.0, 0.5 * slenderness(m.body.structure)));
  REQUIRE(r.outcome == Outcome::completed);
  CHECK(r.counts.impacts >= 2);  // not one long phase: impacts and rocking about both pivots
  const EnergyBalance& e = r.energy;
  CHECK(e.initial > 1e4);
  CHECK(e.ground == 0.0);
  CHECK(std::abs(e.residual()) / e.initial < 1e-8);
}

TEST_CASE("with viscous damping, a damper and a ground motion the energy balance closes to 1e-6 of the input") {
  const ContactModel m = make_contact_model(chimney(), true);
  RunOptions o = tight(8.0);
  o.tolerances.rtol = 1e-10;
  const RunResult r = simulate(m, default_ground_motion(chimney()), o);
  REQUIRE(r.outcome == Outcome::completed);
  CHECK(r.counts.uplifts >= 1);
  CHECK(r.peak(Quantity::damper_d) > std::get<BoucWenLaw>(m.devices[0].law).d_y);  // the damper yields
  const EnergyBalance& e = r.energy;
  CHECK(e.viscous > 0);
  CHECK(e.damper > 0);
  CHECK(e.impacts > 0);
  CHECK(std::abs(e.residual()) < 1e-6 * e.ground);
}

TEST_CASE("rigid block: the free-rocking quarter period matches Housner's integral to 1e-8") {
  const Scene scene = rigid_block();
  const ContactModel m = make_contact_model(scene, false);
  for (double fraction : {0.1, 0.5, 0.9}) {
    const double theta0 = fraction * slenderness(scene.structure);
    const RunResult r = simulate(m, still_ground(), tight(3.0, theta0));
    const double expected = housner_quarter_period(scene.structure, m.body.g, theta0);
    CAPTURE(fraction);
    REQUIRE(r.counts.impacts >= 1);
    CHECK(r.first_impact == close_to(expected, 1e-8));
  }
}

TEST_CASE("a scene's [initial] tilt with excitation kind none: the first impact at Housner's quarter period to 1e-8") {
  const Scene plain = rigid_block();
  const double theta0 = 0.5 * slenderness(plain.structure);
  const Scene scene = rigid_block({"excitation.kind=none", "excitation.duration=3",
                                   "initial.theta=" + std::to_string(theta0)});
  REQUIRE(scene.excitation.none);
  RunOptions o = tight(scene.excitation.duration);
  o.initial = {scene.initial.theta, scene.initial.theta_dot, scene.initial.u, scene.initial.u_dot};
  const ContactModel m = make_contact_model(scene, false);
  const RunResult r = simulate(m, default_ground_motion(scene), o);
  REQUIRE(r.counts.impacts >= 1);
  CHECK(r.counts.uplifts == 0);  // released rocking: no uplift event
  CHECK(r.first_impact == within(housner_quarter_period(scene.structure, m.body.g, scene.initial.theta), 1e-8));
}

TEST_CASE("initial elastic displacements: the chimney on a fixed base, released from its first mode, vibrates freely") {
  const Scene base = chimney({"contact.rocking=false", "structure.damping_ratio=0.0"});
  const ContactModel m = make_contact_model(base, false);
  const Eigen::VectorXd phi = m.body.matrices.fixed_base.shapes.col(0);
  std::vector<std::string> set = {"contact.rocking=false", "structure.damping_ratio=0.0", "excitation.kind=none",
                                  "excitation.duration=2"};
  std::string u = "initial.u=[";
  // Written with 17 digits: a release rounded (to_string's 6 decimals) would
  // mix in the other modes at 1e-4 of the first.
  for (Eigen::Index i = 0; i < phi.size(); ++i) {
    std::ostringstream digits;
    digits << std::setprecision(17) << 0.01 * phi[i] / phi[phi.size() - 1];
    u += (i ? "," : "") + digits.str();
  }
  set.push_back(u + "]");
  const Scene scene = chimney(set);
  REQUIRE(scene.initial.u.size() == 4);
  RunOptions o = tight(2.0);
  o.initial.u = scene.initial.u;
  // In nodal and in modal coordinates (where the release is one mode's amplitude)
  std::vector<RunResult> runs;
  for (ElasticCoordinates c : {ElasticCoordinates::nodal, ElasticCoordinates::modal}) {
    o.coordinates = c;
    runs.push_back(simulate(make_contact_model(scene, false), default_ground_motion(scene), o));
    const RunResult& r = runs.back();
    REQUIRE(r.outcome == Outcome::completed);
    // Free vibration in one mode: the top never exceeds where it was released
    // (rtol 1e-12 over 4.35 periods: the integration's error, a few 1e-10).
    CHECK(r.peak(Quantity::delta_e) * scene.structure.heights[3] == close_to(scene.initial.u[3], 1e-8));
    // and follows u_N cos(omega_1 t) (2 s is 4.35 periods); the final state is nodal.
    const double w1 = m.body.matrices.fixed_base.omega[0];
    CHECK(r.final_state[3] == close_to(scene.initial.u[3] * std::cos(w1 * 2.0), 1e-8));
  }
  CHECK((runs[1].final_state - runs[0].final_state).norm() < 1e-9 * runs[0].final_state.norm());
}

TEST_CASE("a peak between samples is refined: the chimney on a fixed base, set moving in its first mode, peaks as the damped closed form") {
  // u(0) = 0 and u'(0) = v0 phi_1 (v0 at the top) excite one classically
  // damped mode: u_top(t) = v0 e^(-zeta w t) sin(w_d t) / w_d, whose largest
  // value is its first maximum, at tan(w_d t*) = w_d / (zeta w). A sample
  // at a distance d from t* falls short of it by about (w d)^2 / 2 of it,
  // more than the check allows at these samples' spacing; the parabola
  // through the three around it comes to within the integration's error.
  const Scene scene = chimney({"contact.rocking=false"});
  const ContactModel m = make_contact_model(scene, false);
  const Eigen::VectorXd phi = m.body.matrices.fixed_base.shapes.col(0);
  const double v0 = 0.05, H = scene.structure.heights[phi.size() - 1];
  RunOptions o;
  o.tolerances.rtol = 1e-8;
  o.tolerances.atol = 1e-13;
  o.duration = 1.0;
  o.initial.u_dot = v0 * phi / phi[phi.size() - 1];
  const RunResult r = simulate(m, still_ground(), o);
  REQUIRE(r.outcome == Outcome::completed);
  const Rayleigh& ray = m.body.matrices.rayleigh;
  const double w = m.body.matrices.fixed_base.omega[0], zeta = 0.5 * (ray.a0 / w + ray.a1 * w);
  const double wd = w * std::sqrt(1 - zeta * zeta), t_star = std::atan(wd / (zeta * w)) / wd;
  const double peak = v0 * std::exp(-zeta * w * t_star) * std::sin(wd * t_star) / wd;
  REQUIRE(t_star < o.duration);
  CHECK(r.peak(Quantity::delta_e) * H == close_to(peak, 1e-6));
  CHECK(r.peak(Quantity::delta_t) * H == close_to(peak, 1e-6));
}

TEST_CASE("rigid block: each impact leaves r^2 of the energy, so the amplitudes decay as r predicts") {
  const Scene scene = rigid_block({"contact.restitution=0.8"});
  const ContactModel m = make_contact_model(scene, false);
  RunOptions o = tight(6.0, 0.5 * slenderness(scene.structure));
  o.output_interval = 1e-4;
  Recorder rec;
  simulate(m, still_ground(), o, &rec);
  // Largest |theta| of each rocking half-cycle, between sign changes (the rows
  // at the impacts themselves hold theta = 0).
  std::vector<double> amplitudes;  // the first is theta0 itself
  double current = 0, last_sign = 1;
  for (const Response& row : rec.rows) {
    const double th = row[Quantity::theta];
    if (th * last_sign < 0) {
      if (current > 0) amplitudes.push_back(current);
      current = 0;
      last_sign = -last_sign;
    }
    if (th * last_sign > 0) current = std::max(current, std::abs(th));
  }
  REQUIRE(amplitudes.size() >= 5);
  const double g = m.body.g;
  for (std::size_t k = 1; k < 5; ++k) {
    const double ratio = rigid_potential(scene.structure, g, amplitudes[k]) /
                         rigid_potential(scene.structure, g, amplitudes[k - 1]);
    CAPTURE(k);
    CHECK(ratio == close_to(0.8 * 0.8, 1e-6));
  }
}

TEST_CASE("rigid block: a small pulse does not lift it, a large one-sine pulse overturns it") {
  const Scene scene = rigid_block();
  const ContactModel m = make_contact_model(scene, false);
  const double g_tan_alpha = m.body.g * std::tan(slenderness(scene.structure));
  RunOptions o;
  o.duration = 5.0;
  const RunResult small = simulate(m, GroundMotion::pulse(PulseShape::one_sine, 0.9 * g_tan_alpha, 0.5), o);
  CHECK(small.counts.uplifts == 0);
  CHECK(small.peak(Quantity::theta) == 0.0);
  const RunResult large = simulate(m, GroundMotion::pulse(PulseShape::one_sine, 3.0 * g_tan_alpha, 1.0), o);
  CHECK(large.outcome == Outcome::overturned);
  CHECK(large.peak(Quantity::theta_over_alpha) == close_to(1.0, 1e-6));
  CHECK(large.t_end < o.duration);
}

TEST_CASE("a very stiff flexible structure (EI x 1e4) rocks like the rigid block of the same geometry") {
  const GroundMotion pulse = default_ground_motion(chimney());
  RunOptions o;
  o.tolerances.rtol = 1e-8;
  o.duration = 4.0;
  const RunResult rigid = simulate(make_contact_model(chimney({"structure.rigid=true"}), false), pulse, o);
  const RunResult stiff = simulate(make_contact_model(chimney({"structure.EI_scale=1e4"}), false), pulse, o);
  const RunResult as_built = simulate(make_contact_model(chimney(), false), pulse, o);
  REQUIRE(rigid.counts.uplifts >= 1);
  const double theta_rigid = rigid.peak(Quantity::theta);
  CHECK(stiff.peak(Quantity::theta) == close_to(theta_rigid, 1e-3));
  CHECK(stiff.first_uplift == close_to(rigid.first_uplift, 1e-3));
  // ... while the real chimney's flexibility delays its uplift appreciably
  // (measured: 0.129 s against 0.065 s).
  CHECK(as_built.first_uplift > 1.5 * rigid.first_uplift);
}

TEST_CASE("a zero ground motion moves nothing and fires no event") {
  const RunResult r = simulate(make_contact_model(chimney(), true), still_ground(), tight(5.0));
  CHECK(r.outcome == Outcome::completed);
  CHECK(r.stats.events == 0);
  CHECK(r.counts.uplifts == 0);
  for (double p : r.peaks) CHECK(p == 0.0);
}

TEST_CASE("a rigid block at rest still sees a smooth pulse: the step never jumps over it") {
  // At rest in full contact a rigid block's right-hand side is zero, so the
  // step-size control alone would grow the step past a whole Ricker pulse and
  // its uplift guard, which depends on a_g(t) only, would never be sampled.
  const Scene scene = rigid_block();
  const ContactModel m = make_contact_model(scene, false);
  RunOptions o;
  o.duration = 8.0;
  const RunResult r = simulate(m, GroundMotion::pulse(PulseShape::ricker, 2.0 * m.body.g, 1.3), o);
  CHECK(r.counts.uplifts == 1);
  CHECK(r.outcome == Outcome::overturned);
}

TEST_CASE("a central tendon's prestress raises the uplift threshold: m a_g H_cg = m g B + P0 B (first uplift to 1e-8 s)") {
  // A rigid block, no damper, a vertical tendon anchored on the centre line
  // (lever arm B about either pivot) with prestress P0 and no stiffness.
  Scene scene = rigid_block({"damper.enabled=false"});
  const double P0 = 2.0e4;
  const Device tendon{"tendon", {0.0, Kinematics::vertical, 4.0}, ElasticLaw{P0, 0.0}, 0};
  const ContactModel m = make_contact_model(scene, false, {tendon});
  REQUIRE(m.devices.size() == 1);
  REQUIRE(m.acting[0].size() == 1);  // a central anchor: stretched about either pivot, with lever arm B
  REQUIRE(m.acting[1].size() == 1);
  CHECK(m.acting[0][0].lever == m.body.structure.half_width);
  const Structure& st = m.body.structure;
  const double B = st.half_width, mass = m.body.total_mass;
  // a_g at uplift from m a_g H_cg = m g B + P0 B, with m H_cg = H'M1.
  const double a_crit = (m.body.g * B * mass + P0 * B) / m.body.HM1;
  const double amplitude = 1.5 * a_crit, period = 0.8;
  const GroundMotion pulse = GroundMotion::pulse(PulseShape::one_sine, amplitude, period);
  const RunResult r = simulate(m, pulse, tight(1.0));
  // a_g = A sin(2 pi t / T) first reaches a_crit at t = T asin(a_crit / A) / (2 pi).
  const double expected = period * std::asin(a_crit / amplitude) / (2 * std::numbers::pi);
  CHECK(r.first_uplift == close_to(expected, 1e-8));
  // Without the tendon it lifts sooner, at g tan(alpha).
  const RunResult bare = simulate(make_contact_model(scene, false), pulse, tight(1.0));
  CHECK(bare.first_uplift < r.first_uplift - 1e-3);
}

TEST_CASE("a tendon with no prestress and no stiffness, or a dashpot with c = 0, is no device at all") {
  Scene scene = load_default_scene({"damper.enabled=false"});
  const GroundMotion pulse = GroundMotion::pulse(PulseShape::one_sine, 4.0, 0.6);
  const RunResult bare = simulate(make_contact_model(scene, false), pulse, tight(4.0));
  for (const Device& nothing : {Device{"t", {0.0, Kinematics::vertical, 5.0}, ElasticLaw{0, 0}, 0, false, "t"},
                                Device{"v", {-0.5, Kinematics::chord, 0}, ViscousLaw{0, 1}, 0, false, "v"}}) {
    CAPTURE(nothing.name);
    const RunResult with = simulate(make_contact_model(scene, false, {nothing}), pulse, tight(4.0));
    CHECK(with.counts.uplifts == bare.counts.uplifts);
    CHECK(with.counts.impacts == bare.counts.impacts);
    CHECK(with.peak(Quantity::theta) == bare.peak(Quantity::theta));
    CHECK(with.peak(Quantity::base_moment) == bare.peak(Quantity::base_moment));
  }
}

namespace {
// Keeps every response with the devices' samples of the same instant.
struct DeviceRecorder : Observer {
  std::vector<Response> rows;
  std::vector<std::vector<DeviceSample>> samples;
  std::vector<DeviceSample> pending;
  void devices(const std::vector<DeviceSample>& s) override { pending = s; }
  void record(const Response& r) override {
    rows.push_back(r);
    samples.push_back(pending);
  }
};
}  // namespace

TEST_CASE("a device reaching its capacity fractures once, at a located event, and exerts nothing after") {
  // The chimney with a central tendon (P0 + k e) that breaks at e_u = 5 mm.
  const double P0 = 2e6, k = 5e7, e_u = 0.005;
  const Scene scene = chimney({fmt_tendon(P0, k, e_u)});
  const ContactModel m = make_contact_model(scene, true);
  REQUIRE(m.devices.size() == 3);
  DeviceRecorder rec;
  RunOptions o = tight(4.0);
  o.tolerances.rtol = 1e-10;
  const RunResult r = simulate(m, default_ground_motion(scene), o, &rec);
  REQUIRE(r.outcome == Outcome::completed);
  const DeviceResult& tendon = r.devices[2];
  CHECK(tendon.name == "tendon");
  REQUIRE(std::isfinite(tendon.fracture_time));
  CHECK(!std::isfinite(r.devices[0].fracture_time));  // the dampers have no capacity
  // Before the event its elongation stays below the capacity; from the row
  // at the event on, it has none (NaN: what its anchor does is not its
  // elongation) and exerts nothing.
  bool found = false;
  for (std::size_t i = 0; i < rec.rows.size(); ++i) {
    if (rec.rows[i].t < tendon.fracture_time) {
      CHECK(rec.samples[i][2].e <= e_u * (1 + 1e-9));
      continue;
    }
    found = found || rec.rows[i].t == tendon.fracture_time;
    CHECK(std::isnan(rec.samples[i][2].e));
    CHECK(std::isnan(rec.samples[i][2].F));
    CHECK(rec.samples[i][2].moment == 0.0);
  }
  CHECK(found);
  // Its peak elongation is the capacity, to the event location's accuracy.
  // The largest force it carried is the one at fracture; the work done on it,
  // all lost when it broke, is the energy it stored there: P0 e_u + k e_u^2 / 2.
  CHECK(tendon.peak_force == close_to(P0 + k * e_u, 1e-8));
  CHECK(tendon.peak_elongation == close_to(e_u, 1e-9));
  CHECK(tendon.work == close_to(P0 * e_u + 0.5 * k * e_u * e_u, 1e-6));
  // The balance still closes: the work on the devices includes the tendon's.
  CHECK(std::abs(r.energy.residual()) < 1e-6 * r.energy.ground);
}

TEST_CASE("the energy balance closes to 1e-6 of the input for every device law, alone and together, under a record") {
  const auto dir = records_dir();
  if (!dir) return;
  RecordOptions ro;
  ro.scale = 3.0;  // El Centro NS at about 1 g: the chimney rocks and the devices work
  const GroundMotion elcentro = read_record(*dir + "/elcentro_1940_ns.at2", ro);
  // Every registered law (device_laws: a new law is covered by its
  // registration alone) as its example device at both edges, each alone,
  // then all together with a prestressed tendon.
  struct Case {
    std::string what;
    std::vector<std::string> sets;
  };
  std::vector<Case> cases;
  std::vector<std::string> all{fmt_tendon(2e6, 5e7, 0)};
  for (const LawInfo& law : device_laws()) {
    std::string set = "device+={name=\"" + law.name + "\", kind=\"" + law.name + "\", at=\"edges\"";
    for (const LawParameter& p : law.parameters) {
      std::ostringstream value;
      value << std::setprecision(17) << p.example;
      set += ", " + p.key + "=" + value.str();
    }
    set += "}";
    cases.push_back({law.name, {set}});
    all.push_back(set);
  }
  cases.push_back({"all together", all});
  for (const Case& c : cases) {
    CAPTURE(c.what);
    std::vector<std::string> sets{"damper.enabled=false"};
    sets.insert(sets.end(), c.sets.begin(), c.sets.end());
    const ContactModel m = make_contact_model(chimney(sets), true);
    RunOptions o = tight(12.0);
    o.tolerances.rtol = 1e-10;
    const RunResult r = simulate(m, elcentro, o);
    REQUIRE(r.outcome == Outcome::completed);
    CHECK(r.counts.uplifts >= 2);
    double work = 0;
    for (const DeviceResult& d : r.devices) {
      CAPTURE(d.name);
      CHECK(d.peak_elongation > 0);  // every device was stretched
      work += d.work;
    }
    CHECK(work == close_to(r.energy.damper, 1e-9));  // the devices' works add up to the total
    CHECK(std::abs(r.energy.damper) > 1e-3 * r.energy.ground);       // and the devices matter
    CHECK(std::abs(r.energy.residual()) < 1e-6 * r.energy.ground);
  }
}

TEST_CASE("a run in modal coordinates is the nodal run: same events, peaks and energy at tight tolerance") {
  // The chimney spread over 12 nodes (beyond a handful, where the modes
  // differ from the nodes in earnest) under El Centro, rk45 at rtol 1e-10
  // in nodal and in modal coordinates (RunOptions::coordinates): two
  // integrations of the same equations in other variables, agreeing to what
  // the tolerance allows; and the modal run's energy balance closes to 1e-6
  // of the input, as the nodal one does.
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion elcentro = read_record(*dir + "/elcentro_1940_ns.at2");
  Scene scene = chimney();
  spread_over_nodes(scene.structure, 12);
  const ContactModel m = make_contact_model(scene, true);
  RunOptions o = tight(0);
  o.tolerances.rtol = 1e-10;
  o.backend = ode::Backend::rk45;
  o.coordinates = ElasticCoordinates::nodal;
  const RunResult nodal = simulate(m, elcentro, o);
  o.coordinates = ElasticCoordinates::modal;
  const RunResult modal = simulate(m, elcentro, o);
  REQUIRE(nodal.outcome == Outcome::completed);
  REQUIRE(modal.outcome == Outcome::completed);
  CHECK(nodal.counts.uplifts > 5);
  CHECK(modal.counts.uplifts == nodal.counts.uplifts);
  CHECK(modal.counts.impacts == nodal.counts.impacts);
  CHECK(modal.first_uplift == close_to(nodal.first_uplift, 1e-9));
  CHECK(modal.first_impact == close_to(nodal.first_impact, 1e-9));
  // The top's acceleration weighs each mode by omega^2 (K u / m_N): the
  // highest modes, whose amplitudes the two runs share only to atol, count
  // (omega_N / omega_1)^2 more than in the displacements; 1e-6 for it.
  for (std::size_t k = 0; k < quantity_count; ++k) {
    const auto q = static_cast<Quantity>(k);
    CAPTURE(info(q).name);
    CHECK(modal.peaks[k] == close_to(nodal.peaks[k], q == Quantity::a_top ? 1e-6 : 1e-7));
  }
  // final_state is nodal in both
  CHECK((modal.final_state - nodal.final_state).norm() <= 1e-6 * nodal.final_state.norm());
  CHECK(std::abs(modal.energy.residual()) < 1e-6 * modal.energy.ground);
  CHECK(modal.energy.viscous == close_to(nodal.energy.viscous, 1e-7));
}

TEST_CASE("a run that fails says which part of the input drives it: a yield elongation no step can follow") {
  // Below the scene's bounds (d_y >= 1 um, refused there): a library caller can
  // still build it. alpha + beta = 1 keeps |z| <= 1 in exact arithmetic, but
  // z' = e' / d_y at d_y = 1e-200 m is beyond any step.
  Scene scene = load_default_scene({"damper.enabled=false"});
  BoucWenLaw law;
  law.damper.stiffness = 2e7;
  law.damper.post_yield_ratio = 0.05;
  law.damper.alpha = 0.5;
  law.damper.beta = 0.5;
  law.damper.n = 1;
  law.d_y = 1e-200;
  const Device plates{"plates", {3.3, Kinematics::vertical, 1.0}, law, 0, false, "plates"};
  const RunResult r =
      simulate(make_contact_model(scene, false, {plates}), GroundMotion::pulse(PulseShape::one_sine, 4.0, 0.6), tight(2.0));
  CHECK(r.outcome == Outcome::failed);
  INFO(r.failure);
  CHECK(r.failure.find("plates") != std::string::npos);
  CHECK(r.failure.find("devices'") != std::string::npos);
}
