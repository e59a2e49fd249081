// Devices across the base joint of a structure with joints, and a fixed base
// under joints that rock (MODEL.md 15 with 11). A device that is not one of
// the chain's tendons (a damper, a chord device, the scene's [damper] pair)
// stands across the base joint as on a one-joint structure: while the base
// rocks about s it exerts -s D on theta_0, and at rest it holds D_0(s)
// against uplift. Checked:
// - against the one-body run (today's equations, rocking.contact): a rigid
//   block of lumped masses on its centre line, where the momentum law is
//   Eq. 10, with a Bouc-Wen pair and an off-centre prestressed spring (a
//   different lever about each corner) under a pulse, and under El Centro
//   x1.3 (several uplifts: the states kept through full contact), gives the
//   same events and peaks by the chain to 1e-6, and the same device works to
//   1e-6 of their total;
// - the contact reaction at the base carries the devices' pull: a prestress
//   given as a base device and as a tendon gives the same N_0 at rest;
// - against a closed form: a prestressed device at the base raises the
//   base's threshold under a ramp to (B_0 + D_0 / (m g)) / H (MODEL.md 15's
//   uplift condition with 11's restraint), the first uplift at that time to
//   1e-6, and `rocking modal` gives the same push;
// - a tendon between two segments (from_segment) holds only the joints
//   between its anchors: the top of a stack tied to the block below lifts at
//   the closed form's time, to 1e-6;
// - a fixed base (contact.rocking = false): the base never lifts, and the
//   joint above lifts at its own threshold, to 1e-6;
// - against the independent reference tests/chain_reference.hpp (MODEL.md 15
//   with 11's devices, written without rocking.chain): a stack of two rigid
//   blocks with a Bouc-Wen pair at its base and a tendon from the lower
//   block's base to the top (from_segment) under a pulse; the top lifts, then
//   the base, then the base strikes: each event's time, and every history
//   row's joint angles and device forces up to the impact, to 1e-6;
// - the energy balance of a segmental pier with yielding dampers at its
//   footing and its tendon, and each device's work adding to the total;
// - through the program: the chimney's [damper] on a cracked chimney, and a
//   one-line refusal of a non-tendon device anchored on a segment.
// Runs use rk45 at rtol 1e-10 (atol 1e-12), far below the tolerances stated.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <memory>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "chain_reference.hpp"
#include "chain_sums.hpp"
#include "close.hpp"
#include "csv_table.hpp"
#include "records.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
#include "scene_file.hpp"
#include "two_blocks.hpp"
#include "watched_run.hpp"
import rocking.run;
import rocking.report;
import rocking.errors;
import rocking.ground_motion;
import rocking.records;

using namespace rocking;

namespace {

using Ran = WatchedRun<EventsAndRows>;
template <class... Args>
Ran run(const Scene& scene, Args&&... args) {
  return watched_run<EventsAndRows>(scene, 1e-10, std::forward<Args>(args)...);
}

// A rigid block 0.5 m wide and 2 m tall (lumped on its centre line) with a
// yielding pair at its edges and a prestressed spring at its axis, under a
// one-sine pulse; `restitution` picks the run: "eq10" the one-body
// equations, "momentum" the chain's (the same law for this block).
std::string damped_block(const std::string& restitution) {
  return fmt::format(R"(
[structure]
rigid = true
half_width = 0.25
heights = [0.25, 0.75, 1.25, 1.75]
masses = [200.0, 200.0, 200.0, 200.0]
base_mass = 20.0

[contact]
restitution = "{}"

[[device]]
name = "yielding"
kind = "bouc-wen"
at = "edges"
k = 4e5
d_y = 0.002

[[device]]
name = "spring"
kind = "elastic"
at = 0.1
P0 = 500.0
k = 2e5

[excitation]
pulse = "one-sine"
amplitude_g = 0.45
period = 0.6
duration = 3.0
)",
                     restitution);
}

}  // namespace

