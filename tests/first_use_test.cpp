// What a new user meets first, each a defect once reported (issue 14): figures
// without dampers, the scale a run reports, errors that name the right flag,
// options checked before work, unique record ids, exit codes of studies,
// --version and mistyped subcommands, and tests that clean up after themselves.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <nlohmann/json.hpp>
#include "temp_path.hpp"
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>
#include "run_program.hpp"
#include "gnuplot_columns.hpp"
#include "csv_table.hpp"
#include "housner.hpp"
import rocking.scene;

namespace fs = std::filesystem;

namespace {

const std::string scenes = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/";

// A short record of two columns (t [s], a [g]): a one-sine pulse of the
// period, then rest, `length` seconds in all.
std::string short_record(const fs::path& file, double amplitude_g = 0.3, double period = 0.6, double length = 3) {
  std::ofstream out(file);
  for (int i = 0; 0.01 * i <= length + 1e-9; ++i) {
    const double t = 0.01 * i;
    out << t << ' ' << (t < period ? amplitude_g * std::sin(2 * 3.141592653589793 * t / period) : 0.0) << '\n';
  }
  return file.string();
}

// Shell words joined by spaces.
template <class... Words>
std::string fmt_args(const Words&... words) {
  std::string out;
  ((out += (out.empty() ? "" : " ") + std::string(words)), ...);
  return out;
}

}  // namespace

TEST_CASE("a response figure without any damper renders, and draws no damper panel") {
  const fs::path dir = scratch_dir("first_use_no_damper");
  const Result block = run("-q plot response " + scenes + "rigid_block.toml --formats png --out " + dir.string() +
                           " --name block");
  CHECK_MESSAGE(block.code == 0, block.err);
  CHECK(fs::file_size(dir / "block.png") > 0);
  CHECK_FALSE(contains(file_text(dir / "block.gp"), "damper force"));
  const Result none = run("-q plot response --set damper.enabled=false --variants scene --formats png --out " +
                          dir.string() + " --name none");
  CHECK_MESSAGE(none.code == 0, none.err);
  CHECK(fs::is_regular_file(dir / "none.png"));
  REQUIRE(run("-q simulate --set damper.enabled=false --out " + (dir / "free").string()).code == 0);
  const Result from = run("-q plot response --from " + (dir / "free").string() + " --formats png --out " +
                          dir.string() + " --name from");
  CHECK_MESSAGE(from.code == 0, from.err);
  CHECK(fs::is_regular_file(dir / "from.png"));
  // The figure opens with the ground acceleration, and its key hides no data.
  const std::string gp = file_text(dir / "from.gp");
  CHECK(contains(gp, "ground acceleration"));
  CHECK_FALSE(contains(gp, "opaque\n"));
  CHECK_FALSE(contains(gp, "box opaque"));
}

