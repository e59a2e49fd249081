// Where a structure with joints leaves the model (MODEL.md 15), the run ends
// with an outcome it states, never a guess and never "failed":
// - sliding: a joint's friction demand |V|/N reaching the limit its scene
//   states. A rigid stack in full contact under a one-sine pulse moves with
//   the ground, so the part above joint 1 needs V = m a_g on N = m g: the run
//   ends when |a_g| / g first reaches the limit, at t = T asin(mu g / A) /
//   (2 pi), checked to 1e-6 s, through the program (exit 0, summary.json's
//   outcome and `sliding`);
// - separated by an impact: a heavy block rocking on a lighter plinth, both
//   released tilted the same way. The plinth strikes first while the block
//   tips on, and the momentum law's two outcomes (the plinth rocking back,
//   or closing) each need a tensile impulse at joint 1: the block would fly.
//   The run ends `separated` at joint 1. Checked against the independent
//   reference (tests/chain_reference.hpp, written from MODEL.md alone): its
//   integration reaches the plinth's impact at the program's time to 1e-6 s,
//   and its Newton-Euler impulses for both outcomes are tensile at joint 1;
// - undecided: an impact at which the momentum law admits no outcome and no
//   joint is tensile in every one, stated with what refused each outcome;
//   and an impact with more closed joints free to open than the law's search
//   examines (max_impact_outcomes), stated with the count, at once.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <span>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "chain_reference.hpp"
#include "chain_reference_from.hpp"
#include "close.hpp"
#include "run_program.hpp"
#include "scene_file.hpp"
#include "temp_path.hpp"
#include "watched_run.hpp"
import rocking.run;
import rocking.report;
import rocking.chain;
import rocking.scene;

using namespace rocking;

namespace {

using Ran = WatchedRun<EventsAndRows>;
Ran run(const Scene& scene) { return watched_run<EventsAndRows>(scene, 1e-10); }

// A plinth (0.84 m wide, 0.31 m tall, 720 kg) under a heavier block (0.54 m
// wide, 0.46 m tall, 1100 kg), each as two lumped masses on its centre line.
std::string plinth_and_block(const std::string& more) {
  return R"(
[structure]
rigid = true
half_width = 0.42
heights = [0.155, 0.31, 0.54, 0.77]
masses = [360.0, 360.0, 550.0, 550.0]
base_mass = 0.0

[contact]
restitution = "momentum"

[[joint]]
node = 2
half_width = 0.27
base_mass = 0.0
)" + more;
}

}  // namespace

TEST_CASE("a joint's friction demand reaching its stated limit ends the run as sliding, when |a_g| / g first reaches it") {
  const double mu = 0.2, A_g = 0.4, T = 0.5;
  const std::filesystem::path scene = std::filesystem::path(ROCKING_SCENES) / "stacked_blocks.toml";
  const Scene s = load_scene(scene.string(), {fmt::format("joint[0].friction={}", mu),
                                              fmt::format("excitation.amplitude_g={}", A_g),
                                              fmt::format("excitation.period={}", T)});
  const Ran ran = run(s);
  REQUIRE(ran.result.outcome == Outcome::sliding);
  const double expected = T * std::asin(mu / A_g) / (2 * std::numbers::pi);
  CHECK(ran.result.t_end == close_to(expected, 1e-6));
  CHECK(ran.result.counts.uplifts == 0);  // 0.2 g is below both joints' thresholds
  CHECK_MESSAGE(ran.result.stated.starts_with("joint 1 at t = "), ran.result.stated);
  CHECK(past_every_limit(ran.result.outcome));
  // Through the program: exit 0, the outcome and the statement in summary.json and the text summary.
  const std::filesystem::path out = scratch_dir("sliding");
  const cli::Result r = cli::run(fmt::format("simulate {} --set joint[0].friction={} --out {}", scene.string(), mu,
                                             out.string()));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const nlohmann::json summary = nlohmann::json::parse(file_text(out / "summary.json"));
  CHECK(summary["outcome"] == "sliding");
  REQUIRE(summary.contains("sliding"));
  CHECK(summary["sliding"].get<std::string>().find("friction demand") != std::string::npos);
  CHECK(r.out.find("sliding") != std::string::npos);
}

