// A device between the ground and the cap beam of a structure on rocking
// columns (MODEL.md 16 with 11; [[device]] kinematics = "beam"): one device,
// its elongation the change of the distance between a ground anchor and an
// anchor on the beam's underside, its moment F de/d|theta|. Checked against
// closed forms computed here from the scene's numbers, with the beam's motion
// taken from a column's rigid rotation about its pivot corner (the top corner
// opposite it carries the beam), not from rocking.columns:
// - the uplift threshold under a ramp a_g = c t with a prestressed tendon,
//   vertical (it raises the threshold on both sides) and inclined (it lowers
//   it on one), by virtual work at theta = 0, to 1e-6 of the first uplift's
//   time; the column-top forces at rest carrying the tendon's pull (statics);
// - free rocking from a tilt with an elastic inclined device: the first impact
//   at the quadrature of the energy equation (gravity's potential and the
//   device's P0 e + k e^2 / 2) to 1e-6, the energy balance closing to 1e-9
//   of the initial energy, the device's peak elongation and force;
// - against the independent reference tests/columns_reference.hpp (MODEL.md
//   16 with 11's devices, written without rocking.columns): a flexible
//   structure on two columns with an inclined prestressed beam tendon and a
//   Bouc-Wen damper at each column's edges under a pulse, its first uplift,
//   its first impact and every history row's theta, theta' and M_dev up to it,
//   to 1e-6;
// - bad input, each refused key in one line (exit 2).
// Runs use rk45 at rtol 1e-10 (atol 1e-12), far below the tolerances stated.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <gsl/gsl_integration.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "close.hpp"
#include "columns_frame.hpp"
#include "columns_reference.hpp"
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

// An elastic device from the ground at (gx, gy) to the beam's underside at bx.
std::string tie(double gx, double gy, double bx, double P0, double k) {
  return fmt::format("[[device]]\nname = \"tie\"\nkind = \"elastic\"\nkinematics = \"beam\"\nat = {}\nground_height = {}\n"
                     "beam_at = {}\nP0 = {}\nk = {}\n",
                     gx, gy, bx, P0, k);
}

using Ran = WatchedRun<EventsAndRows>;
template <class... Args>
Ran run(const Scene& scene, Args&&... args) {
  return watched_run<EventsAndRows>(scene, 1e-10, std::forward<Args>(args)...);
}

// The beam's displacement when the columns turn by th (> 0) about their right
// corners: the top-left corner, at (-2b, 2h) from the pivot, turned clockwise.
struct Vec {
  double x, y;
};
Vec beam_shift(double th) {
  const double c = std::cos(th), s = std::sin(th);
  return {-2 * b * c + 2 * h * s + 2 * b, 2 * b * s + 2 * h * c - 2 * h};
}

}  // namespace

