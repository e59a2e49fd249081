// Vertical ground motion (MODEL.md 14): the closed forms of a rigid block in
// gravity g + a_v (free rocking times scale by sqrt(g / (g + a_v)); uplift
// under a horizontal pulse when a_h H_cg = (g + a_v) B), the energy balance
// under a three-component record, a zero vertical motion leaving a run bit
// for bit as it was, and the refusal of a component used in the wrong
// direction (its name says which, component_orientation).
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>
#include "housner.hpp"
#include "records.hpp"
#include "temp_path.hpp"
#include "tight_run.hpp"
import rocking.simulation;
import rocking.scene;
import rocking.run;
import rocking.errors;
import rocking.records;

using namespace rocking;

namespace {

Scene rigid_block(std::vector<std::string> overrides = {}) {
  return load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml", overrides);
}

GroundMotion constant(double a, double duration) {
  return GroundMotion::from_samples("constant", {0.0, duration}, {a, a});
}

struct Recorder : Observer {
  std::vector<Response> rows;
  void record(const Response& r) override { rows.push_back(r); }
};

std::string waiau(const std::string& records) { return records + "/formats/20161113_110259_WTMC_20.V2A"; }

// Waiau's N28W scaled by 0.6, with its Up component when `vertical` names it.
GroundMotion waiau_n28w(const std::string& records, const std::string& vertical = "") {
  return read_record(waiau(records), {.component = "N28W", .scale = 0.6, .vertical_component = vertical});
}

}  // namespace

TEST_CASE("a rigid block released from a tilt under constant a_v reaches its first impact sqrt(g / (g + a_v)) times as soon (1e-8)") {
  const Scene scene = rigid_block({"damper.enabled=false"});
  const ContactModel m = make_contact_model(scene, false);
  const double g = m.body.g, theta0 = 0.5 * slenderness(scene.structure);
  const GroundMotion still = constant(0.0, 4.0);
  const RunResult plain = simulate(m, still, tight(4.0, theta0));
  REQUIRE(plain.counts.impacts >= 1);
  for (double a_v : {0.3 * g, -0.3 * g, 0.8 * g}) {
    CAPTURE(a_v);
    const GroundMotion up = constant(a_v, 4.0);
    const RunResult r = simulate(m, still.with_vertical(up), tight(4.0, theta0));
    REQUIRE(r.counts.impacts >= 1);
    CHECK(std::abs(r.first_impact / plain.first_impact - std::sqrt(g / (g + a_v))) < 1e-8);
    // and Housner's quarter period in gravity g + a_v
    CHECK(r.first_impact == close_to(housner_quarter_period(scene.structure, g + a_v, theta0), 1e-8));
  }
}

TEST_CASE("under constant a_v a rigid block lifts when a_h H_cg = (g + a_v) B (first uplift to 1e-8 against the closed form)") {
  const Scene scene = rigid_block({"damper.enabled=false"});
  const ContactModel m = make_contact_model(scene, false);
  const double g = m.body.g, B = m.body.structure.half_width, mass = m.body.total_mass;
  for (double a_v : {0.0, 0.4 * g, -0.4 * g}) {
    CAPTURE(a_v);
    // a_h at uplift: a_h H'M1 = (g + a_v) B m (H'M1 = m H_cg)
    const double a_crit = (g + a_v) * B * mass / m.body.HM1;
    const double amplitude = 1.5 * (g + 0.4 * g) * B * mass / m.body.HM1, period = 0.8;
    const GroundMotion pulse = GroundMotion::pulse(PulseShape::one_sine, amplitude, period);
    const GroundMotion up = constant(a_v, 1.0);
    const RunResult r = simulate(m, pulse.with_vertical(up), tight(1.0));
    REQUIRE(r.counts.uplifts >= 1);
    // a_h = A sin(2 pi t / T) first reaches a_crit at t = T asin(a_crit / A) / (2 pi)
    const double expected = period * std::asin(a_crit / amplitude) / (2 * std::numbers::pi);
    CHECK(r.first_uplift == close_to(expected, 1e-8));
  }
}

