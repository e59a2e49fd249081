// Devices across a joint above the base (MODEL.md 15 with 11): a device that
// is not a tendon, named across joint j >= 1 ([[device]] joint = j), stands
// between the face below (segment j-1) and the segment above as a device at
// the base stands between the ground and the base, in joint j's frame: while
// joint j rocks about s it exerts -s D on theta_j, and at rest it holds
// D_0(s) against uplift there. Checked:
// - against a closed form: a prestressed device across joint 1, off the
//   axis, raises that joint's threshold under a ramp a_g = +-c t to
//   (B_1 + P0 l_s / (m_1 g)) / H_1 about the corner the push lifts it on
//   (l_s = B_1 - s x), the first uplift at that time to 1e-6, and `rocking
//   modal` gives the same held moment and push to 1e-12;
// - against the one-body run (today's equations, rocking.contact): the top
//   block of a stack whose base cannot lift (held, or wide and heavy), with a
//   Bouc-Wen pair across its joint, gives the one-body run of that block
//   with the same pair (Eq. 10, the momentum law for a block of lumped
//   masses on its centre line): the same events, first uplift and impact,
//   peak theta and the devices' peaks to 1e-6, their works to 1e-6 of the
//   total; with a capacity, the same fracture times to 1e-6;
// - the energy balance of the segmental pier on a held footing with a
//   yielding pair across joint 1 under a 1.2 g pulse closes with the devices'
//   work in it (1e-7 of the input, the joints tests' tolerance), each
//   device's work adding to the total;
// - the momentum law's search at an impact with the base rocking (the
//   segmental pier with a stiff yielding pair at its footing under El
//   Centro, which ended failed with "no admissible outcome"): every
//   combination of the other joints' phases examined, the one admissible
//   outcome found and checked against MODEL.md 15's conditions, and the
//   program's run of that pier going on past it; with a pair across joint 1
//   as well, a run at rtol 1e-10 whose joints open for instants closes its
//   energy balance to 1e-7 of the input;
// - an independent integration (tests/chain_reference.hpp, from MODEL.md
//   alone, GSL's rk8pd): two blocks both rocking from a tilt, a Kelvin-Voigt
//   device across joint 1, reach the first impact at the same time to 1e-6;
// - through the program: NAME.force as a history column, the device in
//   summary.json; bad input in one line naming the key (exit 2).
// Runs use rk45 at rtol 1e-10 (atol 1e-12), far below the tolerances stated.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "chain_reference.hpp"
#include "chain_reference_from.hpp"
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
import rocking.chain;
import rocking.records;

using namespace rocking;

namespace {

using Ran = WatchedRun<EventsAndRows>;
template <class... Args>
Ran run(const Scene& scene, Args&&... args) {
  return watched_run<EventsAndRows>(scene, 1e-10, std::forward<Args>(args)...);
}

// The upper block of two_blocks(..., B1, height) alone on the ground: its
// 10 kg slab and three 30 kg nodes at height (1/6, 1/2, 5/6) above its joint.
std::string top_block(double B1, double height, const std::string& restitution, const std::string& more) {
  return fmt::format(R"(
[structure]
rigid = true
half_width = {}
heights = [{}, {}, {}]
masses = [30.0, 30.0, 30.0]
base_mass = 10.0

[contact]
restitution = "{}"
{}
)",
                     B1, height / 6, height / 2, 5 * height / 6, restitution, more);
}

// A yielding pair at the edges of a joint (`joint` empty: the base) and a one-sine pulse.
std::string yielding_pair(const std::string& joint) {
  return fmt::format(R"(
[[device]]
name = "yielding"
kind = "bouc-wen"
at = "edges"
k = 6e4
d_y = 0.001
{}

[excitation]
pulse = "one-sine"
amplitude_g = 0.35
period = 0.5
duration = 3.0
)",
                     joint);
}

}  // namespace