TEST_CASE("a scene's own scale and --scale multiply, and the run reports the product and its factors") {
  const fs::path dir = scratch_dir("first_use_scale");
  short_record(dir / "pulse.txt", 0.1);
  std::string scene = file_text(scenes + "christchurch_chimney.toml");
  const auto at = scene.find("[excitation]");
  REQUIRE(at != std::string::npos);
  scene = scene.substr(0, at) + "[excitation]\nrecord = \"pulse.txt\"\nscale = 2\n";
  std::ofstream(dir / "scaled.toml") << scene;
  const Result r = run("simulate " + (dir / "scaled.toml").string() + " --scale 3 --out " + (dir / "out").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(contains(r.out, "(x6 (scene 2 x --scale 3))"));
  const auto summary = nlohmann::json::parse(file_text(dir / "out" / "summary.json"));
  CHECK(summary["scale"].get<double>() == 6.0);
  CHECK(summary["scale_factors"]["scene"].get<double>() == 2.0);
  CHECK(summary["scale_factors"]["option"].get<double>() == 3.0);
  // The x6 run is what --scale 6 on the bare record gives.
  const Result direct = run("simulate --json --record " + (dir / "pulse.txt").string() + " --scale 6 --out " +
                            (dir / "direct").string());
  REQUIRE(direct.code == 0);
  CHECK(nlohmann::json::parse(direct.out)["peaks"] == summary["peaks"]);
}

TEST_CASE("a list option's error names that option, not another") {
  const Result sizes = run("spectrum --sizes foo");
  CHECK(sizes.code == 2);
  CHECK(contains(sizes.err, "--sizes 'foo'"));
  CHECK_FALSE(contains(sizes.err, "--scales"));
  const Result rtols = run("tradeoff --rtols 1e-3:x");
  CHECK(rtols.code == 2);
  CHECK(contains(rtols.err, "--rtols '1e-3:x'"));
  CHECK_FALSE(contains(rtols.err, "--scales"));
}

TEST_CASE("every option is checked before the first run: a bad --formats does no work") {
  const fs::path dir = scratch_dir("first_use_formats");
  const Result r = run("plot response --formats jpg --out " + (dir / "out").string());
  CHECK(r.code == 2);
  CHECK(lines(r.err) == 1);
  CHECK(contains(r.err, "jpg"));
  CHECK(r.out.empty());                         // no variant was run (each prints a line)
  CHECK_FALSE(fs::exists(dir / "out"));          // nor any folder made
  const Result ida = run("ida --record " + short_record(dir / "p.txt") + " --formats jpg --out " + (dir / "ida").string());
  CHECK(ida.code == 2);
  CHECK_FALSE(fs::exists(dir / "ida" / "ida.csv"));
}

TEST_CASE("two records of the same file name in different folders keep apart in rows and figures") {
  const fs::path dir = scratch_dir("first_use_ids");
  fs::create_directories(dir / "x");
  fs::create_directories(dir / "y");
  const std::string a = short_record(dir / "x" / "rec.txt", 0.2), b = short_record(dir / "y" / "rec.txt", 0.4);
  const Result r = run("-q ida --record " + a + " " + b + " --scales 1 --variants no-damper --formats png --out " +
                       (dir / "out").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string csv = file_text(dir / "out" / "ida.csv");
  CHECK(contains(csv, "\nx/rec.txt,1,no-damper,"));
  CHECK(contains(csv, "\ny/rec.txt,1,no-damper,"));
  CHECK(fs::is_regular_file(dir / "out" / "ida_x_rec.png"));
  CHECK(fs::is_regular_file(dir / "out" / "ida_y_rec.png"));
}

TEST_CASE("IDA figures draw collapse as collapse, start peaks at zero, and name variants in words") {
  const fs::path dir = scratch_dir("first_use_collapse");
  // 0.3 g for 2.5 s: the chimney without damper survives it, and overturns at x3.
  const std::string rec = short_record(dir / "p.txt", 0.3, 2.5, 8);
  const Result r = run("-q ida --record " + rec + " --scales 1,3,6 --variants damper,no-damper,fixed-base --formats png --out " +
                       (dir / "ida").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string csv = file_text(dir / "ida" / "ida.csv");
  REQUIRE(contains(csv, "p.txt,1,no-damper,"));
  REQUIRE(contains(csv, "overturned"));
  // The variant without a damper: the survivor at x1 coded 0, its first
  // overturning (x3) 1, the later one (x6) 2.
  std::ifstream data(dir / "ida" / "ida_p.data" / "1.csv");
  std::vector<std::string> rows;
  for (std::string line; std::getline(data, line);) rows.push_back(line);
  REQUIRE(rows.size() == 4);
  CHECK(rows[0].ends_with(",collapse"));
  CHECK((rows[1].starts_with("1,") && rows[1].ends_with(",0")));
  CHECK((rows[2].starts_with("3,") && rows[2].ends_with(",1")));
  CHECK((rows[3].starts_with("6,") && rows[3].ends_with(",2")));
  const std::string gp = file_text(dir / "ida" / "ida_p.gp");
  // The first overturning has a marker of its own, read from the collapse column by its name.
  CHECK(contains(gp, "column('collapse') == 1"));
  CHECK(contains(gp, "set yrange [0:*]"));  // peaks from zero
  CHECK(contains(gp, "'rocking, no damper'"));
  // The key explains the collapse markers some variant draws, and no other;
  // variant v's markers stand 0.2 (v - 1) level spacings (2 here) aside.
  bool drawn[4] = {false, false, false, false};
  for (int v = 0; v < 3; ++v) {
    std::ifstream variant(dir / "ida" / "ida_p.data" / (std::to_string(v) + ".csv"));
    bool collapses = false;
    std::string line;
    for (std::getline(variant, line); std::getline(variant, line);) {
      const int code = line.back() - '0';
      drawn[code] = true;
      collapses = collapses || code > 0;
    }
    char shifted[64];
    std::snprintf(shifted, sizeof shifted, "((column('level')) + %.9g)", 0.2 * 2 * (v - 1));
    CHECK_MESSAGE(contains(gp, shifted) == collapses, v);
  }
  CHECK(drawn[1]);
  CHECK(drawn[2]);
  CHECK(contains(gp, "title \"first overturning\""));
  CHECK(contains(gp, "title \"overturned again\"") == drawn[2]);
  CHECK(contains(gp, "title \"standing again after overturning\"") == drawn[3]);
  const Result sweep = run("-q sweep --record " + rec + " --scales 1 --set structure.EI_scale=0.25,1 --formats png "
                           "--out " + (dir / "sweep").string());
  REQUIRE_MESSAGE(sweep.code == 0, sweep.err);
  CHECK(contains(file_text(dir / "sweep" / "sweep_p.gp"), "'EI x0.25'"));
}

TEST_CASE("mode shapes: one colour per mode in both panels, and no internal document in the title") {
  const fs::path dir = scratch_dir("first_use_modes");
  REQUIRE(run("-q plot modes --formats png --out " + dir.string()).code == 0);
  const std::string gp = file_text(dir / "modes.gp");
  CHECK_FALSE(contains(gp, "MODEL.md 8"));
  // Mode 1 is line style 1 in the fixed-base panel and in the rocking panel,
  // where it follows the rocking mode R (the rocking phase's first shape).
  CHECK(contains(gp, "using (column('fixed_base_1')):(column('height')) with linespoints linestyle 1 title 'mode 1:"));
  CHECK(contains(gp, "using (column('rocking_2')):(column('height')) with linespoints linestyle 1 title 'mode 1:"));
  CHECK(contains(gp, "using (column('rocking_1')):(column('height')) with linespoints linestyle 6 title 'R:"));
  CHECK_MESSAGE(numbered_column(gp).empty(), numbered_column(gp));  // columns by header name
  // The keys sit below the panels, kept clear of the axis label by its empty second line.
  CHECK(contains(gp, "set key outside below"));
  CHECK(contains(gp, "set xlabel \"lateral displacement (normalised, top = 1) [-]\\n\""));
}

TEST_CASE("the program's own words: --version, a mistyped subcommand, -q after it, singulars, absent dampers") {
  const Result version = run("--version");
  CHECK(version.code == 0);
  CHECK(contains(version.out, "rocking 0."));
  const Result typo = run("simulat");
  CHECK(typo.code == 2);
  CHECK(lines(typo.err) == 1);
  CHECK(contains(typo.err, "unknown subcommand 'simulat'; did you mean 'simulate'?"));
  const fs::path dir = scratch_dir("first_use_words");
  const Result quiet = run("modal -q");
  CHECK(quiet.code == 0);
  const Result block = run("simulate " + scenes + "rigid_block.toml -q --out " + dir.string());
  REQUIRE(block.code == 0);
  CHECK(block.err.empty());  // -q after the subcommand silences the info lines
  CHECK(contains(block.out, "1 uplift,"));
  CHECK_FALSE(contains(block.out, "damper"));  // a block without dampers reports no damper quantity
}

TEST_CASE("modal on a rigid block prints what a block has") {
  const Result r = run("modal " + scenes + "rigid_block.toml --json");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  const double m = j["mass"], J = j["J_p"], R = j["R"], p = j["p"];
  CHECK(p == close_to(std::sqrt(m * 9.81 * R / J), 1e-12));
  CHECK(j["alpha_cg"].get<double>() == close_to(std::atan(0.2 / j["H_cg"].get<double>()), 1e-12));
  CHECK(j["r_eq10"].get<double>() > 0);
  CHECK(contains(run("modal " + scenes + "rigid_block.toml").out, "frequency parameter"));
}

TEST_CASE("the tests' temporary folders are removed when a test process exits") {
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {  // a test process that makes files and exits normally
    std::ofstream(scratch_dir("left_behind") / "file.txt") << "x";
    std::exit(0);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  REQUIRE(WIFEXITED(status));
  CHECK_FALSE(fs::exists(fs::temp_directory_path() / ("rocking_" + std::to_string(child))));
}

TEST_CASE("a teacher's free rocking: --set initial.theta with no excitation, first impact at Housner's time") {
  const fs::path dir = scratch_dir("first_use_initial");
  const rocking::Scene scene = rocking::load_scene(scenes + "rigid_block.toml");
  const double theta0 = 0.5 * rocking::slenderness(scene.structure);
  const Result r = run(fmt_args("simulate", scenes + "rigid_block.toml", "--set excitation.kind=none",
                                "--set excitation.duration=3", "--set initial.theta=" + std::to_string(theta0),
                                "--rtol 1e-12 --atol 1e-14 --json --out", dir.string()));
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["motion"] == "no ground motion");
  const double expected = housner_quarter_period(scene.structure, 9.81, std::stod(std::to_string(theta0)));
  CHECK(j["first_impact_s"].get<double>() == within(expected, 1e-8));
  // A bad initial state is refused with its key.
  const Result bad = run("simulate --set initial.u=[1,2] --out " + dir.string());
  CHECK(bad.code == 2);
  CHECK(contains(bad.err, "initial.u: must have one entry per node (4)"));
  const Result fixed = run("simulate --set contact.rocking=false --set initial.theta=0.1 --out " + dir.string());
  CHECK(fixed.code == 2);
  CHECK(contains(fixed.err, "initial.theta: a fixed base"));
}

TEST_CASE("ida --help says honestly that the hunt can step over a collapse window") {
  const Result r = run("ida --help");
  CHECK(r.code == 0);
  CHECK(contains(r.out, "not monotonic"));
  CHECK(contains(r.out, "bounds the lowest"));
}

TEST_CASE("figure scripts: time axes end at the run's end, fixed bases draw no rocking line, spectra fill regions") {
  const fs::path dir = scratch_dir("first_use_scripts");
  REQUIRE(run("-q plot response --formats png --out " + dir.string() + " --name r").code == 0);
  CHECK(contains(file_text(dir / "r.gp"), "set autoscale xfix"));  // no axis past the end of the run
  const std::string rec = short_record(dir / "p.txt");
  REQUIRE(run("-q ida --record " + rec + " --scales 1,2 --formats png --out " + (dir / "ida").string()).code == 0);
  // The panels in order; the fixed base (series file 2.csv) appears in none
  // of the rocking-angle and damper panels, the rocking variants in all.
  const std::string gp = file_text(dir / "ida" / "ida_p.gp");
  std::vector<std::string> panels;
  for (std::size_t at = gp.find("set ylabel"); at != std::string::npos;) {
    const std::size_t next = gp.find("set ylabel", at + 1);
    panels.push_back(gp.substr(at, next == std::string::npos ? std::string::npos : next - at));
    at = next;
  }
  REQUIRE(panels.size() >= 8);
  auto panel = [&](const std::string& label) {
    for (const std::string& p : panels)
      if (contains(p, label)) return p;
    FAIL("no panel labelled " << label);
    return std::string();
  };
  CHECK_FALSE(contains(panel("rocking angle"), "2.csv"));
  CHECK(contains(panel("rocking angle"), "1.csv"));
  CHECK_FALSE(contains(panel("damper elongation"), "2.csv"));
  CHECK_FALSE(contains(panel("damper elongation"), "1.csv"));  // nor the variant without a damper
  CHECK(contains(panel("damper elongation"), "0.csv"));
  CHECK(contains(panel("base moment"), "2.csv"));
  // --log auto: the base shear's panel is logarithmic exactly when its peaks
  // over the variants (column base_shear of ida.csv) span more than a decade;
  // --log on makes every force-like panel logarithmic and no drift panel,
  // --log off none.
  const CsvTable ida = csv_table(file_text(dir / "ida" / "ida.csv"));
  double low = 1e300, high = 0;
  for (std::size_t i = 0; i < ida.rows.size(); ++i)
    if (const std::string& field = ida.at(i, "base_shear"); !field.empty() && std::stod(field) > 0) {
      const double v = std::stod(field);
      low = std::min(low, v);
      high = std::max(high, v);
    }
  REQUIRE(high > 0);
  // ("\n  set logscale y": "unset logscale y" opens every other panel)
  CHECK(contains(panel("base shear"), "\n  set logscale y") == (high > 10 * low));
  CHECK_FALSE(contains(panel("total top drift"), "\n  set logscale y"));
  for (const std::string mode : {"on", "off"}) {
    const fs::path out = dir / ("log_" + mode);
    REQUIRE(run("-q ida --record " + rec + " --scales 1,2 --formats png --log " + mode + " --out " + out.string())
                .code == 0);
    const std::string script = file_text(out / "ida_p.gp");
    const std::size_t shear = script.find("peak base shear"), drift = script.find("peak total top drift");
    REQUIRE(shear != std::string::npos);
    REQUIRE(drift != std::string::npos);
    const bool shear_log = script.substr(shear, 120).find("\n  set logscale y") != std::string::npos;
    const bool drift_log = script.substr(drift, 120).find("\n  set logscale y") != std::string::npos;
    CHECK(shear_log == (mode == "on"));
    CHECK_FALSE(drift_log);
  }
  CHECK(run("-q ida --record " + rec + " --scales 1 --log sometimes --out " + (dir / "bad").string()).code == 2);
  REQUIRE(run("-q spectrum --sizes 1,2 --frequencies 1:3:1 --amplitudes 1:3:1 --formats png --out " +
              (dir / "sp").string()).code == 0);
  const std::string sp = file_text(dir / "sp" / "spectrum.gp");
  CHECK(contains(sp, "with boxxyerror fillstyle solid"));  // cells filled, not points
  CHECK(contains(sp, "#701f4e9c"));                         // the first size translucent and solid,
  CHECK(contains(sp, "with boxxyerror fillstyle pattern 1 transparent noborder linecolor rgb \"#c0392b\""));  // the next cross-hatched
  // Outside each size's own grid, in seconds and g, hatched as never computed.
  CHECK(contains(sp, "stats 'spectrum.data/size_2.csv' using (column('period_high_s')):(column('amplitude_high_g')) "
                    "nooutput prefix \"HI1\""));
  CHECK(contains(sp, "title 'not computed for block x2'"));
  CHECK_MESSAGE(numbered_column(sp).empty(), numbered_column(sp));  // columns by header name
}
