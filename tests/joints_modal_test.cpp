// `rocking modal` on a structure with joints (MODEL.md 15): at each joint,
// everything above it as one rigid body about the joint's corner. Its static
// uplift threshold is checked against the run itself: a rigid stack under a
// ramp a_g = c t does not move until a joint lifts, so the joint the modal
// summary says lifts first must lift first, at its threshold / c (to 1e-6),
// the tendon's prestress included (the segmental pier). Its p and r are
// checked against Housner's and Eq. 10's for the top block computed here from
// the scene's numbers.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <memory>
#include <string>
#include <utility>
#include <vector>
#include "close.hpp"
#include "run_program.hpp"
#include "watched_run.hpp"
import rocking.run;
import rocking.report;

using namespace rocking;

TEST_CASE("rocking modal on a structure with joints: the joint it says lifts first under a slow push lifts first under a ramp, at its threshold") {
  // The segmental pier also with its central tendon replaced by one at each edge (x = -B and +B): the pair
  // holds P0 B each way whatever the pivot, 2 P0 B in all, where one tendon at the edge would hold none.
  const std::vector<std::string> edges = {
      "device-=tendon",
      "device+={kind=\"elastic\",name=\"ties\",at=\"edges\",kinematics=\"vertical\",free_length=8.0,P0=7.5e5,k=1.95e7,segment=3}"};
  for (const auto& [name, overrides] : std::vector<std::pair<const char*, std::vector<std::string>>>{
           {"stacked_blocks", {}}, {"segmental_pier", {}}, {"segmental_pier", edges}}) {
    CAPTURE(name);
    CAPTURE(overrides.size());
    const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/" + name + ".toml", overrides);
    const nlohmann::json m = modal_summary(scene);
    REQUIRE(m["joints"].size() == 1 + scene.joints.size());
    const int first = m["lifts_first"].get<int>();
    for (const nlohmann::json& j : m["joints"])
      CHECK(j["uplift_g"].get<double>() >= m["joints"][first]["uplift_g"].get<double>());
    const double c = 1.0;  // [m/s^3]
    const double t_star = m["joints"][first]["uplift_g"].get<double>() * gravity / c;
    const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 20.0}, {0.0, 20 * c}));
    const auto ran = watched_run<EventsAndRows>(scene, 1e-10, ramp, 1.05 * t_star);
    REQUIRE(!ran.watch.events.empty());
    CHECK(ran.watch.events.front().kind == EventKind::uplift);
    CHECK(ran.watch.events.front().joint == first);
    CHECK(ran.watch.events.front().t == close_to(t_star, 1e-6));
    MESSAGE(std::string(name) << ": joint " << ran.watch.events.front().joint << " lifts at " << ran.watch.events.front().t
                 << " s; modal: joint " << first << " at " << t_star << " s");
  }
}

TEST_CASE("rocking modal on the stacked blocks: the top block's p and r are Housner's and Eq. 10's") {
  // The top block of stacked_blocks.toml: its masses on its centre line above joint 1, from the scene's numbers.
  const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/stacked_blocks.toml");
  const nlohmann::json top = modal_summary(scene)["joints"][1];
  const JointTable& joint = scene.joints.front();
  const double h = scene.structure.heights[joint.node - 1], B = joint.half_width;
  double m = joint.base_mass, mz = 0, J = joint.base_mass * B * B;
  for (Eigen::Index i = joint.node; i < scene.structure.heights.size(); ++i) {
    const double mi = scene.structure.masses[i], z = scene.structure.heights[i] - h;
    m += mi;
    mz += mi * z;
    J += mi * (B * B + z * z);
  }
  const double H = mz / m, R = std::hypot(B, H);
  CHECK(top["alpha"].get<double>() == close_to(std::atan(B / H), 1e-12));
  CHECK(top["p"].get<double>() == close_to(std::sqrt(m * gravity * R / J), 1e-12));
  CHECK(top["r_momentum"].get<double>() == close_to(1 - 2 * m * B * B / J, 1e-12));
  // The program prints the table and the joint that lifts first.
  const cli::Result r = cli::run(std::string("modal ") + ROCKING_SCENES + "/stacked_blocks.toml");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(cli::contains(r.out, "Under a slow push joint 1 lifts first."));
  const cli::Result j = cli::run(std::string("modal --json ") + ROCKING_SCENES + "/stacked_blocks.toml");
  REQUIRE(j.code == 0);
  CHECK(nlohmann::json::parse(j.out)["lifts_first"] == 1);
}

TEST_CASE("the segmental pier lesson: as built it needs the least push at its footing and rocks there, and on a footing twice as wide at the joint above") {
  // docs/teaching.md lesson 8's numbers: the pushes (to the 3 digits it gives) and where each pier rocks.
  const std::string pier = std::string(ROCKING_SCENES) + "/segmental_pier.toml";
  struct Case {
    std::vector<std::string> overrides;
    std::vector<double> pushes;  // a_g / g per joint, as the lesson states them
    int rocks;                   // the one joint that opens under the pulse
  };
  for (const Case& c : {Case{{}, {0.229, 0.308, 0.466, 0.941}, 0}, Case{{"structure.half_width=1.5"}, {0.458, 0.308, 0.466, 0.941}, 1}}) {
    CAPTURE(c.rocks);
    const Scene scene = load_scene(pier, c.overrides);
    const nlohmann::json m = modal_summary(scene);
    REQUIRE(m["joints"].size() == c.pushes.size());
    for (std::size_t j = 0; j < c.pushes.size(); ++j)
      CHECK(m["joints"][j]["uplift_g"].get<double>() == within(c.pushes[j], 5e-4));
    CHECK(m["lifts_first"] == c.rocks);
    const auto ran = watched_run<EventsAndRows>(scene, 1e-8);
    CHECK(ran.result.outcome == Outcome::completed);
    REQUIRE(ran.result.joints.size() == c.pushes.size());
    for (std::size_t j = 0; j < c.pushes.size(); ++j) {
      CAPTURE(j);
      if (static_cast<int>(j) == c.rocks) CHECK(ran.result.joints[j].uplifts >= 1);
      else CHECK(ran.result.joints[j].uplifts == 0);
    }
  }
}
