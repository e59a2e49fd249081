// rocking.scene: reading scene files, --set overrides, and one-line errors that
// name the file, the line and the key.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include "temp_path.hpp"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>
#include <fstream>
#include <string>
#include <variant>
#include <vector>
#include "one_line_error.hpp"
import rocking.scene;
import rocking.errors;

using namespace rocking;

namespace {

// Writes the embedded chimney scene with `from` replaced by `to` to a temp file.
std::string chimney_with(const std::string& from, const std::string& to) {
  std::string text(default_scene_text());
  const auto at = text.find(from);
  REQUIRE_MESSAGE(at != std::string::npos, "test setup: '" << from << "' not in the scene");
  text.replace(at, from.size(), to);
  const auto path = temp_path("scene_test.toml");
  std::ofstream(path) << text;
  return path.string();
}

int line_of(const std::string& path, const std::string& needle) {
  std::ifstream in(path);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  return -1;
}

std::string error_of(const std::string& path, const std::vector<std::string>& sets = {}) {
  return one_line_error<InputError>([&] { load_scene(path, sets); }, path);
}

}  // namespace

TEST_CASE("the data/ chimney file and the embedded scene agree") {
  const Scene embedded = load_default_scene();
  const Scene file = load_scene(ROCKING_SCENES "/christchurch_chimney.toml");
  CHECK(embedded.name == "Christchurch chimney");
  CHECK(file.structure.heights == embedded.structure.heights);
  CHECK(file.structure.masses == embedded.structure.masses);
  CHECK(file.damper.stiffness == 1.0e7);  // N/m, MODEL.md 9.1
  CHECK(file.contact.restitution_rule == RestitutionRule::constant);
  CHECK(file.contact.restitution == 0.94);
}

TEST_CASE("--set overrides typed values, bare words and booleans") {
  const Scene s = load_default_scene(
      {"structure.EI_scale=0.5", "contact.restitution=eq10", "damper.enabled=false"});
  CHECK(s.structure.EI_scale == 0.5);
  CHECK(s.contact.restitution_rule == RestitutionRule::eq10);
  CHECK_FALSE(s.damper.enabled);
  CHECK(load_default_scene({"structure.masses=[1.0, 2.0, 3.0, 4.0]"}).structure.masses[3] == 4.0);
}

TEST_CASE("a missing key names the key, the file and the table's line") {
  const std::string path = chimney_with("base_mass = 62400.0", "");
  const std::string what = error_of(path);
  CHECK(what == path + ":" + std::to_string(line_of(path, "[structure]")) + ": structure.base_mass: missing key");
}

TEST_CASE("an unknown key is an error, not silently ignored") {
  const std::string path = chimney_with("base_mass = 62400.0", "base_mass = 62400.0\nbase_mas = 1.0");
  const std::string what = error_of(path);
  CHECK(what.starts_with(path + ":" + std::to_string(line_of(path, "base_mas =")) + ": structure.base_mas: unknown key"));
}

TEST_CASE("a negative mass names the element and its line") {
  const std::string path = chimney_with("53800.0", "-53800.0");
  CHECK(error_of(path) == path + ":" + std::to_string(line_of(path, "masses =")) +
                              ": structure.masses[2]: must be in [0.001, 1e+12] kg (got -53800)");
}

TEST_CASE("non-increasing heights are refused") {
  const std::string path = chimney_with("25.5,", "17.0,");
  CHECK(error_of(path).find("structure.heights[2]: heights must increase by at least 0.001 m (got 17 after 17.95)") !=
        std::string::npos);
}

TEST_CASE("a zero section is refused") {
  const std::string path = chimney_with("[9.84, 4.03,", "[9.84, 0.0,");
  CHECK(error_of(path).ends_with("structure.second_moments[1]: must be in [1e-16, 10000] m^4 (got 0)"));
}

