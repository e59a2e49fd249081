// Scenes on [columns] (MODEL.md 16), run the way every front end runs them
// (rocking.run's prepare_run, then simulate; and the program itself): a
// rigid frame released from a tilt against section 16's closed forms (first
// impact by quadrature with p-hat, r), unchanged when the deck's mass sits
// higher; a flexible structure on columns against the independent reference
// tests/columns_reference.hpp to its first impact; squat columns that never
// lift against the fixed-base run (and the shipped chimney on columns made
// squat against its fixed-base twin); the energy balance; a tensile top
// contact as a stated outcome; the rigid frame's overturning spectrum against
// the single block's with p-hat and the frame's r; a study's limit on the
// columns' rocking; bad input; rosw at the default tolerances against rk45
// on the shipped scenes (rosw_events.hpp). Other runs use rk45 at rtol 1e-10, so that the
// tolerances stated (1e-6 for event times and ratios, as the issue states
// them; 1e-6 of the energy scale for the balance) sit far above the
// integration error; the closed forms are computed from the scene's numbers,
// not from the run.
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
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "close.hpp"
#include "columns_reference.hpp"
#include "csv_table.hpp"
#include "frame_quadrature.hpp"
#include "rocking_record.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"
#include "scene_file.hpp"
#include "watched_run.hpp"
#include "records.hpp"
#include "rosw_events.hpp"
import rocking.run;
import rocking.study;
import rocking.errors;

using namespace rocking;

namespace {

std::filesystem::path write_scene(const std::string& name, const std::string& toml) {
  const std::filesystem::path path = temp_path(name + ".toml");
  std::ofstream(path) << toml;
  return path;
}

// A rigid deck (a cap beam and two masses) on three columns 0.5 m wide, 4 m
// tall, 6 m apart: alpha = atan(0.25 / 2).
constexpr double b3 = 0.25, h3 = 2.0, mc3 = 2000.0, beam3 = 6000.0;
std::string rigid_frame(double height_scale, const std::string& more) {
  return fmt::format(R"(
[structure]
rigid = true
half_width = 0.25
heights = [{}, {}]
masses = [4000.0, 3000.0]
base_mass = {}

[columns]
count = 3
half_width = {}
half_height = {}
mass = {}
spacing = 6.0

[contact]
restitution = "momentum"
{})",
                     1.0 * height_scale, 3.0 * height_scale, beam3, b3, h3, mc3, more);
}

// A flexible three-storey structure on two piers.
std::string flexible_frame(double zeta, const std::string& columns, const std::string& more) {
  return fmt::format(R"(
[structure]
half_width = 0.3
heights = [3.0, 6.0, 9.0]
masses = [10000.0, 8000.0, 6000.0]
second_moments = [6.0, 5.0, 4.0]
youngs_modulus = 1.0e8
damping_ratio = {}
base_mass = 8000.0

{}
{})",
                     zeta, columns, more);
}

std::string still(double duration) { return fmt::format("\n[excitation]\nkind = \"none\"\nduration = {}\n", duration); }

using Ran = WatchedRun<EventsAndRows>;
template <class... Args>
Ran run(const Scene& scene, double rtol, Args&&... args) {
  return watched_run<EventsAndRows>(scene, rtol, std::forward<Args>(args)...);
}

}  // namespace