TEST_CASE("a prestressed tendon from the ground to the cap beam moves the frame's uplift threshold by its virtual work: the first uplift under a ramp at the closed form's time") {
  const Frame f;
  const double c = 1.0, g = gravity, P0 = 20e3;  // [m/s^3], [N]
  const double W = n * mc + 2 * f.m_d;          // the columns' centres rise by b per |theta|, the deck by 2b
  const auto ramp = std::make_shared<const GroundMotion>(GroundMotion::from_samples("ramp", {0.0, 10.0}, {0.0, 10 * c}));
  // From the ground at x = -1 m: straight up to the beam (lever 2b about either
  // side), and up to x = 2 m on the beam (3-4-5: it slackens as the frame tips left).
  for (const double bx : {-1.0, 2.0}) {
    CAPTURE(bx);
    const double gx = -1.0, rx = bx - gx, ry = 2 * h, r = std::hypot(rx, ry);
    // At theta = 0 the beam moves by (s 2h, 2b) per |theta| about s: de/d|theta| = n . (s 2h, 2b).
    auto lever = [&](int s) { return (rx * s * 2 * h + ry * 2 * b) / r; };
    // a_g > 0 tips the frame to the left (s = -1): the ground's inertia does
    // a_g h W per |theta|, gravity -g b W, the tendon -P0 de/d|theta|.
    const double a_star = (g * b * W + P0 * lever(-1)) / (h * W);
    REQUIRE(a_star > 0);
    const Scene scene = scene_from("beam_tie", frame(tie(gx, 0.0, bx, P0, 1e7), ""));
    const Ran ran = run(scene, ramp, 1.05 * a_star / c);
    REQUIRE(!ran.watch.events.empty());
    CHECK(ran.watch.events.front().kind == EventKind::uplift);
    CHECK(ran.watch.events.front().pivot == Pivot::left);
    CHECK(ran.result.first_uplift == close_to(a_star / c, 1e-6));
    // rocking modal: the weaker side's held moment, min over s of P0 de/d|theta|.
    const double held = std::min(P0 * lever(-1), P0 * lever(+1));
    CHECK(modal_summary(scene)["columns"]["uplift_g"].get<double>() == close_to(b / h + held / (g * h * W), 1e-12));
    // At rest (a_g(0) = 0) the columns carry the deck's weight and the tendon's
    // pull -P0 (rx, ry) / r at (bx, 0) from the beam's centre; split linearly
    // over the axes -3, 0, 3 m (minimum norm): N = sum N / 3 + M x / 18.
    REQUIRE(!ran.watch.rows.empty());
    const double sum = f.m_d * g + P0 * ry / r, moment = bx * P0 * ry / r;
    const double smallest = sum / 3 - 3 * std::abs(moment) / 18;
    CHECK(ran.watch.rows.front()[Quantity::columns_top_force] == close_to(smallest, 1e-12));
    MESSAGE("tendon to x = " << bx << " m: uplift at " << ran.result.first_uplift << " s, closed form " << a_star / c
                             << " s (bare frame " << g * b / h / c << " s)");
  }
}

TEST_CASE("an elastic device from the ground to the cap beam: free rocking from a tilt lands at the quadrature of the energy equation, and the energy balance closes") {
  const Frame f;
  const double k = 2e5, P0 = 5e3, g = gravity, gx = -1.0, bx = 2.0;
  const double rx = bx - gx, ry = 2 * h, r0 = std::hypot(rx, ry);
  // Tilted to the right the beam moves right and up: the device stretches.
  auto e_of = [&](double th) {
    const Vec d = beam_shift(th);
    return std::hypot(rx + d.x, ry + d.y) - r0;
  };
  const double th0 = 0.5 * f.alpha;
  auto U = [&](double th) {
    const double e = e_of(th);
    return f.lever * g * (std::cos(f.alpha - th) - std::cos(f.alpha)) + P0 * e + 0.5 * k * e * e;
  };
  const double t_quad = fall_time(U, th0, f.J);

  const std::string tilt = fmt::format("\n[initial]\ntheta = {:.17g}\n", th0);
  const Ran with = run(scene_from("beam_spring", frame(tie(gx, 0.0, bx, P0, k), tilt + still(1.2 * t_quad))));
  REQUIRE_MESSAGE(with.result.outcome == Outcome::completed, with.result.failure);
  REQUIRE(with.result.counts.impacts >= 1);
  CHECK(with.result.first_impact == close_to(t_quad, 1e-6));
  const Ran without = run(scene_from("beam_bare", frame("", tilt + still(4 * t_quad))));
  REQUIRE(without.result.counts.impacts >= 1);
  CHECK(with.result.first_impact < without.result.first_impact);
  // Released at rest, the device's peak is at the release.
  REQUIRE(with.result.devices.size() == 1);
  CHECK(with.result.devices[0].peak_elongation == close_to(e_of(th0), 1e-9));
  CHECK(with.result.devices[0].peak_force == close_to(P0 + k * e_of(th0), 1e-9));
  // No damping and no ground: the device's work is what the frame's energy lost (impacts aside).
  const EnergyBalance& eb = with.result.energy;
  CHECK(eb.residual() == within(0.0, 1e-9 * eb.initial));
  CHECK(with.result.devices[0].work == close_to(eb.damper, 1e-12));
  MESSAGE("first impact " << with.result.first_impact << " s (quadrature " << t_quad << " s; " << without.result.first_impact
                          << " s without the device); residual " << eb.residual() << " J of " << eb.initial << " J");
}