TEST_CASE("a prestressed device across joint 1 holds the top down: it lifts under a ramp at (B_1 + P0 l_s / (m_1 g)) / H_1 about the corner the push lifts it on") {
  const double c = 2.5, g = gravity, P0 = 40.0, x = 0.04;  // [m/s^3], [N], [m]
  // The slender-top stack of joints_test, whose top lifts first; a spring across joint 1, 4 cm right of the axis:
  // a lever B_1 - s x about each corner, so each direction of the push has its own threshold.
  const std::string spring = fmt::format(
      "[[device]]\nname = \"spring\"\nkind = \"elastic\"\nat = {}\nP0 = {}\nk = 1e6\njoint = 1\n", x, P0);
  const Scene scene = scene_from("held_top", two_blocks(1.0, 500, 0.1, 1.0, spring));
  const JointedModel jm = jointed_model(scene);
  REQUIRE(jm.upper.size() == 1);
  REQUIRE(jm.chain.data.tendons.empty());
  const ChainData& d = jm.chain.data;
  const SegmentSums all = sums_above(d, 0), top = sums_above(d, 1);
  const double B1 = d.segments[1].half_width, H1 = top.first / top.mass;
  const double base = d.segments[0].half_width / (all.first / all.mass);  // the spring does not cross joint 0
  std::vector<Pivot> lifted;
  for (const double sign_c : {1.0, -1.0}) {
    CAPTURE(sign_c);
    const auto ramp = std::make_shared<const GroundMotion>(
        GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * sign_c * c}));
    // The threshold about each corner; the push lifts the top about one of them.
    double upper[2];
    for (Pivot p : pivots) upper[index(p)] = (B1 + P0 * (B1 - sign(p) * x) / (top.mass * g)) / H1;
    REQUIRE(std::max(upper[0], upper[1]) < base);
    const Ran ran = run(scene, ramp, 1.05 * std::max(upper[0], upper[1]) * g / c);
    REQUIRE(!ran.watch.events.empty());
    const Event& first = ran.watch.events.front();
    CHECK(first.kind == EventKind::uplift);
    CHECK(first.joint == 1);
    lifted.push_back(first.pivot);
    const double expected = upper[index(first.pivot)] * g / c;
    CHECK(ran.result.joints[1].first_uplift == close_to(expected, 1e-6));
    CHECK(ran.result.joints[1].first_uplift > 1.001 * B1 / H1 * g / c);  // the spring moved it
    MESSAGE("the held top lifts about the " << std::string(first.pivot == Pivot::left ? "left" : "right") << " corner at "
                                            << ran.result.joints[1].first_uplift << " s; closed form " << expected
                                            << " s (" << B1 / H1 * g / c << " s without the spring)");
  }
  REQUIRE(lifted.size() == 2);
  CHECK(lifted[0] != lifted[1]);  // the two pushes lift it on opposite corners, each with its own lever
  // rocking modal: the held moment at joint 1 is the least of P0 l_s, the push the least threshold.
  const nlohmann::json modal = modal_summary(scene);
  CHECK(modal["joints"][1]["held_moment_N_m"].get<double>() == close_to(P0 * (B1 - x), 1e-12));
  CHECK(modal["joints"][0]["held_moment_N_m"].get<double>() == 0.0);
  CHECK(modal["joints"][1]["uplift_g"].get<double>() == close_to((B1 + P0 * (B1 - x) / (top.mass * g)) / H1, 1e-12));
}

