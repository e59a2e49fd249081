// Devices on a structure on rocking columns (MODEL.md 16 with 11): a
// [[device]] of a scene on [columns] stands at the base of every column
// alike, with its lever arm about the column's pivot corner, so that the n
// columns' devices exert n times one device's moment. Checked against closed
// forms computed from the scene's numbers, not from the run:
// - the uplift threshold a tendon's prestress raises (16's uplift condition
//   with D_0 = n P0 l), under a ramp a_g = c t, to 1e-6;
// - free rocking from a tilt with an elastic device at a column's edge: the
//   first impact at the quadrature of the energy equation (gravity's and the n
//   devices' potential, 16's J), to 1e-6;
// - the energy balance with a hysteretic damper and a tendon under a pulse,
//   and the per-device works adding to the devices' total;
// - a device reaching its capacity fractures at the tilt its chord gives;
// and through the program: history columns and summary by name, a study's
// default variants with the device removed, bad input. Runs use rk45 at
// rtol 1e-10 (atol 1e-12), far below the tolerances stated.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <gsl/gsl_integration.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "close.hpp"
#include "columns_frame.hpp"
#include "csv_table.hpp"
#include "rocking_record.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
#include "scene_file.hpp"
#include "watched_run.hpp"
import rocking.run;
import rocking.report;
import rocking.errors;

using namespace rocking;

namespace {

using namespace columns_frame;

std::string still(double duration) { return fmt::format("\n[excitation]\nkind = \"none\"\nduration = {}\n", duration); }

using Ran = WatchedRun<EventsAndRows>;
template <class... Args>
Ran run(const Scene& scene, Args&&... args) {
  return watched_run<EventsAndRows>(scene, 1e-10, std::forward<Args>(args)...);
}

}  // namespace

TEST_CASE("a tendon through each column raises the frame's uplift threshold by n P0 b / (h (n m_c + 2 m_d)): the first uplift under a ramp at the closed form's time") {
  const Frame f;
  const double P0 = 40e3, c = 2.0, g = gravity;  // [N], [m/s^3]
  // A tendon up each column's axis (lever b about either corner), anchored in the footing and at the column's top.
  const std::string tendon = fmt::format(
      "[[device]]\nname = \"tie\"\nkind = \"elastic\"\nat = 0.0\nkinematics = \"vertical\"\nfree_length = {}\nP0 = {}\nk = 1e7\n",
      2 * h, P0);
  const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
  for (const double prestress : {0.0, P0}) {
    CAPTURE(prestress);
    const double a_star = g * b / h + n * prestress * b / (h * (n * mc + 2 * f.m_d));
    const Scene scene = scene_from("tied", frame(prestress > 0 ? tendon : "", ""));
    const Ran ran = run(scene, ramp, 1.05 * a_star / c);
    REQUIRE(!ran.watch.events.empty());
    CHECK(ran.watch.events.front().kind == EventKind::uplift);
    CHECK(ran.watch.events.front().pivot == Pivot::left);  // a_g > 0 pushes the frame to the left
    CHECK(ran.result.first_uplift == close_to(a_star / c, 1e-6));
    // rocking modal gives the same push, the devices' moment at rest included.
    CHECK(modal_summary(scene)["columns"]["uplift_g"].get<double>() * gravity == close_to(a_star, 1e-12));
    MESSAGE("P0 " << prestress << " N: uplift at " << ran.result.first_uplift << " s, closed form " << a_star / c << " s");
  }
}