TEST_CASE("a flexible structure at rest is lifted by vertical shaking alone only when g + a_v turns negative") {
  // With no horizontal motion nothing tilts the chimney: under a_v > -g the
  // uplift guards stay negative, the structure stays in full contact and the
  // ground does no work.
  const ContactModel m = make_contact_model(load_default_scene(), true);
  const GroundMotion still = constant(0.0, 2.0);
  const GroundMotion up = GroundMotion::pulse(PulseShape::one_sine, 0.9 * m.body.g, 0.5);
  const RunResult r = simulate(m, still.with_vertical(up), tight(2.0));
  CHECK(r.counts.uplifts == 0);
  CHECK(r.peak(Quantity::delta_t) == 0.0);
  CHECK(r.energy.ground == 0.0);
}

TEST_CASE("under a three-component record (Waiau N28W and Up) the energy balance closes to 1e-6 of the input") {
  const auto records = records_dir();
  if (!records) return;
  const Scene scene = load_default_scene();
  const GroundMotion horizontal = waiau_n28w(*records), both = waiau_n28w(*records, "Up");
  REQUIRE(both.vertical());
  CHECK(both.vertical()->info().component == "Up");
  CHECK(both.vertical()->scale() == 0.6);  // scaled with the horizontal component
  RunOptions o = tight(60.0);
  o.tolerances.rtol = 1e-10;
  const RunResult with = simulate(make_contact_model(scene, true), both, o);
  const RunResult without = simulate(make_contact_model(scene, true), horizontal, o);
  REQUIRE(with.outcome == Outcome::completed);
  CHECK(with.counts.uplifts >= 1);
  const EnergyBalance& e = with.energy;
  CHECK(e.ground > 0);
  CHECK(std::abs(e.residual()) < 1e-6 * e.ground);
  // The vertical motion changes the response (it modulates the restoring moment).
  CHECK(with.peak(Quantity::theta) != without.peak(Quantity::theta));
}

TEST_CASE("a zero vertical motion leaves a run bit for bit as without one: peaks, events, history and energy") {
  const auto records = records_dir();
  if (!records) return;
  const Scene scene = load_default_scene();
  const GroundMotion horizontal = waiau_n28w(*records);
  // the file's own vertical samples, all at zero amplitude
  const GroundMotion zero = read_record(waiau(*records), {.component = "Up", .scale = 0.0, .read_as = ReadAs::vertical});
  REQUIRE(zero.peak() == 0.0);
  const ContactModel m = make_contact_model(scene, true);
  RunOptions o;
  o.duration = 60;
  o.output_interval = 0.01;
  Recorder a, b;
  const RunResult ra = simulate(m, horizontal, o, &a);
  const RunResult rb = simulate(m, horizontal.with_vertical(zero), o, &b);
  REQUIRE(ra.counts.uplifts >= 1);
  CHECK(ra.peaks == rb.peaks);
  CHECK(ra.counts.uplifts == rb.counts.uplifts);
  CHECK(ra.counts.impacts == rb.counts.impacts);
  CHECK(ra.first_uplift == rb.first_uplift);
  CHECK(ra.stats.steps == rb.stats.steps);
  CHECK(ra.energy.ground == rb.energy.ground);
  CHECK(ra.energy.final == rb.energy.final);
  REQUIRE(a.rows.size() == b.rows.size());
  bool same = true;
  for (std::size_t i = 0; i < a.rows.size(); ++i) same = same && a.rows[i].q == b.rows[i].q;
  CHECK(same);
}