TEST_CASE("malformed and unknown --set are one-line errors naming the --set") {
  const std::string path = ROCKING_SCENES "/christchurch_chimney.toml";
  CHECK(error_of(path, {"structure.EI_scale"}).starts_with("--set structure.EI_scale: expected TABLE.KEY=VALUE"));
  CHECK(error_of(path, {"=3"}).starts_with("--set =3: expected"));
  CHECK(error_of(path, {"EI_scale=3"}).starts_with("--set EI_scale=3: expected"));
  CHECK(error_of(path, {"structure.EI_scal=3"}) == "--set structure.EI_scal=3: unknown key 'structure.EI_scal'");
  CHECK(error_of(path, {"structure.EI_scale=-1"}) ==
        "--set structure.EI_scale=-1: structure.EI_scale: must be in [1e-6, 1e6] (got -1)");
  CHECK(error_of(path, {"structure.EI_scale=soft"}) ==
        "--set structure.EI_scale=soft: structure.EI_scale: must be a number");
  // An integer that no double holds exactly is read as its nearest double
  // (toml++ declines to convert it), then checked like any other number.
  CHECK(error_of(path, {"damper.thickness=-2888888880898888881"}) ==
        "--set damper.thickness=-2888888880898888881: damper.thickness: must be in (0, 100] (got -2.8888888808988887e+18)");
  CHECK(error_of(path, {"structure.EI_scale=9007199254740993"}) ==
        "--set structure.EI_scale=9007199254740993: structure.EI_scale: must be in [1e-6, 1e6] (got 9007199254740992)");
}

TEST_CASE("invalid TOML reports the parser's line") {
  const std::string path = chimney_with("half_width = 3.3", "half_width = = 3.3");
  const std::string what = error_of(path);
  CHECK(what.starts_with(path + ":" + std::to_string(line_of(path, "half_width")) + ": invalid TOML:"));
}

TEST_CASE("a missing scene file is one line naming it") {
  CHECK(error_of("/nonexistent/scene.toml") == "/nonexistent/scene.toml: scene file not found");
}

TEST_CASE("NaN and wrong types are refused") {
  CHECK(error_of(chimney_with("half_width = 3.3", "half_width = nan")).ends_with("structure.half_width: must be a finite number"));
  CHECK(error_of(chimney_with("rocking = true", "rocking = 1")).ends_with("contact.rocking: must be true or false"));
  CHECK(error_of(chimney_with("restitution = 0.94", "restitution = 1.5")).ends_with("contact.restitution: must be in [0, 1], eq10 or eq9 (got 1.5)"));
}

TEST_CASE("a rigid block needs no sections, and the rigid_block scene loads") {
  const Scene block = load_scene(std::string(ROCKING_SCENES) + "/rigid_block.toml");
  CHECK(block.structure.rigid);
  CHECK(block.structure.EI.size() == 0);
  CHECK_FALSE(block.damper.enabled);
  CHECK(block.contact.restitution_rule == RestitutionRule::eq10);
  const std::string fixed = one_line_error<InputError>(
      [&] { load_scene(std::string(ROCKING_SCENES) + "/rigid_block.toml", {"contact.rocking=false"}); }, "fixed");
  CHECK(fixed.find("structure.rigid") != std::string::npos);
}

TEST_CASE("[excitation]: the chimney's pulse, a record path relative to the scene, and one-line errors") {
  const Scene chimney = load_default_scene();
  CHECK(chimney.excitation.record.empty());
  CHECK(chimney.excitation.pulse == PulseShape::one_sine);
  CHECK(chimney.excitation.amplitude == close_to(0.35 * 9.81, 1e-12));
  const GroundMotion pulse = default_ground_motion(chimney);
  CHECK(pulse.peak() == close_to(0.35 * 9.81, 1e-12));

  const std::string with_record = chimney_with("pulse = \"one-sine\"", "record = \"motions/quake.txt\"\nunits = \"cm/s2\"\ndt = 0.01");
  const Scene s = load_scene(with_record, {"excitation.period=0.6"});
  CHECK(s.excitation.record == (std::filesystem::path(with_record).parent_path() / "motions/quake.txt").string());
  CHECK(s.excitation.record_options.unit.value_or(AccelerationUnit::g) == AccelerationUnit::cm_per_s2);
  CHECK(s.excitation.record_options.dt == 0.01);

  const std::string bad = chimney_with("pulse = \"one-sine\"", "pulse = \"square\"");
  const std::string e = error_of(bad);
  CHECK(e.find(":" + std::to_string(line_of(bad, "pulse = \"square\"")) + ":") != std::string::npos);
  CHECK(e.find("excitation.pulse") != std::string::npos);
  CHECK(error_of(bad, {"excitation.pulse=ricker", "excitation.period=-1"}).find("excitation.period") != std::string::npos);
}