TEST_CASE("devices across the base joint: a rigid block with a yielding pair and a spring runs by the chain as by the one-body equations") {
  std::vector<std::shared_ptr<const GroundMotion>> motions{nullptr};  // the scene's pulse
  if (const auto dir = records_dir())
    motions.push_back(std::make_shared<const GroundMotion>(read_record(*dir + "/elcentro_1940_ns.at2").scaled(1.3)));
  for (const auto& motion : motions) {
  CAPTURE(motion ? motion->name() : std::string("pulse"));
  const Ran one = run(scene_from("block_eq10", damped_block("eq10")), motion);
  const Scene jointed = scene_from("block_momentum", damped_block("momentum"));
  REQUIRE(jointed.jointed());
  const Ran chain = run(jointed, motion);
  REQUIRE(one.result.outcome == Outcome::completed);
  REQUIRE(chain.result.outcome == Outcome::completed);
  REQUIRE(one.result.counts.impacts >= 3);
  if (motion) REQUIRE(one.result.counts.uplifts >= 2);  // full contact between rocking spells
  CHECK(chain.result.counts.uplifts == one.result.counts.uplifts);
  CHECK(chain.result.counts.impacts == one.result.counts.impacts);
  CHECK(chain.result.first_uplift == close_to(one.result.first_uplift, 1e-6));
  CHECK(chain.result.first_impact == close_to(one.result.first_impact, 1e-6));
  CHECK(chain.result.peak(Quantity::theta) == close_to(one.result.peak(Quantity::theta), 1e-6));
  REQUIRE(chain.result.devices.size() == one.result.devices.size());
  REQUIRE(one.result.devices.size() == 3);
  for (std::size_t k = 0; k < one.result.devices.size(); ++k) {
    const DeviceResult &a = one.result.devices[k], &b = chain.result.devices[k];
    CAPTURE(a.name);
    CHECK(b.name == a.name);
    CHECK(a.peak_force > 0);
    CHECK(b.peak_force == close_to(a.peak_force, 1e-6));
    CHECK(b.peak_elongation == close_to(a.peak_elongation, 1e-6));
    // The works are integrals whose steps the motion chooses (they steer no
    // step), over trajectories that agree to 1e-6: held to 1e-6 of the
    // devices' total work, the balance's scale.
    CHECK(b.work == within(a.work, 1e-6 * one.result.energy.damper));
    MESSAGE(a.name << ": work " << a.work << " J, chain - one-body " << b.work - a.work << " J");
  }
  CHECK(chain.result.energy.damper == close_to(one.result.energy.damper, 1e-6));
  // The chain's balance closes with the devices' work in it.
  const EnergyBalance& eb = chain.result.energy;
  CHECK(eb.residual() == within(0.0, 1e-7 * eb.ground));
  MESSAGE("one-body: " << one.result.counts.uplifts << " uplifts, " << one.result.counts.impacts
                       << " impacts, W_devices " << one.result.energy.damper << " J; chain: "
                       << chain.result.counts.impacts << " impacts, W_devices " << eb.damper << " J, residual "
                       << eb.residual() << " J of " << eb.ground << " J input");
  }
}

