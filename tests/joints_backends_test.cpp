// A structure with joints (MODEL.md 15) under the other backends and under
// vertical ground motion (MODEL.md 14). The SUNDIALS backends integrate the
// chain's equations as rk45 does: the segmental pier under its pulse lifts
// and first strikes at the same instants (to 1e-6 at rtol 1e-10). Under
// vertical shaking a rigid stack in full contact still does not move until a
// joint lifts, so the first uplift under a ramp a_g = c t with a constant
// a_v is exact: at a_g / (g + a_v) = the joint's threshold (MODEL.md 15, with
// 14's gravity), the threshold computed here from the scene's numbers.
// rosw at the default tolerances lifts and strikes as rk45 does on the
// shipped scenes with joints, under their pulses and El Centro
// (rosw_events.hpp says what is held and to which tolerance), and on a
// finely meshed flexible chain, a 16-node tower cracked at node 12, where it
// solves with the chain's stiff part (docs/chain.md "Stiff steps"): there
// rk45's steps are bound by the stability of the shaft's fastest modes and
// rosw's by the motion, so that rosw takes less than an eighth of rk45's
// right-hand sides, and the automatic choice is rosw.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include "close.hpp"
#include "csv_table.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
#include "watched_run.hpp"
#include "records.hpp"
#include "rosw_events.hpp"
#include "scene_file.hpp"
import rocking.run;

using namespace rocking;

TEST_CASE("the segmental pier under CVODE and ARKODE: its first uplift and first impact are rk45's") {
  const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/segmental_pier.toml");
  const auto reference = watched_run<EventsAndRows>(scene, 1e-10);
  REQUIRE(reference.result.counts.impacts >= 1);
  for (const char* integrator : {"cvode", "arkode"}) {
    CAPTURE(integrator);
    const auto other = watched_run<EventsAndRows>(scene, 1e-10, nullptr, std::nullopt, integrator);
    CHECK(other.result.integrator == integrator);
    CHECK(other.result.first_uplift == close_to(reference.result.first_uplift, 1e-6));
    CHECK(other.result.first_impact == close_to(reference.result.first_impact, 1e-6));
    CHECK(other.result.counts.impacts == reference.result.counts.impacts);
  }
}

TEST_CASE("the stacked blocks under a ramp with a constant vertical acceleration: the top lifts at a_g / (g + a_v) = its threshold") {
  const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/stacked_blocks.toml");
  // The artefact above joint 1: B_1 over the height of its centre of mass above the joint, its masses on its
  // centre line (the scene's nodes above the joint's node).
  const JointTable& joint = scene.joints.front();
  const double h = scene.structure.heights[joint.node - 1];
  double m = joint.base_mass, mz = 0;
  for (Eigen::Index i = joint.node; i < scene.structure.heights.size(); ++i) {
    m += scene.structure.masses[i];
    mz += scene.structure.masses[i] * (scene.structure.heights[i] - h);
  }
  const double threshold = joint.half_width / (mz / m);
  const double c = 2.0;  // [m/s^3]
  for (const double a_v : {-2.0, 0.0, 3.0}) {  // [m/s^2], up positive
    CAPTURE(a_v);
    const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
    const auto vertical = std::make_shared<const GroundMotion>(GroundMotion::from_samples("lift", {0.0, 10.0}, {a_v, a_v}));
    const double t_star = threshold * (gravity + a_v) / c;
    const auto ran = watched_run<EventsAndRows>(scene, 1e-10, ramp, 1.05 * t_star, "rk45", vertical);
    REQUIRE(!ran.watch.events.empty());
    CHECK(ran.watch.events.front().kind == EventKind::uplift);
    CHECK(ran.watch.events.front().joint == 1);
    CHECK(ran.watch.events.front().t == close_to(t_star, 1e-6));
  }
}

TEST_CASE("a tendon's work counts from the start of the run: the segmental pier released from a tilt") {
  // Released from a tilt the tendon is already stretched; its work (int F de since the start) is 0 at t = 0 and
  // equals the devices' total W_devices at every row.
  const std::filesystem::path out = temp_path("pier_tilt");
  const cli::Result r = cli::run(std::string("-q simulate ") + ROCKING_SCENES +
                                 "/segmental_pier.toml --set initial.theta=0.01 --set excitation.kind=none "
                                 "--set excitation.duration=2 --history t,W_devices,tendon.work --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(out / "history.csv"));
  REQUIRE(h.rows.size() > 10);
  double largest = 0;
  for (std::size_t i = 0; i < h.rows.size(); ++i) largest = std::max(largest, std::abs(std::stod(h.at(i, "W_devices [J]"))));
  REQUIRE(largest > 0);
  CHECK(std::stod(h.at(0, "tendon.work [J]")) == within(0.0, 1e-9 * largest));
  for (std::size_t i = 0; i < h.rows.size(); ++i)
    CHECK(std::stod(h.at(i, "tendon.work [J]")) == close_to(std::stod(h.at(i, "W_devices [J]")), 1e-6, 1e-9 * largest));
}

TEST_CASE("rosw at the default tolerances: the stacked blocks and the segmental pier lift and strike as rk45 does, under their pulses and El Centro") {
  const auto records = records_dir();
  if (!records) return;
  for (const char* name : {"stacked_blocks", "segmental_pier"}) {
    const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/" + name + ".toml");
    const std::string scene_name = name;
    for (const std::string& record : {std::string(), *records + "/elcentro_1940_ns.at2"}) {
      CAPTURE(scene_name);
      CAPTURE(record);
      rosw_events::check(scene, record);
    }
  }
}

TEST_CASE("a 16-node tower cracked at node 12: rosw with the chain's stiff part lifts and strikes as rk45 does, on an eighth of its right-hand sides, and is the automatic choice") {
  const auto records = records_dir();
  if (!records) return;
  // The shipped 16-node tower (data/scenes/towers) with a rigid top piece standing free on node 12.
  std::string toml = file_text(std::string(ROCKING_SCENES) + "/towers/tower_16.toml");
  const std::size_t damper = toml.find("[damper]");
  REQUIRE(damper != std::string::npos);
  toml.insert(damper, "[[joint]]\nnode = 12\nhalf_width = 1.5\nbase_mass = 0.0\nrestitution = \"momentum\"\nrigid = true\n\n");
  const Scene scene = scene_from("tower_16_cracked", toml);
  for (const std::string& record : {std::string(), *records + "/elcentro_1940_ns.at2"}) {
    CAPTURE(record);
    rosw_events::check(scene, record);
    const rosw_events::Run rk = rosw_events::run(scene, "rk45", record), ro = rosw_events::run(scene, "rosw", record),
                           automatic = rosw_events::run(scene, "auto", record);
    REQUIRE(ro.result.stats.rhs > 0);
    CHECK(ro.result.stats.rhs * 8 < rk.result.stats.rhs);
    CHECK(automatic.result.integrator == "rosw");
  }
}