TEST_CASE("--set damper.enabled=false works on a scene without a [damper] table") {
  const Scene block = load_scene(std::string(ROCKING_SCENES) + "/rigid_block.toml", {"damper.enabled=false"});
  CHECK_FALSE(block.damper.enabled);
  const Scene chimney = load_default_scene({"damper.enabled=false", "damper.stiffness=-1"});
  CHECK_FALSE(chimney.damper.enabled);  // a disabled damper's properties are not read
}

// --- [[device]] tables (MODEL.md 11) -------------------------------------------

namespace {
const char* tendon_and_fluid = R"(
[[device]]
name = "tendon"
kind = "elastic"
at = 0.0
kinematics = "vertical"
free_length = 30.0
P0 = 2.0e6
k = 5.0e7
capacity = 0.05

[[device]]
name = "fluid"
kind = "viscous"
at = "edges"
c = 3.0e5
a = 0.3
)";
}  // namespace

TEST_CASE("[[device]] tables: law, anchor, kinematics, capacity and the law's keys") {
  const Scene s = load_scene(chimney_with("[excitation]", std::string(tendon_and_fluid) + "\n[excitation]"));
  REQUIRE(s.devices.size() == 3);  // the tendon, and the fluid damper at each edge
  const Device& tendon = s.devices[0];
  CHECK(tendon.name == "tendon");
  CHECK(tendon.geometry.x == 0.0);
  CHECK(tendon.geometry.kinematics == Kinematics::vertical);
  CHECK(tendon.geometry.free_length == 30.0);
  CHECK(tendon.capacity == 0.05);
  REQUIRE(std::holds_alternative<ElasticLaw>(tendon.law));
  CHECK(std::get<ElasticLaw>(tendon.law).P0 == 2.0e6);
  CHECK(std::get<ElasticLaw>(tendon.law).k == 5.0e7);
  CHECK(s.devices[1].name == "fluid_left");
  CHECK(s.devices[1].geometry.x == -3.3);
  CHECK(s.devices[2].name == "fluid_right");
  CHECK(s.devices[2].geometry.x == 3.3);
  CHECK(s.devices[2].geometry.kinematics == Kinematics::chord);
  CHECK(std::get<ViscousLaw>(s.devices[2].law).a == 0.3);
  // Every device of the scene: the [damper]'s two first.
  const std::vector<Device> all = scene_devices(s);
  REQUIRE(all.size() == 5);
  CHECK(all[0].name == "damper_left");
  CHECK(all[4].name == "fluid_right");
}

TEST_CASE("--set adds a device, sets a device's key, or removes them all") {
  const std::string add = R"(device+={kind="elastic", at=0, kinematics="vertical", free_length=33, P0=1e6, k=2e7})";
  Scene s = load_default_scene({add});
  REQUIRE(s.devices.size() == 1);
  CHECK(s.devices[0].name == "elastic_1");
  s = load_default_scene({add, "device[0].P0=3e6", "device[0].name=tendon"});
  CHECK(std::get<ElasticLaw>(s.devices[0].law).P0 == 3e6);
  CHECK(s.devices[0].name == "tendon");
  CHECK(load_default_scene({add, add, "device=[]"}).devices.empty());
}