TEST_CASE("the base's contact carries its devices' pull: a prestress as a base device and as a tendon gives the same N_0") {
  // The segmental pier at rest (no ground motion): its footing's normal force
  // is the weight plus what the prestress pulls down, whether a chord device
  // at the base or the central tendon holds it (MODEL.md 15: the contact
  // carries every force on the segment).
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const double P = 2e6;
  struct Joint0 : Observer {
    std::vector<JointSample> last;
    void joints(std::span<const JointSample> s) override { last.assign(s.begin(), s.end()); }
    void record(const Response&) override {}
  };
  auto n0 = [&](const std::vector<std::string>& set) {
    std::vector<std::string> all{"device=[]", "excitation.kind=\"none\"", "excitation.duration=0.05"};
    all.insert(all.end(), set.begin(), set.end());
    const WatchedRun<Joint0> r = watched_run<Joint0>(load_scene(file.string(), all), 1e-10);
    REQUIRE(r.result.outcome == Outcome::completed);
    REQUIRE(!r.watch.last.empty());
    return r.watch.last[0].N;
  };
  const double bare = n0({});
  const double chord = n0({fmt::format("device+={{name=\"anchor\",kind=\"elastic\",at=0.0,P0={},k=1.0}}", P)});
  const double tendon = n0({fmt::format(
      "device+={{name=\"tie\",kind=\"elastic\",at=0.0,kinematics=\"vertical\",free_length=10,P0={},k=1.0}}", P)});
  CHECK(chord == close_to(bare + P, 1e-9));
  CHECK(tendon == close_to(bare + P, 1e-9));
  MESSAGE("N_0 at rest: " << bare << " N bare, " << chord << " N with the base device, " << tendon << " N with the tendon");
}

TEST_CASE("a prestressed device at the base holds a stack down: its base lifts under a ramp at (B_0 + D_0 / (m g)) / H") {
  const double c = 2.5, g = gravity, P0 = 150.0;  // [m/s^3], [N]
  const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
  // The squat-top stack of joints_test, whose base lifts first; a spring on the base's axis (lever B_0 about either corner).
  const std::string spring =
      fmt::format("[[device]]\nname = \"spring\"\nkind = \"elastic\"\nat = 0.0\nP0 = {}\nk = 1e6\n", P0);
  const Scene scene = scene_from("held_stack", two_blocks(0.25, 500, 0.25, 0.3, spring));
  const ChainData d = jointed_model(scene).chain.data;
  const SegmentSums all = sums_above(d, 0), top = sums_above(d, 1);
  const double B0 = d.segments[0].half_width;
  const double base = (B0 + P0 * B0 / (all.mass * g)) / (all.first / all.mass);
  const double upper = d.segments[1].half_width / (top.first / top.mass);
  REQUIRE(base < upper);
  const Ran ran = run(scene, ramp, 1.05 * base * g / c);
  REQUIRE(!ran.watch.events.empty());
  CHECK(ran.watch.events.front().kind == EventKind::uplift);
  CHECK(ran.watch.events.front().joint == 0);
  CHECK(ran.result.first_uplift == close_to(base * g / c, 1e-6));
  // Without the spring it lifts at B_0 / H: the device's restraint is what moved it.
  const double bare = B0 / (all.first / all.mass);
  CHECK(ran.result.first_uplift > 1.001 * bare * g / c);
  // rocking modal gives the same push, the device's moment at rest included.
  const nlohmann::json modal = modal_summary(scene);
  CHECK(modal["joints"][0]["uplift_g"].get<double>() == close_to(base, 1e-12));
  CHECK(modal["joints"][0]["held_moment_N_m"].get<double>() == close_to(P0 * B0, 1e-12));
  CHECK(modal["lifts_first"].get<int>() == 0);
  MESSAGE("the base lifts at " << ran.result.first_uplift << " s; closed form " << base * g / c << " s (" << bare * g / c
                               << " s without the spring)");
}