TEST_CASE("a rigid frame released from a tilt: the first impact at the quadrature with p-hat and the rate after it by 16's r, to 1e-6, unchanged when the deck sits higher") {
  // Section 16's closed forms from the scene's numbers.
  const double R = std::hypot(b3, h3), alpha = std::atan2(b3, h3), g = gravity;
  const double gamma = (beam3 + 4000.0 + 3000.0) / (3 * mc3);
  const double p2_hat = 3 * g / (4 * R) * (1 + 2 * gamma) / (1 + 3 * gamma);
  const double r = (1 - 1.5 * std::pow(std::sin(alpha), 2) + 3 * gamma * std::cos(2 * alpha)) / (1 + 3 * gamma);
  const double th0 = 0.5 * alpha;
  const double t_quad = quadrature_impact_time(alpha, p2_hat, th0);
  const double rate_before = -std::sqrt(2 * p2_hat * (std::cos(alpha - th0) - std::cos(alpha)));
  const std::string tilt = fmt::format("\n[initial]\ntheta = {:.17g}\n", th0);

  double first_impact[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const double scale = k == 0 ? 1.0 : 3.0;
    CAPTURE(scale);
    const Ran ran = run(scene_from("frame", rigid_frame(scale, tilt + still(1.5 * t_quad))), 1e-10);
    REQUIRE(ran.result.outcome == Outcome::completed);
    REQUIRE(ran.result.counts.impacts >= 1);
    first_impact[k] = ran.result.first_impact;
    CHECK(ran.result.first_impact == close_to(t_quad, 1e-6));
    const auto impact = std::ranges::find_if(ran.watch.events, [](const Event& e) { return e.kind == EventKind::impact; });
    REQUIRE(impact != ran.watch.events.end());
    const std::size_t row = ran.watch.row_after[static_cast<std::size_t>(impact - ran.watch.events.begin())];
    REQUIRE(row < ran.watch.rows.size());
    const Response& after = ran.watch.rows[row];
    CHECK(after.t == close_to(t_quad, 1e-6));
    CHECK(after[Quantity::columns_theta_dot] / rate_before == close_to(r, 1e-6));
    CHECK(after.phase == Phase::rocking(Pivot::left));
    MESSAGE("deck heights x" << scale << ": first impact " << ran.result.first_impact << " s (quadrature " << t_quad
                             << " s), rate ratio " << after[Quantity::columns_theta_dot] / rate_before << " (16's r "
                             << r << ")");
    // The peak tilt is the release's, and the beam moved by 16's dx at it.
    CHECK(ran.result.peak(Quantity::columns_theta) == close_to(th0, 1e-9));
    CHECK(ran.result.peak(Quantity::beam_x) ==
          close_to(2 * R * (std::sin(alpha) - std::sin(alpha - th0)), 1e-9));
  }
  CHECK(first_impact[1] == close_to(first_impact[0], 1e-6));
}

TEST_CASE("the program's rigid frame overturns from a tilt past alpha's point of no return, and rosw agrees with rk45 on the first impact") {
  const double alpha = std::atan2(b3, h3);
  const Ran over = run(scene_from("frame", rigid_frame(1, fmt::format("\n[initial]\ntheta = {:.17g}\ntheta_dot = 0.3\n", 0.9 * alpha) +
                                                             still(5.0))),
                       1e-10);
  CHECK(over.result.outcome == Outcome::overturned);
  const std::string tilt = fmt::format("\n[initial]\ntheta = {:.17g}\n", 0.5 * alpha) + still(1.0);
  const Ran rk = run(scene_from("frame", rigid_frame(1, tilt)), 1e-10);
  const Ran ro = run(scene_from("frame", rigid_frame(1, tilt)), 1e-10, nullptr, std::nullopt, "rosw");
  REQUIRE(rk.result.counts.impacts >= 1);
  REQUIRE(ro.result.counts.impacts >= 1);
  CHECK(ro.result.integrator != rk.result.integrator);
  CHECK(ro.result.first_impact == close_to(rk.result.first_impact, 1e-6));
}