TEST_CASE("a plinth striking while the heavier block on it tips on: every outcome of the momentum law needs a tensile impulse at joint 1, and the run ends separated there, as the independent reference finds") {
  const double th0 = -0.01, th1 = -0.05;
  const Scene scene = scene_from("plinth_and_block", plinth_and_block("\n[excitation]\nkind = \"none\"\nduration = 2.0\n"),
                                 {fmt::format("initial.theta={}", th0), fmt::format("joint[0].initial_theta={}", th1)});
  const Ran ran = run(scene);
  REQUIRE_MESSAGE(ran.result.outcome == Outcome::separated, ran.result.stated);
  REQUIRE(ran.result.separated_joint.has_value());
  CHECK(*ran.result.separated_joint == 1);
  CHECK(ran.result.counts.impacts == 0);  // the plinth's first impact is where it ends
  CHECK_MESSAGE(ran.result.stated.find("tensile impulse") != std::string::npos, ran.result.stated);

  // The reference: free rocking from the same tilts to the first impact.
  const chainref::Chain ref = reference_from(jointed_model(scene).chain.data);
  const chainref::Phases before = {-1, -1};
  const chainref::ImpactResult hit =
      chainref::first_impact(ref, before, {th0, th1}, {0.0, 0.0}, 0.0, 2.0, chainref::Ground{});
  REQUIRE(hit.joint == 0);
  CHECK(ran.result.t_end == close_to(hit.t, 1e-6));
  // The momentum law's two outcomes (joint 1 keeps its corner, theta_1 != 0):
  // the plinth rocking back about its right corner, or closing.
  for (const chainref::Phases& after : {chainref::Phases{+1, -1}, chainref::Phases{0, -1}}) {
    CAPTURE(after[0]);
    const chainref::PostImpact post = chainref::momentum_impact(ref, before, hit.q, hit.qd, 0, after);
    const std::vector<std::array<double, 3>> impulse =
        chainref::impact_impulses(ref, before, hit.q, hit.qd, 0, after, post);
    const double N0 = impulse[0][0], N1 = impulse[1][0];
    CHECK(N0 > 0);  // the plinth is pushed up by the ground
    CHECK(N1 < -1e-3 * N0);  // the block would be pulled down onto the plinth: tensile
    MESSAGE("after {" << after[0] << ", " << after[1] << "}: N_0 " << N0 << " N s, N_1 " << N1 << " N s");
  }
  MESSAGE(ran.result.stated);
}

namespace {

// Every joint's last sample, at the row the run ends on (RunOptions::final_row).
struct LastJoints : EventsAndRows {
  std::vector<JointSample> last;
  void joints(std::span<const JointSample> samples) override { last.assign(samples.begin(), samples.end()); }
};

// Four blocks under a Ricker pulse, the second tilted at the start: at
// 0.50 s joint 2 strikes with joints 1 and 3 closed and the base rocking.
std::string four_blocks() {
  return R"(
[structure]
rigid = true
half_width = 0.2986
heights = [0.4428, 0.8856, 1.3560, 1.8264, 2.1430, 2.4596, 3.1855, 3.9114]
masses = [231.715, 106.519, 911.564, 617.570, 394.378, 229.294, 540.154, 324.162]
base_mass = 155.57

[contact]
restitution = "momentum"
theta_dot_min = 0.0015

[[joint]]
node = 2
half_width = 0.5550
base_mass = 0.0
initial_theta = -0.15625265212770084

[[joint]]
node = 4
half_width = 0.3191
base_mass = 0.0

[[joint]]
node = 6
half_width = 0.4112
base_mass = 0.0

[excitation]
pulse = "ricker"
amplitude_g = 0.263
period = 0.381
duration = 4.0
)";
}

}  // namespace