TEST_CASE("a flexible structure held down by a prestressed spring: the chain's first uplift is the one-body equations' (the corner's acceleration less D_0 over the inertia about the corner)") {
  // The chimney without its dampers, a 300 kN spring 1 m off its axis (a
  // different lever about each corner): on a flexible structure the corner's
  // acceleration, not only the moment, decides the uplift (MODEL.md 4's two
  // conditions), so a wrong D_0 there would move it.
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "christchurch_chimney.toml";
  const std::vector<std::string> set{"damper.enabled=false", "excitation.duration=0.2",
                                     "device+={name=\"spring\",kind=\"elastic\",at=1.0,P0=3e5,k=1e6}"};
  std::vector<std::string> chain_set = set;
  chain_set.push_back("contact.restitution=\"momentum\"");
  const Ran one = run(load_scene(file.string(), set));
  const Scene jointed = load_scene(file.string(), chain_set);
  REQUIRE(jointed.jointed());
  const Ran chain = run(jointed);
  std::vector<std::string> bare_set{"damper.enabled=false", "excitation.duration=0.2"};
  const Ran bare = run(load_scene(file.string(), bare_set));
  REQUIRE(one.result.counts.uplifts >= 1);
  REQUIRE(chain.result.counts.uplifts >= 1);
  CHECK(chain.result.first_uplift == close_to(one.result.first_uplift, 1e-6));
  CHECK(chain.watch.events.front().pivot == one.watch.events.front().pivot);
  CHECK(one.result.first_uplift > bare.result.first_uplift);  // the spring holds it down
  MESSAGE("first uplift: one-body " << one.result.first_uplift << " s, chain " << chain.result.first_uplift
                                    << " s, without the spring " << bare.result.first_uplift << " s");
}

TEST_CASE("a tendon between two segments holds only the joints between its anchors: the top lifts at (B_1 + D_0 / (m_1 g)) / H_1") {
  const double c = 2.5, g = gravity, P0 = 40.0;  // [m/s^3], [N]
  const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
  // The slender-top stack of joints_test, whose top lifts first, with a tie on its axis from the lower block's
  // base (segment 0) to the top of the upper one (segment 1): it crosses joint 1 only.
  const std::string tie = fmt::format("[[device]]\nname = \"tie\"\nkind = \"elastic\"\nat = 0.0\nkinematics = "
                                      "\"vertical\"\nfree_length = 1.0\nfrom_segment = 0\nsegment = 1\nP0 = {}\nk = 1e6\n",
                                      P0);
  const Scene scene = scene_from("tied_stack", two_blocks(1.0, 500, 0.1, 1.0, tie));
  const ChainData d = jointed_model(scene).chain.data;
  REQUIRE(d.tendons.size() == 1);
  CHECK(d.tendons[0].from.segment == 0);
  const SegmentSums all = sums_above(d, 0), top = sums_above(d, 1);
  const double B1 = d.segments[1].half_width;
  const double upper = (B1 + P0 * B1 / (top.mass * g)) / (top.first / top.mass);
  const double base = d.segments[0].half_width / (all.first / all.mass);  // the tie does not cross joint 0
  REQUIRE(upper < base);
  CHECK(upper > 1.001 * B1 / (top.first / top.mass));  // the tie moved it
  const Ran ran = run(scene, ramp, 1.05 * upper * g / c);
  REQUIRE(!ran.watch.events.empty());
  CHECK(ran.watch.events.front().kind == EventKind::uplift);
  CHECK(ran.watch.events.front().joint == 1);
  CHECK(ran.result.joints[1].first_uplift == close_to(upper * g / c, 1e-6));
  const nlohmann::json modal = modal_summary(scene);
  CHECK(modal["joints"][1]["held_moment_N_m"].get<double>() == close_to(P0 * B1, 1e-12));
  CHECK(modal["joints"][0]["held_moment_N_m"].get<double>() == 0.0);
  CHECK(modal["joints"][1]["uplift_g"].get<double>() == close_to(upper, 1e-12));
  // Its lower anchor must lie below its upper one: one line naming the key.
  std::string bad = tie;
  bad.replace(bad.find("from_segment = 0"), 16, "from_segment = 1");
  CHECK_THROWS_WITH_AS(scene_from("tied_bad", two_blocks(1.0, 500, 0.1, 1.0, bad)),
                       doctest::Contains("from_segment"), InputError);
  MESSAGE("the tied top lifts at " << ran.result.joints[1].first_uplift << " s; closed form " << upper * g / c << " s");
}