TEST_CASE("an elastic device at each column's edge: free rocking from a tilt lands at the quadrature of the energy equation") {
  const Frame f;
  const double k = 2e6, P0 = 5e3, g = gravity;
  // At the left edge of each column's base (x = -b): about the right corner its lever is l = 2b and it
  // stretches along the chord, e = 2 l sin(theta/2) (MODEL.md 11).
  const std::string device =
      fmt::format("[[device]]\nname = \"spring\"\nkind = \"elastic\"\nat = {}\nkinematics = \"chord\"\nP0 = {}\nk = {}\n", -b, P0, k);
  const double l = 2 * b, th0 = 0.5 * f.alpha;
  // The potential: gravity's and the n devices' stored energy P0 e + k e^2 / 2.
  auto U = [&](double th) {
    const double e = 2 * l * std::sin(0.5 * th);
    return f.lever * g * (std::cos(f.alpha - th) - std::cos(f.alpha)) + n * (P0 * e + 0.5 * k * e * e);
  };
  const double t_quad = fall_time(U, th0, f.J);

  const std::string tilt = fmt::format("\n[initial]\ntheta = {:.17g}\n", th0);
  const Ran with = run(scene_from("spring", frame(device, tilt + still(1.2 * t_quad))));
  REQUIRE(with.result.counts.impacts >= 1);
  CHECK(with.result.first_impact == close_to(t_quad, 1e-6));
  // The devices pull the frame back: it lands sooner than without them.
  const Ran without = run(scene_from("bare", frame("", tilt + still(4 * t_quad))));
  REQUIRE(without.result.counts.impacts >= 1);
  CHECK(with.result.first_impact < without.result.first_impact);
  // Released at rest, the device's peak is at the release: e = 2 l sin(th0/2), F = P0 + k e.
  REQUIRE(with.result.devices.size() == 1);
  const double e0 = 2 * l * std::sin(0.5 * th0);
  CHECK(with.result.devices[0].peak_elongation == close_to(e0, 1e-9));
  CHECK(with.result.devices[0].peak_force == close_to(P0 + k * e0, 1e-9));
  // No damping and no ground: what the devices store is what the frame's energy lost.
  const EnergyBalance& eb = with.result.energy;
  CHECK(eb.residual() == within(0.0, 1e-9 * eb.initial));
  MESSAGE("first impact " << with.result.first_impact << " s (quadrature " << t_quad << " s; " << without.result.first_impact
                          << " s without the devices)");
}

TEST_CASE("devices on a flexible structure on columns under a pulse: the energy balance closes and each device's work adds to the total") {
  const std::string text = R"(
[structure]
half_width = 0.3
heights = [3.0, 6.0, 9.0]
masses = [10000.0, 8000.0, 6000.0]
second_moments = [6.0, 5.0, 4.0]
youngs_modulus = 1.0e8
damping_ratio = 0.03
base_mass = 8000.0

[columns]
count = 2
half_width = 0.4
half_height = 2.5
mass = 4000.0
spacing = 8.0

[contact]
restitution = "momentum"

[[device]]
name = "tie"
kind = "elastic"
at = 0.0
kinematics = "vertical"
free_length = 5.0
P0 = 20e3
k = 5e7

[[device]]
name = "yielding"
kind = "bouc-wen"
at = "edges"
kinematics = "chord"
k = 4e7
eps = 0.05
d_y = 0.001

[excitation]
pulse = "one-sine"
amplitude_g = 0.35
period = 0.6
duration = 4.0
)";
  const Ran ran = run(scene_from("damped", text));
  REQUIRE(ran.result.outcome == Outcome::completed);
  REQUIRE(ran.result.counts.uplifts >= 1);
  REQUIRE(ran.result.counts.impacts >= 2);
  const EnergyBalance& e = ran.result.energy;
  CHECK(e.damper > 0);
  CHECK(e.residual() == within(0.0, 1e-6 * e.ground));
  double works = 0;
  REQUIRE(ran.result.devices.size() == 3);  // tie, yielding_left, yielding_right
  for (const DeviceResult& d : ran.result.devices) {
    CAPTURE(d.name);
    CHECK(d.peak_elongation > 0);
    works += d.work;
  }
  CHECK(works == close_to(e.damper, 1e-9));
  // The history's running terms end at the totals, and M_dev is the n devices' moment.
  const Response& last = ran.watch.rows.back();
  CHECK(last[Quantity::work_devices] == close_to(e.damper, 1e-6, 1e-9 * e.ground));
  MESSAGE("W_ground " << e.ground << " J, W_devices " << e.damper << " J, residual " << e.residual() << " J");
}