TEST_CASE("a yielding pair across the joint of a top whose base cannot lift runs as the one-body top block with that pair") {
  const Ran one = run(scene_from("top_eq10", top_block(0.1, 1.0, "eq10", yielding_pair(""))));
  REQUIRE(one.result.outcome == Outcome::completed);
  REQUIRE(one.result.counts.impacts >= 3);
  REQUIRE(one.result.devices.size() == 2);
  // The base held (contact.rocking = false), and a wide, heavy lower block that never lifts.
  const std::string stack = two_blocks(1.0, 5000, 0.1, 1.0, yielding_pair("joint = 1"));
  for (const bool held : {true, false}) {
    CAPTURE(held);
    const Scene jointed = scene_from(held ? "stack_held" : "stack_wide", stack,
                                     held ? std::vector<std::string>{"contact.rocking=false"} : std::vector<std::string>{});
    const Ran chain = run(jointed);
    REQUIRE_MESSAGE(chain.result.outcome == Outcome::completed, chain.result.failure);
    CHECK(chain.result.joints[0].uplifts == 0);
    CHECK(chain.result.joints[1].uplifts == one.result.counts.uplifts);
    CHECK(chain.result.joints[1].impacts == one.result.counts.impacts);
    CHECK(chain.result.joints[1].first_uplift == close_to(one.result.first_uplift, 1e-6));
    CHECK(chain.result.joints[1].first_impact == close_to(one.result.first_impact, 1e-6));
    CHECK(chain.result.joints[1].peak_theta == close_to(one.result.peak(Quantity::theta), 1e-6));
    REQUIRE(chain.result.devices.size() == 2);
    for (std::size_t k = 0; k < 2; ++k) {
      const DeviceResult &a = one.result.devices[k], &b = chain.result.devices[k];
      CAPTURE(a.name);
      CHECK(b.name == a.name);
      CHECK(a.peak_force > 0);
      CHECK(b.peak_force == close_to(a.peak_force, 1e-6));
      CHECK(b.peak_elongation == close_to(a.peak_elongation, 1e-6));
      // Integrals the steps do not steer, over trajectories that agree to 1e-6: to 1e-6 of the total.
      CHECK(b.work == within(a.work, 1e-6 * one.result.energy.damper));
    }
    const EnergyBalance& eb = chain.result.energy;
    CHECK(eb.residual() == within(0.0, 1e-7 * eb.ground));
    MESSAGE("one-body: " << one.result.counts.uplifts << " uplifts, " << one.result.counts.impacts << " impacts, peak "
                         << one.result.peak(Quantity::theta) << " rad, W_devices " << one.result.energy.damper
                         << " J; chain: peak " << chain.result.joints[1].peak_theta << " rad, W_devices " << eb.damper
                         << " J");
  }
}

TEST_CASE("a pair across joint 1 that breaks at its capacity breaks when the one-body top block's does") {
  const Ran one = run(scene_from("top_breaks", top_block(0.1, 1.0, "eq10", yielding_pair("capacity = 0.01"))));
  const Ran chain = run(scene_from("stack_breaks", two_blocks(1.0, 5000, 0.1, 1.0, yielding_pair("capacity = 0.01\njoint = 1")),
                                   {"contact.rocking=false"}));
  REQUIRE(one.result.devices.size() == 2);
  REQUIRE(chain.result.devices.size() == 2);
  int broke = 0;
  for (std::size_t k = 0; k < 2; ++k) {
    CAPTURE(one.result.devices[k].name);
    const double t = one.result.devices[k].fracture_time;
    if (!std::isfinite(t)) continue;
    ++broke;
    CHECK(chain.result.devices[k].fracture_time == close_to(t, 1e-6));
  }
  REQUIRE(broke >= 1);  // the capacity is reached
  // The chain's fracture event names the joint it stands across.
  bool named = false;
  for (const Event& e : chain.watch.events)
    if (e.kind == EventKind::fracture) named = e.joint == 1;
  CHECK(named);
  CHECK(chain.result.joints[1].peak_theta == close_to(one.result.peak(Quantity::theta), 1e-6));
}