TEST_CASE("an impact the momentum law admits no outcome for, with no joint tensile in all, ends the run undecided: every candidate fails one of MODEL.md 15's conditions, and rosw ends at the same impact") {
  const Scene scene = scene_from("four_blocks", four_blocks());
  RunSpec spec{.scene = scene};
  spec.solver.rtol = 1e-10;
  spec.solver.atol = 1e-12;
  const PreparedRun p = prepare_run(spec);
  RunOptions options = p.options;
  options.final_row = true;
  LastJoints watch;
  const RunResult r = simulate(p.model, p.motion, options, &watch);
  REQUIRE_MESSAGE(r.outcome == Outcome::undecided, r.stated);
  CHECK_MESSAGE(r.stated.find("admits none of the 6 outcomes") != std::string::npos, r.stated);
  CHECK(!past_every_limit(r.outcome));
  REQUIRE(!watch.events.empty());
  const Event& last = watch.events.back();
  REQUIRE(last.kind == EventKind::impact);
  CHECK(last.t == r.t_end);

  // The state the run ended in (the impacting joint at theta = 0, the rates before the impact), replayed.
  const Chain c = jointed_model(scene).chain;
  REQUIRE(static_cast<int>(watch.last.size()) == c.joints);
  std::vector<Phase> before;
  Eigen::VectorXd q(c.size), qd(c.size);
  for (int k = 0; k < c.joints; ++k) {
    before.push_back(watch.last[static_cast<std::size_t>(k)].phase);
    q[k] = watch.last[static_cast<std::size_t>(k)].theta;
    qd[k] = watch.last[static_cast<std::size_t>(k)].theta_dot;
  }
  const int j = last.joint;
  CHECK(q[j] == within(0.0, 1e-12));  // the event located: theta_j at 0 to round-off
  q[j] = 0;
  const ImpactOutcome out = chain_impact(c, before, j, q, qd);
  CHECK(out.status == ImpactStatus::none);
  REQUIRE(out.candidates.size() == 6);  // joint j's two outcomes, three for the one other closed joint
  // Each candidate, by MODEL.md 15's conditions read from its impulses: some joint's impulse tensile, a closed
  // joint's resultant past its corner, or a joint it opens moving shut. The tolerances are the law's scale:
  // 1e-10 of sum m |v-| for the impulses (here the largest |N| bounds it from below), 1e-12 of |theta_j'-| for rates.
  std::vector<int> tensile_in_all(static_cast<std::size_t>(c.joints), 1);
  for (const ImpactCandidate& cand : out.candidates) {
    double scale = 0;
    for (const JointReaction& im : cand.impulse) scale = std::max(scale, std::abs(im.N));
    bool fails = false;
    for (int k = 0; k < c.joints; ++k) {
      const JointReaction& im = cand.impulse[static_cast<std::size_t>(k)];
      const double B = c.data.segments[static_cast<std::size_t>(k)].half_width;
      const bool tensile = im.N < -1e-9 * scale;
      const bool past = !cand.phases[static_cast<std::size_t>(k)].is_rocking() && std::abs(im.M) > B * im.N + 1e-9 * B * scale;
      const bool opened = cand.phases[static_cast<std::size_t>(k)].is_rocking() &&
                          (k == j || !before[static_cast<std::size_t>(k)].is_rocking());
      const bool shutting = opened && cand.phases[static_cast<std::size_t>(k)].sign() * cand.q_dot[k] < -1e-9 * std::abs(qd[j]);
      fails = fails || tensile || past || shutting;
      if (!tensile) tensile_in_all[static_cast<std::size_t>(k)] = 0;
    }
    CHECK(fails);
    CHECK(!cand.consistent());
  }
  // No joint is tensile in every candidate: the impact throws no one part off, so the run cannot end separated.
  CHECK(std::ranges::count(tensile_in_all, 1) == 0);
  // rosw ends at the same impact, undecided.
  spec.solver.integrator = "rosw";
  const PreparedRun ps = prepare_run(spec);
  const RunResult rs = simulate(ps.model, ps.motion, ps.options);
  CHECK(rs.outcome == Outcome::undecided);
  CHECK(rs.t_end == close_to(r.t_end, 1e-6));
  MESSAGE(r.stated);
}