TEST_CASE("component names tell vertical from horizontal: a record read in the wrong direction is refused in one line") {
  for (const char* v : {"Up", "UP", "DWN", "V", "U-D", "UD", "HNZ", "BNZ", "Vertical", "Z"})
    CHECK_MESSAGE(component_orientation(v) == Orientation::vertical, v);
  for (const char* h : {"N28W", "S62W", "N89.5E", "E-W", "N-S", "090", "360", "L", "T", "HN1", "HNE", "W", "S"})
    CHECK_MESSAGE(component_orientation(h) == Orientation::horizontal, h);
  for (const char* u : {"", "X", "comp1", "acc"}) CHECK_MESSAGE(component_orientation(u) == Orientation::unknown, u);

  const std::filesystem::path dir = scratch_dir("vertical_test_orientation");
  const std::filesystem::path file = dir / "three.V2A";
  for (const RecordFormatInfo& f : record_formats())
    if (f.name == "geonet") std::ofstream(file) << f.example();
  RecordOptions up;
  up.component = "Up";
  try {
    (void)read_record(file.string(), up);
    FAIL("the vertical component was read as a horizontal one");
  } catch (const InputError& e) {
    const std::string what = e.what();
    CHECK(what.find("is vertical") != std::string::npos);
    CHECK(what.find("--vertical Up") != std::string::npos);
    CHECK(what.find('\n') == std::string::npos);
  }
  up.read_as = ReadAs::vertical;
  CHECK(read_record(file.string(), up).peak() > 0);
  RecordOptions across;
  across.component = "N10E";
  across.read_as = ReadAs::vertical;
  CHECK_THROWS_WITH_AS((void)read_record(file.string(), across), doctest::Contains("is horizontal"), InputError);
}

TEST_CASE("a run specification's vertical motion: a component of the record's file, a file, or the scene's") {
  const std::filesystem::path dir = scratch_dir("vertical_test_spec");
  const std::filesystem::path file = dir / "three.V2A";
  for (const RecordFormatInfo& f : record_formats())
    if (f.name == "geonet") std::ofstream(file) << f.example();
  RunSpec spec;
  spec.scene = load_default_scene();
  spec.motion.record = file.string();
  spec.motion.file.component = "N10E";
  spec.motion.vertical = "Up";
  spec.motion.scale = 2;
  const PreparedRun run = prepare_run(spec);
  const GroundMotion* up = run.motion.vertical();
  REQUIRE(up);
  CHECK(run.model.vertical_shaking);
  CHECK(up->info().component == "Up");
  CHECK(up->peak() == close_to(0.5 * run.motion.peak(), 1e-3));  // the example's Up is half N10E, both scaled
  CHECK(!run.label.vertical.empty());
  const std::vector<std::string> names = run.columns.names();
  CHECK(std::ranges::find(names, "a_v") != names.end());
  Recorder rows;
  RunOptions o = run.options;
  const RunResult r = simulate(run.model, run.motion, o, &rows);
  REQUIRE(!rows.rows.empty());
  double largest = 0;
  for (const Response& row : rows.rows) largest = std::max(largest, std::abs(row[Quantity::a_v]));
  CHECK(largest == close_to(up->peak(), 1e-12));
  CHECK(r.outcome != Outcome::failed);

  // Without a vertical motion the history has no a_v column.
  RunSpec plain = spec;
  plain.motion.vertical.clear();
  const PreparedRun p = prepare_run(plain);
  CHECK(!p.motion.vertical());
  const std::vector<std::string> plain_names = p.columns.names();
  CHECK(std::ranges::find(plain_names, "a_v") == plain_names.end());

  // A component name with no record file to take it from, and a missing file.
  RunSpec lone;
  lone.scene = load_default_scene();
  lone.motion.vertical = "Up";
  CHECK_THROWS_WITH_AS(prepare_run(lone), doctest::Contains("--vertical Up: no such file"), InputError);
  RunSpec wrong = spec;
  wrong.motion.vertical = "N80W";
  CHECK_THROWS_WITH_AS(prepare_run(wrong), doctest::Contains("is horizontal"), InputError);

  // The scene's [excitation] vertical, beside its record.
  RunSpec own;
  own.scene = load_default_scene({"excitation.record=\"" + file.string() + "\"", "excitation.component=\"N10E\"",
                                  "excitation.vertical=\"Up\""});
  const PreparedRun s = prepare_run(own);
  REQUIRE(s.motion.vertical());
  CHECK(s.motion.vertical()->peak() == close_to(0.5 * s.motion.peak(), 1e-3));
  // scaled with the horizontal one
  RunSpec doubled = own;
  doubled.motion.scale = 2;
  CHECK(prepare_run(doubled).motion.vertical()->peak() == close_to(2 * s.motion.vertical()->peak(), 1e-12));
}