TEST_CASE("a beam device through the program: history columns by name, and each refused key in one line (exit 2)") {
  const std::string frame_scene = (std::filesystem::path(ROCKING_SCENES) / "rocking_frame.toml").string();
  const std::filesystem::path out = temp_path("frame_beam_tie");
  const std::string tendon = "device+={kind=\"elastic\",name=\"tie\",kinematics=\"beam\",at=0.0,beam_at=0.0,P0=2e6,k=5e8}";
  const cli::Result r = cli::run(fmt::format("-q simulate {} --set '{}' --out {}", frame_scene, tendon, out.string()));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string history = file_text(out / "history.csv");
  const std::string header = history.substr(0, history.find('\n'));
  for (const std::string name : {"tie.elongation", "tie.force", "M_dev"})
    CHECK_MESSAGE(cli::contains(header, name + " ["), header);
  const auto summary = nlohmann::json::parse(file_text(out / "summary.json"));
  REQUIRE(summary["devices"].size() == 1);
  CHECK(summary["devices"][0]["peak_force_N"].get<double>() >= 2e6);
  CHECK(summary["devices"][0]["work_J"].is_number());

  auto refused = [&](const std::string& scene, const std::string& device, const std::string& says) {
    cli::refused(fmt::format("simulate {} --set 'device+={{{}}}' --out {}", scene, device, temp_path("refused").string()),
                 says);
  };
  const std::string block = (std::filesystem::path(ROCKING_SCENES) / "rigid_block.toml").string();
  const std::string tendon_keys = "kind=\"elastic\",name=\"tie\",P0=0.0,k=1e7";
  // No [columns]: no beam, and no beam anchor.
  refused(block, tendon_keys + ",kinematics=\"beam\",at=0.0", "device[0].kinematics");
  refused(block, tendon_keys + ",kinematics=\"vertical\",free_length=2.0,at=0.0,beam_at=0.0", "device[0].beam_at");
  // The beam anchor: required, on the beam (|x| <= 3 + 0.8 m).
  refused(frame_scene, tendon_keys + ",kinematics=\"beam\",at=0.0", "device[0].beam_at");
  refused(frame_scene, tendon_keys + ",kinematics=\"beam\",at=0.0,beam_at=3.9", "device[0].beam_at");
  // The elongation counts from the rest distance.
  refused(frame_scene, tendon_keys + ",kinematics=\"beam\",at=0.0,beam_at=0.0,free_length=9.6", "device[0].free_length");
  // A number for the ground anchor.
  refused(frame_scene, tendon_keys + ",kinematics=\"beam\",at=\"edges\",beam_at=0.0", "device[0].at");
  // Anchors that meet at rest.
  refused(frame_scene, tendon_keys + ",kinematics=\"beam\",at=1.0,beam_at=1.0,ground_height=9.6", "device[0].ground_height");
  // A column device has no beam anchor.
  refused(frame_scene, tendon_keys + ",kinematics=\"chord\",at=0.0,beam_at=0.0", "device[0].beam_at");
  refused(frame_scene, tendon_keys + ",kinematics=\"vertical\",free_length=9.6,at=0.0,ground_height=1.0",
          "device[0].ground_height");
}