TEST_CASE("a flexible structure on columns under a record: the program's first uplift and first impact are the independent reference's to 1e-6") {
  // A record of 0.3 g at 1.5 Hz (with 0.1 g vertical at 2.7 Hz), sampled every 5 ms.
  std::vector<double> t, ah, av;
  for (int k = 0; k <= 1200; ++k) {
    const double tk = 0.005 * k;
    t.push_back(tk);
    ah.push_back(0.3 * gravity * std::sin(2 * std::numbers::pi * 1.5 * tk));
    av.push_back(0.1 * gravity * std::sin(2 * std::numbers::pi * 2.7 * tk + 0.3));
  }
  const auto motion = std::make_shared<const GroundMotion>(GroundMotion::from_samples("sine", t, ah));
  const auto up_motion = std::make_shared<const GroundMotion>(GroundMotion::from_samples("sine up", t, av));
  const std::string columns = "[columns]\ncount = 2\nhalf_width = 0.15\nhalf_height = 2.5\nmass = 3000.0\nspacing = 4.0\n";
  const Scene scene = scene_from("flexible", flexible_frame(0.05, columns, "[contact]\nrestitution = \"momentum\"\n"));
  const Ran ran = run(scene, 1e-10, motion, 6.0, "rk45", up_motion);
  REQUIRE(ran.result.counts.uplifts >= 1);
  CHECK(ran.result.reports(Quantity::a_v));
  REQUIRE(ran.result.counts.impacts >= 1);

  // The reference: the same frame from MODEL.md 16 alone, K and C as rocking.beam assembles them.
  RunSpec spec{.scene = scene};
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
  colref::Ground gm{t, ah, av};
  colref::State rest;
  rest.u.assign(3, 0.0);
  rest.ud.assign(3, 0.0);
  const colref::RunResult up = colref::full_contact_until_uplift(f, rest, 0.0, gm, {.t_end = 6.0});
  REQUIRE(up.outcome == colref::Outcome::Uplift);
  colref::State lifted = up.state;
  lifted.s = up.uplift_s;
  const colref::RunResult hit = colref::first_impact(f, lifted, up.t, gm, {.t_end = 6.0});
  REQUIRE(hit.outcome == colref::Outcome::Impact);
  CHECK(ran.result.first_uplift == close_to(up.t, 1e-6));
  CHECK(ran.watch.events.front().pivot == (up.uplift_s > 0 ? Pivot::right : Pivot::left));
  CHECK(ran.result.first_impact == close_to(hit.t, 1e-6));
  MESSAGE("uplift " << ran.result.first_uplift << " s (reference " << up.t << " s), first impact "
                    << ran.result.first_impact << " s (reference " << hit.t << " s)");
  // The energy balance closes (damping, ground input horizontal and vertical, impacts).
  const EnergyBalance& e = ran.result.energy;
  const double scale = std::max({std::abs(e.ground), std::abs(e.viscous), std::abs(e.impacts), std::abs(e.final)});
  CHECK(e.residual() == within(0.0, 1e-6 * scale));
  MESSAGE("energy: ground " << e.ground << " J, viscous " << e.viscous << " J, impacts " << e.impacts << " J, residual "
                            << e.residual() << " J");
}

TEST_CASE("columns too squat to rock: the structure on them responds as on a fixed base to 1e-6") {
  const std::string pulse = "\n[excitation]\npulse = \"one-sine\"\namplitude_g = 0.3\nperiod = 0.4\nduration = 3.0\n";
  // Columns 6 m wide and 1 m tall (alpha = atan 6): no horizontal motion lifts them. The outer columns stand
  // 12 m apart, so that the structure's overturning moment (about 0.3 g on 132 t m of first moment, twice
  // amplified: 0.78 MN m, or 65 kN at each top) stays far below the half weight each top carries (157 kN).
  const std::string squat = "[columns]\ncount = 2\nhalf_width = 3.0\nhalf_height = 0.5\nmass = 3000.0\nspacing = 12.0\n";
  const Ran on = run(scene_from("squat", flexible_frame(0.05, squat, pulse)), 1e-10);
  const Ran fixed = run(scene_from("fixed", flexible_frame(0.05, "[contact]\nrocking = false\n", pulse)), 1e-10);
  REQUIRE(on.result.outcome == Outcome::completed);
  CHECK(on.result.counts.uplifts == 0);
  for (Quantity q : {Quantity::delta_e, Quantity::delta_t, Quantity::base_shear, Quantity::base_moment, Quantity::a_top}) {
    CAPTURE(info(q).name);
    CHECK(on.result.peak(q) == close_to(fixed.result.peak(q), 1e-6));
  }
  REQUIRE(on.watch.rows.size() == fixed.watch.rows.size());
  double scale = 0;
  for (const Response& r : fixed.watch.rows) scale = std::max(scale, std::abs(r[Quantity::u_top]));
  for (std::size_t k = 0; k < on.watch.rows.size(); k += 10)
    CHECK(on.watch.rows[k][Quantity::u_top] == within(fixed.watch.rows[k][Quantity::u_top], 1e-6 * scale));
  MESSAGE("peak delta_e " << on.result.peak(Quantity::delta_e) << " on squat columns, " << fixed.result.peak(Quantity::delta_e)
                          << " on a fixed base");
}