TEST_CASE("a fixed base under joints that rock: the base never lifts, the joint above lifts at its own threshold") {
  const double c = 2.5, g = gravity;
  const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
  // The squat-top stack: on a rocking base its base lifts first; held down, its top lifts at B_1 / (H_cg,1 - h_1).
  const std::string text = two_blocks(0.25, 500, 0.25, 0.3);
  const Scene rocking_base = scene_from("stack_rocking", text);
  const Scene fixed = scene_from("stack_fixed", text, {"contact.rocking=false"});
  const ChainData d = jointed_model(fixed).chain.data;
  const SegmentSums all = sums_above(d, 0), top = sums_above(d, 1);
  const double base = d.segments[0].half_width / (all.first / all.mass);
  const double upper = d.segments[1].half_width / (top.first / top.mass);
  REQUIRE(base < upper);
  const Ran free = run(rocking_base, ramp, 1.05 * base * g / c);
  REQUIRE(!free.watch.events.empty());
  CHECK(free.watch.events.front().joint == 0);
  const Ran held = run(fixed, ramp, 1.05 * upper * g / c);
  REQUIRE(!held.watch.events.empty());
  CHECK(held.watch.events.front().kind == EventKind::uplift);
  CHECK(held.watch.events.front().joint == 1);
  CHECK(held.result.joints[1].first_uplift == close_to(upper * g / c, 1e-6));
  CHECK(held.result.joints[0].uplifts == 0);
  for (const Response& r : held.watch.rows) CHECK(r[Quantity::theta] == 0.0);
  // rocking modal names the joint above as the one that lifts first.
  CHECK(modal_summary(fixed)["lifts_first"].get<int>() == 1);
  // A fixed base does not start tilted.
  CHECK_THROWS_AS(scene_from("stack_fixed_tilt", text, {"contact.rocking=false", "initial.theta=0.01"}), InputError);
  MESSAGE("held base: the top lifts at " << held.result.joints[1].first_uplift << " s, closed form " << upper * g / c
                                         << " s (the free base lifts at " << free.result.first_uplift << " s)");
}

TEST_CASE("a segmental pier with yielding dampers at its footing and its tendon: the energy balance closes and each device's work adds to the total") {
  const std::filesystem::path scene_file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const Scene scene =
      load_scene(scene_file.string(), {"device+={name=\"yielding\", kind=\"bouc-wen\", at=\"edges\", k=5e7, d_y=0.003}"});
  const Ran ran = watched_run<EventsAndRows>(scene, 1e-10);
  REQUIRE(ran.result.outcome == Outcome::completed);
  REQUIRE(ran.result.joints[0].uplifts >= 1);
  REQUIRE(ran.result.devices.size() == 3);
  double works = 0;
  for (const DeviceResult& d : ran.result.devices) {
    CAPTURE(d.name);
    CHECK(d.peak_force > 0);
    works += d.work;
  }
  const EnergyBalance& eb = ran.result.energy;
  CHECK(works == close_to(eb.damper, 1e-9));
  CHECK(eb.residual() == within(0.0, 1e-7 * eb.ground));
  // The dampers dissipate: their work is positive and the pier rocks less than without them.
  CHECK(ran.result.devices[0].work > 0);
  const Ran bare = watched_run<EventsAndRows>(load_scene(scene_file.string()), 1e-10);
  CHECK(ran.result.peak(Quantity::theta) < bare.result.peak(Quantity::theta));
  MESSAGE("peak theta " << ran.result.peak(Quantity::theta) << " rad with the dampers, " << bare.result.peak(Quantity::theta)
                        << " rad without; W_devices " << eb.damper << " J, residual " << eb.residual() << " J of "
                        << eb.ground << " J input");
}