TEST_CASE("a device at a column's edge reaching its capacity fractures at the tilt its chord gives, in every column at once") {
  const Frame f;
  const double l = 2 * b, theta_f = 0.3 * f.alpha;
  const double capacity = 2 * l * std::sin(0.5 * theta_f);
  const std::string device = fmt::format(
      "[[device]]\nname = \"plate\"\nkind = \"elastic\"\nat = {}\nkinematics = \"chord\"\nP0 = 0.0\nk = 1e6\ncapacity = {:.17g}\n", -b,
      capacity);
  const std::string tilt = fmt::format("\n[initial]\ntheta_dot = 0.2\n");
  const Ran ran = run(scene_from("plate", frame(device, tilt + still(1.0))));
  const auto at = std::ranges::find_if(ran.watch.events, [](const Event& e) { return e.kind == EventKind::fracture; });
  REQUIRE(at != ran.watch.events.end());
  REQUIRE(at->device == 0);
  const Response& row = ran.watch.rows.at(ran.watch.row_after[static_cast<std::size_t>(at - ran.watch.events.begin())]);
  CHECK(row[Quantity::columns_theta] == close_to(theta_f, 1e-6));
  CHECK(ran.result.devices[0].fracture_time == close_to(at->t, 1e-12));
  CHECK(ran.result.devices[0].peak_elongation == close_to(capacity, 1e-6));
  MESSAGE("fractured at " << at->t << " s, theta " << row[Quantity::columns_theta] << " rad (chord gives " << theta_f << ")");
}

TEST_CASE("the program runs the rocking frame with a tie through each pier and with dampers: device columns by name, summary, and a study without the dampers") {
  const std::filesystem::path frame_scene = std::filesystem::path(ROCKING_SCENES) / "rocking_frame.toml";
  const std::string tie = "device+={kind=\"elastic\",name=\"tie\",at=0.0,kinematics=\"vertical\",free_length=9.6,P0=2e6,k=5e8}";
  const std::filesystem::path out = temp_path("frame_tie");
  const cli::Result r = cli::run(fmt::format("-q simulate {} --set '{}' --out {}", frame_scene.string(), tie, out.string()));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string history = file_text(out / "history.csv");
  const std::string header = history.substr(0, history.find('\n'));
  for (const std::string name : {"tie.elongation", "tie.force", "M_dev"}) CHECK_MESSAGE(cli::contains(header, name + " ["), header);
  const auto summary = nlohmann::json::parse(file_text(out / "summary.json"));
  REQUIRE(summary["devices"].size() == 1);
  CHECK(summary["devices"][0]["name"] == "tie");
  CHECK(summary["devices"][0]["peak_force_N"].get<double>() >= 2e6);
  // Without the tie the same pulse rocks the frame further.
  const cli::Result bare = cli::run(fmt::format("-q simulate {} --out {}", frame_scene.string(), (out / "bare").string()));
  REQUIRE_MESSAGE(bare.code == 0, bare.err);
  const auto bare_summary = nlohmann::json::parse(file_text(out / "bare" / "summary.json"));
  CHECK(summary["columns"]["peak_theta"].get<double>() < bare_summary["columns"]["peak_theta"].get<double>());
  // A study's default variants: as built, and without the dissipating devices; no failed row.
  const std::string dampers =
      "device+={kind=\"bouc-wen\",name=\"yielding\",at=\"edges\",kinematics=\"chord\",k=2e8,eps=0.05,d_y=0.002}";
  const std::string record = rocking_record(out / "sine.txt", 6.0);
  const cli::Result ida = cli::run(fmt::format("-q ida {} --set '{}' --record {} --scales 1,2 --no-plot --out {}",
                                               frame_scene.string(), dampers, record, (out / "ida").string()));
  REQUIRE_MESSAGE(ida.code == 0, ida.err);
  const CsvTable rows = csv_table(file_text(out / "ida" / "ida.csv"));
  REQUIRE(rows.rows.size() == 4);
  int without = 0;
  for (std::size_t i = 0; i < rows.rows.size(); ++i) {
    CAPTURE(i);
    CHECK(rows.at(i, "outcome") != "failed");
    without += rows.at(i, "variant") == "without:yielding" ? 1 : 0;
  }
  CHECK(without == 2);
}

TEST_CASE("a device on columns anchored off a column's base: exit 2 naming the key and the column's half-width") {
  const std::filesystem::path frame_scene = std::filesystem::path(ROCKING_SCENES) / "rocking_frame.toml";
  cli::refused(fmt::format("simulate {} --set 'device+={{kind=\"elastic\",name=\"tie\",at=1.0,kinematics=\"vertical\","
                           "free_length=9.6,P0=0.0,k=1e7}}' --out {}",
                           frame_scene.string(), temp_path("off_base").string()),
               "column's base");
}