// Thirteen squat drums (2 m wide, 0.2 m tall, 400 kg as two masses: at
// mid-height and at the top, where the next joint is) under a slender top
// (0.1 m wide, 20 kg as two masses 0.5 m and 1 m above its joint): a 0.15 g
// pulse lifts the top alone. Its threshold is B / (h_cg - h) = 0.05 / 0.75
// = 0.067 g; every joint below it has a half-width of 1 m under a cg at most
// 1.36 m above it (the whole stack's, on the base), 0.74 g and more.
std::string drums_under_a_slender_top() {
  std::string heights, masses, joints;
  for (int k = 1; k <= 13; ++k) {
    heights += fmt::format("{}, {}, ", 0.2 * k - 0.1, 0.2 * k);
    masses += "200.0, 200.0, ";
    joints += fmt::format("[[joint]]\nnode = {}\nhalf_width = {}\nbase_mass = 0.0\n", 2 * k, k < 13 ? 1.0 : 0.05);
  }
  return fmt::format(R"(
[structure]
rigid = true
half_width = 1.0
heights = [{}3.1, 3.6]
masses = [{}10.0, 10.0]
base_mass = 0.0

[contact]
restitution = "momentum"

{}
[excitation]
pulse = "one-sine"
amplitude_g = 0.15
period = 0.5
duration = 3.0
)", heights, masses, joints);
}

TEST_CASE("an impact with more closed joints free to open than the search examines ends the run undecided, at once, saying so") {
  const Scene scene = scene_from("drums", drums_under_a_slender_top());
  const Chain c = jointed_model(scene).chain;
  REQUIRE(c.joints == 14);
  // The top rocking back onto the last drum, every other joint closed: 13 joints may open, 2 x 3^13 outcomes.
  std::vector<Phase> before(static_cast<std::size_t>(c.joints), Phase::full_contact());
  before.back() = Phase::rocking(Pivot::right);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(c.size), qd = Eigen::VectorXd::Zero(c.size);
  qd[c.joints - 1] = -0.5;
  const ImpactOutcome out = chain_impact(c, before, c.joints - 1, q, qd);
  CHECK(out.status == ImpactStatus::beyond_search);
  CHECK(out.may_open == 13);
  CHECK(out.candidates.empty());
  // Ten closed joints free to open are examined, every outcome: the three lowest joints rocking (theta != 0).
  std::vector<Phase> fewer = before;
  for (int k = 0; k < 3; ++k) fewer[static_cast<std::size_t>(k)] = Phase::rocking(Pivot::left);
  Eigen::VectorXd q3 = q;
  for (int k = 0; k < 3; ++k) q3[k] = -1e-3;
  const ImpactOutcome examined = chain_impact(c, fewer, c.joints - 1, q3, qd);
  CHECK(examined.status != ImpactStatus::beyond_search);
  CHECK(examined.may_open == 10);
  CHECK(examined.candidates.size() == max_impact_outcomes);
  // A run reaches such an impact, the top striking the drums: it ends undecided there, the count in its statement.
  const Ran ran = run(scene);
  REQUIRE_MESSAGE(ran.result.outcome == Outcome::undecided, ran.result.stated);
  CHECK_MESSAGE(ran.result.stated.find("13 closed joints may open, giving 2 x 3^13 outcomes to examine, beyond "
                                       "the 118098 the momentum law examines at one impact") != std::string::npos,
                ran.result.stated);
  CHECK(ran.result.counts.uplifts == 1);
  CHECK(ran.result.joints.back().uplifts == 1);
}