TEST_CASE("free undamped rocking of a rigid frame conserves energy between impacts, and the impacts take what 16's r says") {
  const double alpha = std::atan2(b3, h3);
  // Released at half alpha, the frame (p-hat about 1.6 rad/s) first lands after about 0.8 s and then rocks in
  // half-cycles of about 1.6 s: 6 s hold at least three impacts.
  const std::string tilt = fmt::format("\n[initial]\ntheta = {:.17g}\n", 0.5 * alpha) + still(6.0);
  const Ran ran = run(scene_from("frame", rigid_frame(1, tilt)), 1e-11);
  REQUIRE(ran.result.counts.impacts >= 3);
  const EnergyBalance& e = ran.result.energy;
  CHECK(e.ground == 0.0);
  CHECK(e.viscous == 0.0);
  CHECK(e.residual() == within(0.0, 1e-9 * e.initial));
  // Each impact keeps r^2 of the kinetic energy (16's r), all of it there is at theta = 0.
  const double gamma = (beam3 + 7000.0) / (3 * mc3);
  const double r = (1 - 1.5 * std::pow(std::sin(alpha), 2) + 3 * gamma * std::cos(2 * alpha)) / (1 + 3 * gamma);
  const Ran one = run(scene_from("frame", rigid_frame(1, tilt)), 1e-11, nullptr, 1.5 * ran.result.first_impact);
  REQUIRE(one.result.counts.impacts == 1);
  CHECK(one.result.energy.impacts / one.result.energy.initial == close_to(1 - r * r, 1e-6));
}

TEST_CASE("a tall deck on a narrow frame pulls a column top into tension: the run stops there, stated") {
  // A heavy mass 20 m above the beam of two columns only 1 m apart, pushed hard.
  const std::string text = R"(
[structure]
rigid = true
half_width = 0.3
heights = [20.0]
masses = [20000.0]
base_mass = 1000.0

[columns]
count = 2
half_width = 0.3
half_height = 1.5
mass = 2000.0
spacing = 1.0

[excitation]
pulse = "one-sine"
amplitude_g = 0.5
period = 0.6
duration = 3.0
)";
  const Ran ran = run(scene_from("tension", text), 1e-8);
  CHECK(ran.result.outcome == Outcome::separated);
  CHECK(ran.result.stated.find("tensile") != std::string::npos);
  REQUIRE(ran.result.columns);
  CHECK(ran.result.columns->smallest_top_force <= 1e-3 * 21000 * gravity);
  MESSAGE(ran.result.stated);
}

TEST_CASE("the rigid frame's overturning spectrum is the single block's with p-hat and the frame's r, to the spectrum's grid") {
  // MODEL.md 16 from rigid_frame's numbers: three columns b3 x h3 under a deck of the beam and 7000 kg.
  const double alpha = std::atan2(b3, h3), R = std::hypot(b3, h3);
  const double gamma = (beam3 + 7000.0) / (3 * mc3);
  const double p_hat = std::sqrt(3 * gravity / (4 * R) * (1 + 2 * gamma) / (1 + 3 * gamma));
  const double r = (1 - 1.5 * std::pow(std::sin(alpha), 2) + 3 * gamma * std::cos(2 * alpha)) / (1 + 3 * gamma);
  // Housner's block with p = p-hat: a point mass g / p-hat^2 from its pivot, at the frame's alpha, with r given.
  const double Rb = gravity / (p_hat * p_hat);
  const Scene single = scene_from("single", fmt::format(R"(
[structure]
rigid = true
half_width = {:.17g}
heights = [{:.17g}]
masses = [1000.0]
base_mass = 0.0

[contact]
restitution = {:.17g}
)",
                                                        Rb * std::sin(alpha), Rb * std::cos(alpha), r));
  const Scene frame = scene_from("frame", rigid_frame(1, ""));
  std::vector<double> freqs, amps;
  for (int k = 1; k <= 12; ++k) freqs.push_back(0.5 * k);
  for (int k = 4; k <= 18; ++k) amps.push_back(0.25 * k);
  const BlockSpectrum f = overturning_spectrum(frame, 1.0, PulseShape::one_sine, freqs, amps, 2);
  const BlockSpectrum b = overturning_spectrum(single, 1.0, PulseShape::one_sine, freqs, amps, 2);
  CHECK(f.p == close_to(p_hat, 1e-12));
  CHECK(f.alpha == close_to(alpha, 1e-12));
  CHECK(b.p == close_to(p_hat, 1e-12));
  REQUIRE(f.complete == f.points.size());
  REQUIRE(b.complete == b.points.size());
  // Outcomes agree at every grid point, except where a point sits on the boundary of the overturning region in
  // both spectra (a neighbour on the grid has the other outcome), where the two integrations may fall either way.
  const std::size_t na = amps.size();
  auto on_boundary = [&](const BlockSpectrum& s, std::size_t k) {
    const std::size_t i = k / na, j = k % na;
    for (auto [di, dj] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
      const long ii = static_cast<long>(i) + di, jj = static_cast<long>(j) + dj;
      if (ii < 0 || jj < 0 || ii >= static_cast<long>(freqs.size()) || jj >= static_cast<long>(na)) continue;
      if (s.points[static_cast<std::size_t>(ii) * na + static_cast<std::size_t>(jj)].overturned != s.points[k].overturned)
        return true;
    }
    return false;
  };
  int overturned = 0, differ = 0;
  for (std::size_t k = 0; k < f.points.size(); ++k) {
    CAPTURE(f.points[k].frequency_ratio);
    CAPTURE(f.points[k].amplitude_ratio);
    CHECK(f.points[k].uplift == b.points[k].uplift);
    overturned += b.points[k].overturned;
    if (f.points[k].overturned != b.points[k].overturned) {
      ++differ;
      CHECK(on_boundary(f, k));
      CHECK(on_boundary(b, k));
    }
  }
  CHECK(overturned > 0);
  CHECK(overturned < static_cast<int>(b.points.size()));
  MESSAGE(overturned << " of " << b.points.size() << " pulses overturn the single block; the frame differs at " << differ
                     << " boundary points");
}