TEST_CASE("the program: the chimney's [damper] on a cracked chimney, and a non-tendon device on a segment refused in one line") {
  const std::filesystem::path scene_file = std::filesystem::path(ROCKING_SCENES) / "christchurch_chimney.toml";
  const std::filesystem::path out = scratch_dir("cracked_damper");
  const cli::Result r = cli::run(fmt::format("simulate {} --set joint+={{node=3,half_width=1.5,rigid=true}} --duration 0.4 "
                                             "--history t,theta,damper_left.force,joint1.theta --out {}",
                                             scene_file.string(), out.string()),
                                 120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(out / "history.csv"));
  CHECK(h.has("damper_left.force [N]"));
  CHECK(h.has("joint1.theta [rad]"));
  const nlohmann::json summary = nlohmann::json::parse(file_text(out / "summary.json"));
  CHECK(summary["devices"].size() == 2);

  const cli::Result bad = cli::run(
      fmt::format("simulate {} --set joint+={{node=3,half_width=1.5,rigid=true}} --set "
                  "device+={{kind=\"bouc-wen\",at=0,segment=1}} --out {}",
                  scene_file.string(), scratch_dir("cracked_bad").string()),
      60);
  CHECK(bad.code == 2);
  CHECK(cli::lines(bad.err) == 1);
  CHECK_MESSAGE(bad.err.find("segment") != std::string::npos, bad.err);
}

namespace {

// Every event, and at each history row the joints' and the devices' samples.
struct JointsAndDevices : Observer {
  std::vector<Event> events;
  std::vector<double> t;
  std::vector<std::vector<JointSample>> joint_rows;
  std::vector<std::vector<DeviceSample>> device_rows;
  std::vector<JointSample> joints_now;
  std::vector<DeviceSample> devices_now;
  void event(const Event& e) override { events.push_back(e); }
  void joints(std::span<const JointSample> s) override { joints_now.assign(s.begin(), s.end()); }
  void devices(const std::vector<DeviceSample>& s) override { devices_now = s; }
  void record(const Response& r) override {
    t.push_back(r.t);
    joint_rows.push_back(joints_now);
    device_rows.push_back(devices_now);
  }
};

}  // namespace