TEST_CASE("a wrong [[device]] is a one-line error naming the device, the key and the place") {
  const std::string path = chimney_with("[excitation]", std::string(tendon_and_fluid) + "\n[excitation]");
  const int tendon_line = line_of(path, "name = \"tendon\"");
  const auto error = [&](const std::vector<std::string>& sets) { return error_of(path, sets); };
  CHECK(error({"device[0].k=-1"}) == "--set device[0].k=-1: device[0].k: must be >= 0 and <= 1e+13 [N/m] (got -1)");
  std::string laws;  // every registered law, in registry order
  for (const LawInfo& l : device_laws()) laws += (laws.empty() ? "" : ", ") + l.name;
  CHECK(error({"device[0].kind=spring"}).find("device[0].kind: unknown law 'spring' (laws: " + laws + ")") !=
        std::string::npos);
  CHECK(error({"device[0].at=4"}).find("device[0].at: must be on the base, -B <= x <= B = 3.3 [m] (got 4)") !=
        std::string::npos);
  CHECK(error({"device[1].free_length=2"}) == "--set device[1].free_length=2: device[1].free_length: only a vertical "
                                               "device has a free length");
  CHECK(error({"device[2].k=1"}).find("no device [2]: the scene has 2 device tables") != std::string::npos);
  CHECK(error({"device[0].name=damper_left"}).find("'damper_left' names two devices") != std::string::npos);
  // The [damper] is the device "damper": no [[device]] may take its name.
  CHECK(error({"device[1].name=damper"}).find("device[1].name: 'damper' names the scene's [damper]") != std::string::npos);
  CHECK(error({"device[0].name=a,b"}).find("device[0].name: must be letters, digits, _ or -") != std::string::npos);
  // A typo in the file: file:line of the key.
  const std::string typo = chimney_with("[excitation]", std::string(tendon_and_fluid) + "spring_rate = 1\n\n[excitation]");
  const std::string e = error_of(typo);
  CHECK(e.find("device[1].spring_rate: unknown key for a viscous device (known: a, at, c, capacity, free_length, "
               "from_segment, joint, kind, kinematics, name, segment)") != std::string::npos);
  CHECK(e.find(std::to_string(line_of(typo, "spring_rate = 1"))) != std::string::npos);
  CHECK(tendon_line > 0);
  CHECK(error({"device+=3"}).find("expected one device as an inline table") != std::string::npos);
  CHECK(one_line_error<InputError>([] { load_default_scene({"device+={at=0}"}); }, "").find("device[0].kind: missing key") !=
        std::string::npos);
}

TEST_CASE("devices are listed as the scene names them: the [damper] is the device \"damper\", an edges table one device") {
  const Scene chimney = load_scene(ROCKING_SCENES "/christchurch_chimney.toml");
  const std::vector<DeviceGroup> c = device_groups(chimney);
  REQUIRE(c.size() == 1);
  CHECK(c[0].name == "damper");
  CHECK(c[0].dissipates);
  CHECK(c[0].devices.size() == 2);
  CHECK_FALSE(c[0].table.has_value());
  // Its removal is a --set text like any device's, and takes the pair away.
  const Scene without = load_scene(ROCKING_SCENES "/christchurch_chimney.toml", {c[0].removal});
  CHECK_FALSE(without.damper.enabled);
  CHECK(scene_devices(without).empty());
  CHECK_THROWS_WITH_AS(load_scene(ROCKING_SCENES "/christchurch_chimney.toml", {"device-=damper", "device-=damper"}),
                       "--set device-=damper: no [[device]] named 'damper'", InputError);

  const Scene wall = load_scene(ROCKING_SCENES "/controlled_rocking_wall.toml");
  const std::vector<DeviceGroup> w = device_groups(wall);
  REQUIRE(w.size() == 2);
  CHECK(w[0].name == "tendon");
  CHECK_FALSE(w[0].dissipates);
  REQUIRE(w[0].prestress_key != nullptr);
  CHECK(std::string(w[0].prestress_key) == "P0");
  CHECK(w[0].prestress == 2.6e6);  // the scene's P0, as written
  CHECK(w[0].table == std::optional<std::size_t>(0));
  CHECK(w[1].name == "dampers");
  CHECK(w[1].dissipates);
  CHECK(w[1].prestress_key == nullptr);
  CHECK(w[1].table == std::optional<std::size_t>(1));
  REQUIRE(w[1].devices.size() == 2);
  CHECK(w[1].devices[0].name == "dampers_left");
  CHECK(w[1].devices[1].name == "dampers_right");
  for (const DeviceGroup& g : w) {
    CAPTURE(g.name);
    const Scene less = load_scene(ROCKING_SCENES "/controlled_rocking_wall.toml", {g.removal});
    for (const Device& d : scene_devices(less)) CHECK(d.group != g.name);
  }
}

namespace {
// The chimney on rocking columns: its [columns] table with `keys`.
std::string chimney_on_columns(const std::string& keys) {
  return chimney_with("[excitation]", "[columns]\n" + keys + "\n\n[excitation]");
}
}  // namespace