TEST_CASE("rocking spectrum on the shipped rocking frame scales its axes by the frame's p-hat") {
  const std::filesystem::path out = temp_path("frame_spectrum");
  const cli::Result r = cli::run(fmt::format("spectrum {}/rocking_frame.toml --sizes 1 --frequencies 1:2:1 "
                                             "--amplitudes 2:3:1 --formats svg --out {}",
                                             ROCKING_SCENES, out.string()),
                                 120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK_MESSAGE(cli::contains(r.out, "frame x1: 2 columns"), r.out);
  CHECK(std::filesystem::exists(out / "spectrum.svg"));
}

TEST_CASE("the shipped rocking frame runs through the program: history columns by name, summary keys, text summary") {
  const std::filesystem::path out = temp_path("frame_out");
  const cli::Result r = cli::run(fmt::format("simulate {}/rocking_frame.toml --out {}", ROCKING_SCENES, out.string()), 120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(cli::contains(r.out, "columns.theta_over_alpha"));
  CHECK(cli::contains(r.out, "smallest top contact force"));
  std::ifstream summary(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(summary);
  CHECK(s["outcome"] == "completed");
  REQUIRE(s.contains("columns"));
  CHECK(s["columns"]["uplifts"].get<long>() >= 1);
  CHECK(s["columns"]["smallest_top_force_N"].get<double>() > 0);
  CHECK(s["peaks"].contains("columns.theta_over_alpha"));
  CHECK(s["peaks"].contains("beam.x"));
  CHECK(!s["peaks"].contains("theta"));  // the deck does not rock on the beam
  std::ifstream history(out / "history.csv");
  std::string header;
  std::getline(history, header);
  for (const char* name : {"columns.theta", "columns.theta_over_alpha", "columns.theta_dot", "beam.x", "columns.top_force_min", "delta_t"})
    CHECK_MESSAGE(cli::contains(header, name), header);
}

TEST_CASE("a study limits the columns' rocking: --limit columns.theta_over_alpha, its ida.csv column against each row's own run") {
  // The shipped rocking frame (piers 1.6 m wide and 9.6 m tall: alpha = atan(0.8 / 4.8)) under a 0.25 g sine
  // (tests/rocking_record.hpp) at scales 1 and 2; each row's columns.theta_over_alpha is the run's peak columns'
  // angle (summary.json's columns object, `rocking simulate` at the row's scale) over alpha.
  const std::filesystem::path dir = scratch_dir("columns_ida");
  const std::string record = rocking_record(dir / "sine.txt", 6.0);
  const std::string scene = std::string(ROCKING_SCENES) + "/rocking_frame.toml";
  const cli::Result r = cli::run("-q ida " + scene + " --record " + record +
                                 " --variants scene --scales 1,2 --limit columns.theta_over_alpha=0.05 --no-plot --out " +
                                 (dir / "ida").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable ida = csv_table(file_text(dir / "ida" / "ida.csv"));
  for (const char* column : {"columns.theta", "columns.theta_over_alpha"}) CHECK_MESSAGE(ida.has(column), column);
  const double alpha = std::atan(0.8 / 4.8);
  REQUIRE(ida.rows.size() == 2);
  int reached = 0, completed = 0;
  for (std::size_t i = 0; i < ida.rows.size(); ++i) {
    if (ida.at(i, "outcome") == "overturned") ++reached;
    if (ida.at(i, "outcome") != "completed") continue;
    ++completed;
    const std::string scale = ida.at(i, "scale");
    CAPTURE(scale);
    const std::filesystem::path out = dir / ("run" + std::to_string(i));
    const cli::Result one =
        cli::run("-q simulate " + scene + " --record " + record + " --scale " + scale + " --out " + out.string());
    REQUIRE_MESSAGE(one.code == 0, one.err);
    const auto summary = nlohmann::json::parse(file_text(out / "summary.json"));
    const double peak = summary["columns"]["peak_theta"].get<double>();
    CHECK(summary["columns"]["peak_theta_over_alpha"].get<double>() == close_to(peak / alpha, 1e-8));
    const double ratio = std::stod(ida.at(i, "columns.theta_over_alpha"));
    CHECK(ratio == close_to(peak / alpha, 1e-8));  // both printed to 9 digits
    CHECK(std::stod(ida.at(i, "columns.theta")) == close_to(peak, 1e-8));
    reached += ratio >= 0.05 ? 1 : 0;
  }
  CHECK(completed >= 1);
  CHECK(reached >= 1);
  CHECK(cli::contains(file_text(dir / "ida" / "fragility.csv"), "columns.theta_over_alpha>=0.05"));
}

TEST_CASE("the shipped chimney on columns made squat responds as its fixed-base twin does, to 1e-6") {
  // Columns 6 m wide and 1 m tall (alpha = atan 6) under a 0.05 g pulse: they never lift, and the chimney on the
  // beam is the chimney on a fixed base (its twin: christchurch_chimney.toml, not rocking, without dampers).
  const std::vector<std::string> weak = {"excitation.amplitude_g=0.05"};
  std::vector<std::string> squat = weak, twin = weak;
  for (const char* s : {"columns.half_width=3.0", "columns.half_height=0.5"}) squat.emplace_back(s);
  for (const char* s : {"contact.rocking=false", "damper.enabled=false"}) twin.emplace_back(s);
  auto shipped = [](const char* file, const std::vector<std::string>& set) {
    return load_scene(std::string(ROCKING_SCENES) + "/" + file, set);
  };
  const Ran on = run(shipped("chimney_on_columns.toml", squat), 1e-10);
  const Ran fixed = run(shipped("christchurch_chimney.toml", twin), 1e-10);
  REQUIRE(on.result.outcome == Outcome::completed);
  CHECK(on.result.counts.uplifts == 0);
  REQUIRE(on.result.columns);
  CHECK(on.result.columns->smallest_top_force > 0);
  for (Quantity q : {Quantity::delta_e, Quantity::delta_t, Quantity::base_shear, Quantity::base_moment, Quantity::a_top}) {
    CAPTURE(info(q).name);
    CHECK(on.result.peak(q) == close_to(fixed.result.peak(q), 1e-6));
  }
}

TEST_CASE("bad columns input: exit 2 with one line naming the key") {
  const std::filesystem::path frame = std::filesystem::path(ROCKING_SCENES) / "rocking_frame.toml";
  const std::string out = temp_path("bad_out").string();
  for (const auto& [set, says] : std::vector<std::pair<std::string, std::string>>{
           {"columns.count=0", "columns.count"},
           {"columns.half_width=-1", "columns.half_width"},
           {"columns.half_height=0", "columns.half_height"},
           {"columns.mass=0", "columns.mass"},
           {"columns.spacing=1.0", "columns.spacing"},
           {"contact.restitution=eq9", "eq9"},
       })
    cli::refused(fmt::format("simulate {} --set '{}' --out {}", frame.string(), set, out), says);
  const std::filesystem::path both = write_scene("both", std::string(rigid_frame(1, "")) + "\n[[joint]]\nnode = 1\nhalf_width = 0.2\n");
  cli::refused(fmt::format("simulate {} --out {}", both.string(), out), "[[joint]]");
}

TEST_CASE("the deck lesson: under 0.5 g for 1 s the bent with its deck survives and its piers alone overturn") {
  // docs/teaching.md lesson 7's commands and numbers.
  const std::string frame = std::string(ROCKING_SCENES) + "/rocking_frame.toml";
  const std::string pulse = " --set excitation.amplitude_g=0.5 --set excitation.duration=15";
  const std::filesystem::path deck = temp_path("lesson_deck"), bare = temp_path("lesson_bare");
  const cli::Result a = cli::run("-q simulate " + frame + pulse + " --out " + deck.string(), 120);
  REQUIRE_MESSAGE(a.code == 0, a.err);
  const cli::Result b = cli::run("-q simulate " + frame + pulse +
                                     " --set structure.masses=[1.0] --set structure.base_mass=1.0 --out " + bare.string(),
                                 120);
  REQUIRE_MESSAGE(b.code == 0, b.err);
  const auto with = nlohmann::json::parse(file_text(deck / "summary.json"));
  const auto without = nlohmann::json::parse(file_text(bare / "summary.json"));
  CHECK(with["outcome"] == "completed");
  CHECK(with["columns"]["impacts"] == 7);
  CHECK(with["columns"]["peak_theta_over_alpha"].get<double>() == within(0.53, 0.005));
  CHECK(without["outcome"] == "overturned");
  CHECK(without["t_end"].get<double>() == within(2.6, 0.05));
  // p-hat as the lesson prints it, from MODEL.md 16 with the scene's numbers.
  const double R = std::hypot(0.8, 4.8), p2 = 3 * gravity / (4 * R);
  const double gamma = (500000.0 + 120000.0) / (2 * 59000.0), gamma0 = 2.0 / (2 * 59000.0);
  CHECK(gamma == within(5.3, 0.05));
  CHECK(std::sqrt(p2 * (1 + 2 * gamma) / (1 + 3 * gamma)) == within(1.02, 0.005));
  CHECK(std::sqrt(p2 * (1 + 2 * gamma0) / (1 + 3 * gamma0)) == within(1.23, 0.005));
  const cli::Result s = cli::run(fmt::format("spectrum {} --sizes 1 --frequencies 1:1:1 --amplitudes 1:1:1 --formats svg "
                                             "--out {}",
                                             frame, temp_path("lesson_spectrum").string()),
                                 120);
  REQUIRE_MESSAGE(s.code == 0, s.err);
  CHECK_MESSAGE(cli::contains(s.out, "p-hat = 1.019 rad/s"), s.out);
}

TEST_CASE("rocking modal on columns: the frame's alpha, gamma, p-hat and r by MODEL.md 16, and the structure's fixed-base modes") {
  const std::string frame = std::string(ROCKING_SCENES) + "/rocking_frame.toml";
  const cli::Result r = cli::run("modal " + frame + " --json", 60);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto c = nlohmann::json::parse(r.out)["columns"];
  // The scene's numbers: piers b = 0.8, h = 4.8, 59 t each; a 500 t deck on a 120 t beam.
  const double alpha = std::atan(0.8 / 4.8), R = std::hypot(0.8, 4.8), gamma = 620000.0 / (2 * 59000.0);
  const double p2 = 3 * gravity / (4 * R);
  CHECK(c["alpha"].get<double>() == close_to(alpha, 1e-12));
  CHECK(c["gamma"].get<double>() == close_to(gamma, 1e-12));
  CHECK(c["p"].get<double>() == close_to(std::sqrt(p2), 1e-12));
  CHECK(c["p_hat"].get<double>() == close_to(std::sqrt(p2 * (1 + 2 * gamma) / (1 + 3 * gamma)), 1e-12));
  CHECK(c["r_rigid_deck"].get<double>() ==
        close_to((1 - 1.5 * std::pow(std::sin(alpha), 2) + 3 * gamma * std::cos(2 * alpha)) / (1 + 3 * gamma), 1e-12));
  CHECK(c["uplift_g"].get<double>() == close_to(0.8 / 4.8, 1e-12));
  const cli::Result table = cli::run("modal " + frame, 60);
  REQUIRE_MESSAGE(table.code == 0, table.err);
  CHECK_MESSAGE(cli::contains(table.out, "p-hat     1.0188"), table.out);
  CHECK_FALSE(cli::contains(table.out, "Eq. 10"));  // nothing of a structure rocking on its own base
  // The chimney on its columns: while they stand, the chimney's fixed-base modes.
  const cli::Result on = cli::run(fmt::format("modal {}/chimney_on_columns.toml --json", ROCKING_SCENES), 60);
  const cli::Result twin = cli::run(fmt::format("modal {}/christchurch_chimney.toml --json", ROCKING_SCENES), 60);
  REQUIRE_MESSAGE(on.code == 0, on.err);
  REQUIRE_MESSAGE(twin.code == 0, twin.err);
  const auto a = nlohmann::json::parse(on.out)["fixed_base_hz"].get<std::vector<double>>();
  const auto b = nlohmann::json::parse(twin.out)["fixed_base_hz"].get<std::vector<double>>();
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) CHECK(a[k] == close_to(b[k], 1e-12));
}

TEST_CASE("plot response names the rocking measure a run has: the columns' theta/alpha on the frame, none on a fixed base") {
  const cli::Result frame = cli::run(fmt::format("plot response {}/rocking_frame.toml --formats svg --out {}", ROCKING_SCENES,
                                                 temp_path("frame_plot").string()),
                                     120);
  REQUIRE_MESSAGE(frame.code == 0, frame.err);
  CHECK_MESSAGE(cli::contains(frame.out, "columns' theta/alpha 0.3"), frame.out);  // the summary's 0.349
  const cli::Result fixed = cli::run(fmt::format("plot response {}/christchurch_chimney.toml --variants fixed-base --formats svg "
                                                 "--out {}",
                                                 ROCKING_SCENES, temp_path("fixed_plot").string()),
                                     120);
  REQUIRE_MESSAGE(fixed.code == 0, fixed.err);
  CHECK_MESSAGE(cli::contains(fixed.out, "theta/alpha -,"), fixed.out);
}

TEST_CASE("the chimney on columns under its pulse: rosw and the SUNDIALS backends agree with rk45 on the first uplift and impact") {
  const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/chimney_on_columns.toml");
  const Ran reference = run(scene, 1e-10);
  REQUIRE(reference.result.counts.impacts >= 1);
  for (const char* integrator : {"rosw", "cvode", "arkode"}) {
    CAPTURE(integrator);
    const Ran other = run(scene, 1e-10, nullptr, std::nullopt, integrator);
    CHECK(other.result.integrator == integrator);
    REQUIRE(other.result.counts.impacts >= 1);
    CHECK(other.result.first_uplift == close_to(reference.result.first_uplift, 1e-6));
    CHECK(other.result.first_impact == close_to(reference.result.first_impact, 1e-6));
    CHECK(other.result.peak(Quantity::columns_theta) == close_to(reference.result.peak(Quantity::columns_theta), 1e-5));
    MESSAGE(std::string(integrator) << ": first impact " << other.result.first_impact << " s (rk45 " << reference.result.first_impact
                       << " s), " << other.result.counts.impacts << " impacts (rk45 " << reference.result.counts.impacts << ")");
  }
}

TEST_CASE("rosw at the default tolerances: the rocking frame and the chimney on columns lift and strike as rk45 does, under their pulses and El Centro") {
  const auto records = records_dir();
  if (!records) return;
  for (const char* name : {"rocking_frame", "chimney_on_columns"}) {
    const Scene scene = load_scene(std::string(ROCKING_SCENES) + "/" + name + ".toml");
    const std::string scene_name = name;
    for (const std::string& record : {std::string(), *records + "/elcentro_1940_ns.at2"}) {
      CAPTURE(scene_name);
      CAPTURE(record);
      rosw_events::check(scene, record);
    }
  }
}