TEST_CASE("the segmental pier on a held footing with a yielding pair across joint 1 under a 1.2 g pulse: the energy balance closes with the devices' work") {
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const Scene scene = load_scene(
      file.string(), {"contact.rocking=false", "excitation.amplitude_g=1.2",
                      "device+={name=\"joint1\", kind=\"bouc-wen\", at=\"edges\", k=5e7, d_y=0.003, joint=1}"});
  const Ran ran = run(scene);
  REQUIRE_MESSAGE(ran.result.outcome == Outcome::completed, ran.result.failure);
  REQUIRE(ran.result.joints[1].impacts >= 3);
  // Joint 1's pair, then the tendon: each acted, and their works add to the devices' total.
  REQUIRE(ran.result.devices.size() == 3);
  CHECK(ran.result.devices[0].name == "joint1_left");
  double works = 0;
  for (const DeviceResult& d : ran.result.devices) {
    CAPTURE(d.name);
    CHECK(d.peak_force > 0);
    works += d.work;
  }
  CHECK(ran.result.devices[0].work + ran.result.devices[1].work > 0);  // the pair dissipates
  const EnergyBalance& eb = ran.result.energy;
  CHECK(works == close_to(eb.damper, 1e-9));
  CHECK(eb.residual() == within(0.0, 1e-7 * eb.ground));
  // Without the pair joint 1 rocks further: the device is what held it.
  const Ran bare = run(load_scene(file.string(), {"contact.rocking=false", "excitation.amplitude_g=1.2"}));
  CHECK(ran.result.joints[1].peak_theta < bare.result.joints[1].peak_theta);
  MESSAGE("joint 1: " << ran.result.joints[1].impacts << " impacts, peak " << ran.result.joints[1].peak_theta
                      << " rad (" << bare.result.joints[1].peak_theta << " rad without the pair); its work "
                      << ran.result.devices[0].work + ran.result.devices[1].work << " J; residual " << eb.residual()
                      << " J of " << eb.ground << " J input");
}

TEST_CASE("the segmental pier with a stiff yielding pair at its footing and one across joint 1 under El Centro: the run completes and the energy balance closes with the devices' work") {
  const auto records = records_dir();
  if (!records) return;
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const Scene scene =
      load_scene(file.string(), {"device+={name=\"footing\", kind=\"bouc-wen\", at=\"edges\", k=1e8, d_y=0.01}",
                                 "device+={name=\"joint1\", kind=\"bouc-wen\", at=\"edges\", k=5e7, d_y=0.003, joint=1}"});
  const auto motion = std::make_shared<const GroundMotion>(read_record(*records + "/elcentro_1940_ns.at2"));
  const Ran ran = run(scene, motion);
  // The footing's pair holds the base back, so joint 1 opens while the base rocks; its impacts open joint 2
  // for instants, which then falls back within a step (the return located on the step's dense output: a
  // state past the face would add energy no motion gives).
  REQUIRE_MESSAGE(ran.result.outcome == Outcome::completed, ran.result.failure);
  REQUIRE(ran.result.joints[1].impacts >= 3);
  CHECK(ran.result.joints[2].uplifts >= 1);
  // The base's pair, joint 1's pair, the tendon: each acted, and their works add to the devices' total.
  REQUIRE(ran.result.devices.size() == 5);
  CHECK(ran.result.devices[2].name == "joint1_left");
  double works = 0;
  for (const DeviceResult& d : ran.result.devices) {
    CAPTURE(d.name);
    CHECK(d.peak_force > 0);
    works += d.work;
  }
  CHECK(ran.result.devices[2].work + ran.result.devices[3].work > 0);  // joint 1's pair dissipates
  const EnergyBalance& eb = ran.result.energy;
  CHECK(works == close_to(eb.damper, 1e-9));
  CHECK(eb.residual() == within(0.0, 1e-7 * eb.ground));
  MESSAGE("joint 1: " << ran.result.joints[1].impacts << " impacts, peak " << ran.result.joints[1].peak_theta
                      << " rad; its pair's work " << ran.result.devices[2].work + ran.result.devices[3].work
                      << " J; W_devices " << eb.damper << " J, residual " << eb.residual() << " J of " << eb.ground
                      << " J input");
}