TEST_CASE("[columns]: the rocking columns under the structure are read and checked as the engine needs them") {
  const Scene s = load_scene(chimney_on_columns("count = 3\nhalf_width = 0.4\nhalf_height = 3.0\nmass = 2.0e4\nspacing = 6.0"));
  REQUIRE(s.columns.has_value());
  CHECK(s.columns->count == 3);
  CHECK(s.columns->half_width == 0.4);
  CHECK(s.columns->half_height == 3.0);
  CHECK(s.columns->mass == 2.0e4);
  CHECK(s.columns->spacing == 6.0);
  const Columns c = make_columns(*s.columns, s.structure);  // the engine takes what the scene read
  CHECK(c.deck_mass == close_to(s.structure.base_mass + s.structure.masses.sum(), 1e-15));
  // one column needs no spacing; a scene without [columns] has none
  const Scene one = load_scene(chimney_on_columns("count = 1\nhalf_width = 0.4\nhalf_height = 3.0\nmass = 2.0e4"));
  CHECK(one.columns->spacing == 0.0);
  CHECK_FALSE(load_default_scene().columns.has_value());
  // the chimney's dampers on columns stand at the edges of each column's base (x = -b and +b), each
  // stretched about the far corner with the lever 2b
  const ContactModel m = make_contact_model(s, false);
  REQUIRE(m.devices.size() == 2);
  CHECK(m.devices[0].geometry.x == -0.4);
  CHECK(m.devices[1].geometry.x == 0.4);
  for (Pivot p : pivots) {
    REQUIRE(m.acting[index(p)].size() == 1);
    CHECK(m.acting[index(p)][0].lever == close_to(0.8, 1e-15));
  }
}

TEST_CASE("a wrong [columns] is a one-line error naming the key, its range and the line") {
  const std::string ok = "half_width = 0.4\nhalf_height = 3.0\nmass = 2.0e4\n";
  struct Case {
    std::string keys, expected;
  };
  const Case cases[] = {
      {"count = 0\nspacing = 6.0\n" + ok, "columns.count: must be a whole number from 1 to 1000 (got 0)"},
      {"count = 2.5\nspacing = 6.0\n" + ok, "columns.count: must be a whole number from 1 to 1000 (got 2.5)"},
      {"count = 2\nspacing = 6.0\nhalf_width = 0.0\nhalf_height = 3.0\nmass = 2.0e4", "columns.half_width: must be in [0.001, 10000] m (got 0)"},
      {"count = 2\nspacing = 6.0\nhalf_width = 0.4\nhalf_height = -3.0\nmass = 2.0e4", "columns.half_height: must be in [0.001, 10000] m (got -3)"},
      {"count = 2\nspacing = 6.0\nhalf_width = 0.4\nhalf_height = 3.0\nmass = 0.0", "columns.mass: must be in [0.001, 1e+12] kg (got 0)"},
      {"count = 2\nspacing = 0.7\n" + ok, "columns.spacing: must be at least a column's width, 2 half_width = 0.8 m, and at most 10000 m (got 0.7)"},
      {"count = 2\n" + ok, "columns.spacing: missing key"},
      {"count = 2\nspacing = 6.0\nheight = 3.0\n" + ok, "columns.height: unknown key"},
  };
  for (const Case& c : cases) {
    const std::string path = chimney_on_columns(c.keys);
    const std::string error = error_of(path);
    CHECK_MESSAGE(error.find(c.expected) != std::string::npos, error);
    CHECK_MESSAGE(error.find(path) == 0, error);  // where: the file (and its line)
  }
  // through --set, the --set is named
  const std::string set = one_line_error<InputError>(
      [] { load_default_scene({"columns.count=-1"}); },
      "--set columns.count=-1");
  CHECK_MESSAGE(set.find("--set columns.count=-1: columns.count: must be a whole number") != std::string::npos, set);
  // [columns] beside [[joint]] tables is refused in one line
  const std::string both = error_of(chimney_on_columns("count = 2\nspacing = 6.0\n" + ok + "\n[[joint]]\nnode = 2"));
  CHECK_MESSAGE(both.find("[columns] with [[joint]]: a structure on rocking columns that also rocks at its own joints is not supported") !=
                    std::string::npos,
                both);
}