TEST_CASE("a stack with a yielding pair at its base and a tendon from the lower block's base to the top, under a pulse: the program's run is the independent reference's to 1e-6 up to the first impact") {
  const double B0 = 0.25, m_lower = 200, B1 = 0.12, height = 1.0, P0 = 300, k_tie = 1e6;
  const std::string devices = fmt::format(R"(
[[device]]
name = "tie"
kind = "elastic"
at = 0.0
kinematics = "vertical"
free_length = 1.0
from_segment = 0
segment = 1
P0 = {}
k = {}

[[device]]
name = "plate"
kind = "bouc-wen"
at = "edges"
k = 4e5
eps = 0.05
d_y = 0.0001
alpha = 0.6
beta = 0.4
n = 1.0
)",
                                          P0, k_tie);
  // A one-sine pulse of 0.4 g and 0.6 s, sampled every 5 ms, then still.
  std::vector<double> t, ah;
  for (int k = 0; k <= 400; ++k) {
    const double tk = 0.005 * k;
    t.push_back(tk);
    ah.push_back(tk < 0.6 ? 0.4 * gravity * std::sin(2 * std::numbers::pi * tk / 0.6) : 0.0);
  }
  const auto motion = std::make_shared<const GroundMotion>(GroundMotion::from_samples("pulse", t, ah));
  const Scene scene = scene_from("stack_tie_plates", two_blocks(B0, m_lower, B1, height, devices));
  const WatchedRun<JointsAndDevices> ran = watched_run<JointsAndDevices>(scene, 1e-10, motion, 2.0);
  const std::vector<Event>& ev = ran.watch.events;
  REQUIRE(ev.size() >= 3);
  // The model's order: the devices across the base joint, then the tendons.
  REQUIRE(ran.result.devices.size() == 3);
  CHECK(ran.result.devices[0].name == "plate_left");
  CHECK(ran.result.devices[1].name == "plate_right");
  CHECK(ran.result.devices[2].name == "tie");

  // The reference: two_blocks' masses on the centre line (node 3, the 1 kg cap at 1 m, is the lower
  // block's), the tie from (0, 0) on segment 0 to the top node of segment 1, the plates at x = -+B0.
  chainref::Chain C;
  C.g = gravity;
  chainref::Segment lower, upper;
  lower.h = 0.0;
  lower.B = B0;
  lower.m0 = 10.0;
  lower.masses = {{0.25, m_lower}, {0.75, m_lower}, {1.0, 1.0}};
  upper.h = 1.0;
  upper.B = B1;
  upper.m0 = 10.0;
  upper.masses = {{1 + height / 6, 30.0}, {1 + height / 2, 30.0}, {1 + 5 * height / 6, 30.0}};
  C.seg = {lower, upper};
  chainref::SegmentTendon tie;
  tie.from = 0;
  tie.to = 1;
  tie.x = 0.0;
  tie.y_top = 1 + 5 * height / 6;
  tie.P0 = P0;
  tie.k = k_tie;
  C.tendons = {tie};
  chainref::BaseDevice plate;
  plate.law = chainref::Law::bouc_wen;
  plate.k = 4e5;
  plate.eps = 0.05;
  plate.dy = 0.0001;
  plate.alpha = 0.6;
  plate.beta = 0.4;
  plate.nbw = 1.0;
  chainref::BaseDevice left = plate, right = plate;
  left.x = -B0;
  right.x = B0;
  C.base = {left, right};
  chainref::Ground G;
  G.ah_rec.t = t;
  G.ah_rec.a = ah;

  // Phase by phase to the first impact, opening each joint that lifts; the rows' times recorded.
  const std::vector<double>& rows = ran.watch.t;
  chainref::Phases ph{0, 0};
  std::vector<double> q, qd, z{0.0, 0.0};
  double t0 = 0.0;
  std::vector<chainref::PhaseEvent> found;
  std::vector<std::pair<chainref::Phases, chainref::PhaseState>> states;
  for (int phase = 0; phase < 4; ++phase) {
    const chainref::PhaseEvent e = chainref::run_phase(C, ph, q, qd, z, t0, 2.0, G, {}, rows);
    for (const chainref::PhaseState& s : e.out) states.push_back({ph, s});
    found.push_back(e);
    if (e.kind != chainref::PhaseEvent::Kind::uplift) break;
    std::vector<double> q2, qd2;
    for (int j = 0, i = 0; j < 2; ++j) {
      if (j == e.joint) {
        q2.push_back(0.0);
        qd2.push_back(0.0);
      } else if (ph[j] != 0) {
        q2.push_back(e.q[i]);
        qd2.push_back(e.qd[i]);
        ++i;
      }
    }
    ph[e.joint] = e.side;
    q = q2;
    qd = qd2;
    z = e.z;
    t0 = e.t;
  }
  // The top lifts, then the base, then the base strikes: both devices act before the impact.
  REQUIRE(found.size() == 3);
  CHECK(found[0].joint == 1);
  CHECK(found[1].joint == 0);
  REQUIRE(found[2].kind == chainref::PhaseEvent::Kind::impact);
  for (std::size_t k = 0; k < found.size(); ++k) {
    CAPTURE(k);
    CHECK(ev[k].kind == (k < 2 ? EventKind::uplift : EventKind::impact));
    CHECK(ev[k].joint == found[k].joint);
    if (k < 2) CHECK(ev[k].pivot == (found[k].side > 0 ? Pivot::right : Pivot::left));
    CHECK(ev[k].t == close_to(found[k].t, 1e-6));
  }
  const double t_hit = found[2].t;

  // Every row before the impact: both joints' angles and rates, and each device's elongation and force,
  // within 1e-6 of their peaks over the rows.
  struct Values {
    double th0, th1, thd0, thd1, e_tie, F_tie, e_plate, F_plate;
  };
  std::vector<Values> ref;
  for (const auto& [phases, s] : states) {
    if (s.t >= t_hit - 1e-6) break;
    const chainref::Kin K = chainref::kinematics(C, phases, s.q, s.qd);
    Values v{};
    double th[2] = {0, 0}, thd[2] = {0, 0};
    for (int j = 0, i = 0; j < 2; ++j)
      if (phases[j] != 0) {
        th[j] = s.q[i];
        thd[j] = s.qd[i];
        ++i;
      }
    v.th0 = th[0];
    v.th1 = th[1];
    v.thd0 = thd[0];
    v.thd1 = thd[1];
    const chainref::SegmentTendonState T = chainref::segment_tendon_state(C, K, tie);
    v.e_tie = T.e;
    v.F_tie = T.F;
    // the plate that the base's rocking lifts (about the left corner: the right plate)
    const chainref::BaseDeviceState P = chainref::base_device_state(C, right, phases[0], th[0], s.z[1]);
    v.e_plate = P.acting ? P.e : 0.0;
    v.F_plate = P.F;
    ref.push_back(v);
  }
  REQUIRE(ref.size() > 20);
  Values peak{};
  auto grow = [](double& p, double x) { p = std::max(p, std::abs(x)); };
  for (const Values& v : ref) {
    grow(peak.th0, v.th0);
    grow(peak.th1, v.th1);
    grow(peak.thd0, v.thd0);
    grow(peak.thd1, v.thd1);
    grow(peak.e_tie, v.e_tie);
    grow(peak.F_tie, v.F_tie);
    grow(peak.e_plate, v.e_plate);
    grow(peak.F_plate, v.F_plate);
  }
  REQUIRE(peak.e_tie > 0);
  REQUIRE(peak.F_plate > 0);
  REQUIRE(found[1].side == -1);  // the base rocks about its left corner: the right plate stretches
  double worst = 0;  // the largest difference over the quantity's peak
  for (std::size_t k = 0; k < ref.size(); ++k) {
    CAPTURE(rows[k]);
    const std::vector<JointSample>& j = ran.watch.joint_rows[k];
    const std::vector<DeviceSample>& d = ran.watch.device_rows[k];
    REQUIRE(j.size() == 2);
    REQUIRE(d.size() == 3);
    worst = std::max({worst, std::abs(j[0].theta - ref[k].th0) / peak.th0, std::abs(j[1].theta - ref[k].th1) / peak.th1,
                      std::abs(j[0].theta_dot - ref[k].thd0) / peak.thd0, std::abs(j[1].theta_dot - ref[k].thd1) / peak.thd1,
                      std::abs(d[2].e - ref[k].e_tie) / peak.e_tie, std::abs(d[2].F - ref[k].F_tie) / peak.F_tie,
                      std::abs(d[1].e - ref[k].e_plate) / peak.e_plate, std::abs(d[1].F - ref[k].F_plate) / peak.F_plate});
    CHECK(j[0].theta == within(ref[k].th0, 1e-6 * peak.th0));
    CHECK(j[1].theta == within(ref[k].th1, 1e-6 * peak.th1));
    CHECK(j[0].theta_dot == within(ref[k].thd0, 1e-6 * peak.thd0));
    CHECK(j[1].theta_dot == within(ref[k].thd1, 1e-6 * peak.thd1));
    CHECK(d[2].e == within(ref[k].e_tie, 1e-6 * peak.e_tie));
    CHECK(d[2].F == within(ref[k].F_tie, 1e-6 * peak.F_tie));
    CHECK(d[1].e == within(ref[k].e_plate, 1e-6 * peak.e_plate));
    CHECK(d[1].F == within(ref[k].F_plate, 1e-6 * peak.F_plate));
  }
  MESSAGE("top lifts " << ev[0].t << " s (reference " << found[0].t << "), base lifts " << ev[1].t << " s (" << found[1].t
                       << "), base strikes " << ev[2].t << " s (" << t_hit << "); " << ref.size()
                       << " rows; peaks: theta_0 " << peak.th0 << ", theta_1 " << peak.th1 << " rad, tie "
                       << peak.F_tie << " N, plate " << peak.F_plate << " N; largest row difference " << worst
                       << " of the peak");
}