TEST_CASE("the strongly damped segmental pier under El Centro through the program: joint 1's first impact, with the base rocking, opens joint 2 and the run goes on") {
  const auto records = records_dir();
  if (!records) return;
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const std::filesystem::path out = scratch_dir("damped_pier");
  const cli::Result r = cli::run(
      fmt::format("simulate {} --record {}/elcentro_1940_ns.at2 --set "
                  "'device+={{name=\"footing\",kind=\"bouc-wen\",at=\"edges\",k=1e8,d_y=0.01}}' --out {}",
                  file.string(), *records, out.string()),
      120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const nlohmann::json s = nlohmann::json::parse(file_text(out / "summary.json"));
  CHECK(s["outcome"] == "completed");
  const nlohmann::json& joints = s["joints"];
  REQUIRE(joints.size() == 4);
  // The impact that the search ended the run at (4.807 s) opens joint 2 at that instant.
  CHECK(joints[2]["first_uplift_s"].get<double>() == joints[1]["first_impact_s"].get<double>());
  // At the program's defaults (rk45, rtol 1e-4): the balance closes to that rtol of the input.
  const nlohmann::json& e = s["energy_J"];
  CHECK(s["rtol"].get<double>() == 1e-4);
  CHECK(e["balance_residual"].get<double>() == within(0.0, 1e-4 * e["ground_input"].get<double>()));
  MESSAGE("joint 1's first impact at " << joints[1]["first_impact_s"] << " s; energy residual "
                                       << e["balance_residual"] << " J of " << e["ground_input"] << " J");
}

TEST_CASE("an impact at joint 1 with the base rocking: the momentum law's one admissible outcome opens joint 2 alone, which opening joints one after another misses") {
  // The state of the damped pier (above) as joint 1 first struck, 4.807 s into El Centro: the base rocking
  // about its left corner, turning back, joint 1 closing on its left corner, the joints above closed.
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const Chain c = jointed_model(load_scene(file.string())).chain;
  REQUIRE(c.size == 4);
  const Phase left = Phase::rocking(Pivot::left), right = Phase::rocking(Pivot::right), shut = Phase::full_contact();
  const std::vector<Phase> before{left, left, shut, shut};
  Eigen::VectorXd q = Eigen::VectorXd::Zero(4), qd = Eigen::VectorXd::Zero(4);
  q[0] = -0.005253034788293444;
  qd[0] = 0.010118438422416127;
  qd[1] = 0.03762785757661327;
  const ImpactOutcome out = chain_impact(c, before, 1, q, qd);
  CHECK(out.candidates.size() == 2 * 9);  // joint 1's two outcomes, three for each closed joint above
  REQUIRE(out.status == ImpactStatus::unique);
  const std::vector<Phase> expected{left, shut, right, shut};
  for (int k = 0; k < 4; ++k) CHECK(phase_name(out.phases[k]) == phase_name(expected[k]));
  REQUIRE(out.uplifted.size() == 1);
  CHECK(out.uplifted[0] == 2);
  // MODEL.md 15's conditions, checked from its impulses: every one compressive, every closed joint's
  // resultant within its face, the opened joint moving open; and no kinetic energy gained.
  const ImpactCandidate chosen = impact_into(c, before, 1, expected, q, qd);
  for (int k = 0; k < 4; ++k) {
    CAPTURE(k);
    const JointReaction& r = chosen.impulse[static_cast<std::size_t>(k)];
    CHECK(r.N > 0);
    if (!expected[k].is_rocking()) CHECK(std::abs(r.M) <= c.data.segments[static_cast<std::size_t>(k)].half_width * r.N);
  }
  CHECK(chosen.q_dot[2] > 0);
  ChainWorkspace w = make_workspace(c);
  const double before_kinetic = chain_energy(c, before, q, qd, w).kinetic;
  CHECK(chain_energy(c, out.phases, q, out.q_dot, w).kinetic <= before_kinetic);
  // Closing joint 1 with the others closed sends joints 2 and 3 past their corners; opening both (where the
  // sequence of openings stops) leaves joint 3 moving shut: neither is admissible.
  const ImpactCandidate closed = impact_into(c, before, 1, std::vector<Phase>{left, shut, shut, shut}, q, qd);
  CHECK(!closed.consistent());
  for (int k : {2, 3}) CHECK(std::abs(closed.impulse[k].M) > c.data.segments[k].half_width * closed.impulse[k].N);
  const ImpactCandidate both = impact_into(c, before, 1, std::vector<Phase>{left, shut, right, right}, q, qd);
  CHECK(!both.consistent());
  CHECK(both.q_dot[3] < 0);
}

TEST_CASE("two blocks rocking from a tilt with a Kelvin-Voigt device across joint 1: the independent reference reaches the first impact at the same time") {
  const double th0 = 0.02, th1 = -0.05, x = 0.05, k = 2e4, c = 150.0;
  const std::string device = fmt::format(
      "[[device]]\nname = \"kv\"\nkind = \"kelvin\"\nat = {}\nk = {}\nc = {}\njoint = 1\n", x, k, c);
  const std::string text = two_blocks(0.25, 100, 0.1, 1.0, device) + still(2.0);
  const Scene scene = scene_from("kv_stack", text, {fmt::format("initial.theta={}", th0),
                                                    fmt::format("joint[0].initial_theta={}", th1)});
  const Ran ran = run(scene);
  REQUIRE(ran.result.counts.impacts >= 1);
  const double t_program = ran.result.first_impact;
  // The reference: the same chain (its segments from the model's data), the device in its own form.
  const chainref::Chain ref = reference_from(jointed_model(scene).chain.data);
  chainref::Ground ground;  // none
  const auto with = [&](bool device_on) {
    chainref::Chain r = ref;
    if (device_on) r.devices.push_back({.joint = 1, .x = x, .k = k, .c = c});
    return chainref::first_impact(r, {1, -1}, {th0, th1}, {0.0, 0.0}, 0.0, 2.0, ground);
  };
  const chainref::ImpactResult reference = with(true), bare = with(false);
  REQUIRE(reference.joint >= 0);
  CHECK(t_program == close_to(reference.t, 1e-6));
  CHECK(ran.watch.events.size() >= 1);
  // The impact is the reference's joint's.
  for (const Event& e : ran.watch.events)
    if (e.kind == EventKind::impact) {
      CHECK(e.joint == reference.joint);
      break;
    }
  // The device matters: without it the reference's impact comes elsewhere.
  CHECK(std::abs(bare.t - reference.t) > 1e-3 * reference.t);
  MESSAGE("first impact: program " << t_program << " s, reference " << reference.t << " s (joint " << reference.joint
                                   << "), without the device " << bare.t << " s");
}

TEST_CASE("the program: a device across joint 2 of the segmental pier in history.csv and summary.json, and bad input in one line naming the key") {
  const std::filesystem::path file = std::filesystem::path(ROCKING_SCENES) / "segmental_pier.toml";
  const std::filesystem::path out = scratch_dir("upper_device");
  const cli::Result r = cli::run(
      fmt::format("simulate {} --set 'device+={{name=\"pad\",kind=\"kelvin\",at=0.5,k=1e8,c=1e6,joint=2}}' --duration 1.0 "
                  "--history t,joint2.theta,pad.force,pad.elongation --out {}",
                  file.string(), out.string()),
      120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(out / "history.csv"));
  CHECK(h.has("pad.force [N]"));
  CHECK(h.has("pad.elongation [m]"));
  const nlohmann::json summary = nlohmann::json::parse(file_text(out / "summary.json"));
  bool named = false;
  for (const nlohmann::json& d : summary["devices"]) named = named || d["name"] == "pad";
  CHECK(named);
  // Bad input: one line on stderr naming the key, exit 2.
  const std::string kv = "device+={kind=\"kelvin\",k=1,c=1,";
  const std::string pier = fmt::format("simulate {} --out {} --set ", file.string(), scratch_dir("upper_bad").string());
  cli::refused(pier + "'" + kv + "at=0,joint=4}'", "joint");             // the pier has joints 0 to 3
  cli::refused(pier + "'" + kv + "at=0,joint=1.5}'", "joint");           // not an integer
  cli::refused(pier + "'" + kv + "at=0,joint=1,segment=2}'", "joint");   // a tendon's key with it
  cli::refused(pier + "'" + kv + "at=0.8,joint=1}'", "B_1");             // off joint 1's face (B_1 = 0.75)
  const std::filesystem::path chimney = std::filesystem::path(ROCKING_SCENES) / "christchurch_chimney.toml";
  cli::refused(fmt::format("simulate {} --out {} --set '{}at=0,joint=1}}'", chimney.string(),
                           scratch_dir("upper_bad").string(), kv),
               "joint");  // no [[joint]] tables
}