TEST_CASE("an inclined beam tendon and a yielding damper at each column's edges under a pulse: the program's run is the independent reference's to 1e-6 up to the first impact") {
  // A flexible three-storey structure on two piers (columns_run_test's), a
  // tendon from the ground at x = 1.5 m to the beam's underside at x = -1 m
  // (50 kN prestress), and a Bouc-Wen plate at both edges of each column's base.
  // The pulse pushes the frame to the left first, where the tendon, leaning
  // left from its ground anchor, holds it down.
  const std::string text = R"(
[structure]
half_width = 0.3
heights = [3.0, 6.0, 9.0]
masses = [10000.0, 8000.0, 6000.0]
second_moments = [6.0, 5.0, 4.0]
youngs_modulus = 1.0e8
damping_ratio = 0.05
base_mass = 8000.0

[columns]
count = 2
half_width = 0.15
half_height = 2.5
mass = 3000.0
spacing = 4.0

[contact]
restitution = "momentum"

[[device]]
name = "tie"
kind = "elastic"
kinematics = "beam"
at = 1.5
ground_height = 0.0
beam_at = -1.0
P0 = 5e4
k = 2e6

[[device]]
name = "plate"
kind = "bouc-wen"
at = "edges"
kinematics = "chord"
k = 4e7
eps = 0.05
d_y = 0.001
alpha = 0.6
beta = 0.4
n = 1.0
)";
  // A one-sine pulse of 0.3 g and 0.7 s, sampled every 5 ms, then still.
  std::vector<double> t, ah;
  for (int k = 0; k <= 1200; ++k) {
    const double tk = 0.005 * k;
    t.push_back(tk);
    ah.push_back(tk < 0.7 ? 0.3 * gravity * std::sin(2 * std::numbers::pi * tk / 0.7) : 0.0);
  }
  const auto motion = std::make_shared<const GroundMotion>(GroundMotion::from_samples("pulse", t, ah));
  const Scene scene = scene_from("tie_and_plates", text);
  const Ran ran = run(scene, motion, 6.0);
  REQUIRE(ran.watch.events.size() >= 2);
  REQUIRE(ran.watch.events[0].kind == EventKind::uplift);
  REQUIRE(ran.watch.events[1].kind == EventKind::impact);

  // The reference: the same frame from MODEL.md 16 and 11, K and C as rocking.beam assembles them.
  RunSpec spec;
  spec.scene = scene;
  spec.motion.given = motion;
  const PreparedRun p = prepare_run(spec);
  const Columns& c = p.model.on_columns->columns;
  colref::Frame f;
  f.n = 2;
  f.b = 0.15;
  f.h = 2.5;
  f.mc = 3000;
  f.xcol = {-2.0, 2.0};
  f.mb = 8000;
  f.m = {10000, 8000, 6000};
  f.H = {3, 6, 9};
  f.flexible = true;
  f.g = gravity;
  for (Eigen::Index i = 0; i < 3; ++i)
    for (Eigen::Index j = 0; j < 3; ++j) {
      f.K.push_back(c.matrices.K(i, j));
      f.C.push_back(c.matrices.C(i, j));
    }
  colref::Device tie;
  tie.kin = colref::Kinematics::beam;
  tie.x = 1.5;
  tie.gy = 0.0;
  tie.bx = -1.0;
  tie.P0 = 5e4;
  tie.k = 2e6;
  colref::Device plate;
  plate.kin = colref::Kinematics::chord;
  plate.law = colref::Law::bouc_wen;
  plate.k = 4e7;
  plate.eps = 0.05;
  plate.dy = 0.001;
  plate.alpha = 0.6;
  plate.beta = 0.4;
  plate.nbw = 1.0;
  colref::Device left = plate, right = plate;
  left.x = -f.b;
  right.x = f.b;
  f.dev = {tie, left, right};
  colref::Ground gm{t, ah, std::vector<double>(t.size(), 0.0)};
  colref::State rest;
  rest.u.assign(3, 0.0);
  rest.ud.assign(3, 0.0);
  rest.z.assign(3, 0.0);
  // The rows' times, each phase its own.
  std::vector<double> contact_times, rocking_times;
  const colref::RunResult up0 = colref::full_contact_until_uplift(f, rest, 0.0, gm, {.t_end = 6.0, .out_times = {}});
  REQUIRE(up0.outcome == colref::Outcome::Uplift);
  for (const Response& r : ran.watch.rows) (r.t < up0.t ? contact_times : rocking_times).push_back(r.t);
  const colref::RunResult up = colref::full_contact_until_uplift(f, rest, 0.0, gm, {.t_end = 6.0, .out_times = contact_times});
  colref::State lifted = up.state;
  lifted.s = up.uplift_s;
  const colref::RunResult hit = colref::first_impact(f, lifted, up.t, gm, {.t_end = 6.0, .out_times = rocking_times});
  REQUIRE(hit.outcome == colref::Outcome::Impact);
  CHECK(hit.min_top_N > 0);  // the beam stays on the columns: the program does not stop as separated
  CHECK(ran.result.first_uplift == close_to(up.t, 1e-6));
  CHECK(ran.watch.events[0].pivot == (up.uplift_s > 0 ? Pivot::right : Pivot::left));
  CHECK(ran.result.first_impact == close_to(hit.t, 1e-6));
  // The tendon holds the frame down about the side it lifts on (a positive moment at rest).
  REQUIRE(up.uplift_s == -1);
  const double D0 = colref::device_moment_at_rest(f, rest, up.uplift_s);
  CHECK(D0 > 0);

  // Every row before the impact: theta, theta' and the devices' moment (signed as theta). The
  // row recorded at the uplift is the rocking phase's first (theta = 0): the devices hold D_0 there.
  std::vector<colref::State> states = up.out;
  states.insert(states.end(), hit.out.begin(), hit.out.end());
  std::size_t compared = 0;
  double peak_th = 0, peak_thd = 0, peak_m = 0;
  std::vector<double> ref_m(states.size());
  const std::size_t uplift_row = ran.watch.row_after[0];
  for (std::size_t k = 0; k < states.size(); ++k) {
    ref_m[k] = k == uplift_row ? up.uplift_s * D0 : states[k].s * colref::device_moment(f, states[k]);
    peak_th = std::max(peak_th, std::abs(states[k].th));
    peak_thd = std::max(peak_thd, std::abs(states[k].thd));
    peak_m = std::max(peak_m, std::abs(ref_m[k]));
  }
  REQUIRE(peak_th > 0.1 * f.b / f.h);
  double worst = 0;  // the largest difference over the quantity's peak
  for (std::size_t k = 0; k < ran.watch.rows.size() && ran.watch.rows[k].t < hit.t - 1e-6; ++k) {
    const Response& r = ran.watch.rows[k];
    REQUIRE(k < states.size());
    CAPTURE(r.t);
    worst = std::max({worst, std::abs(r[Quantity::columns_theta] - states[k].th) / peak_th,
                      std::abs(r[Quantity::columns_theta_dot] - states[k].thd) / peak_thd,
                      std::abs(r[Quantity::device_moment] - ref_m[k]) / peak_m});
    CHECK(r[Quantity::columns_theta] == within(states[k].th, 1e-6 * peak_th));
    CHECK(r[Quantity::columns_theta_dot] == within(states[k].thd, 1e-6 * peak_thd));
    CHECK(r[Quantity::device_moment] == within(ref_m[k], 1e-6 * peak_m));
    ++compared;
  }
  CHECK(compared > 50);
  MESSAGE("uplift " << ran.result.first_uplift << " s (reference " << up.t << " s), first impact " << ran.result.first_impact
                    << " s (reference " << hit.t << " s); " << compared << " rows, peak theta " << peak_th
                    << " rad, peak M_dev " << peak_m << " N m, held moment at rest " << D0
                    << " N m; largest row difference " << worst << " of the peak");
}
