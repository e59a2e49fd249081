// `rocking ida` and `rocking sweep` as a user meets them: the CSV of a study is
// byte-identical between --threads 1, --threads 2 and mpirun -np 2, and so are
// a suite's summaries; each row's record, scaled by the row's factor, has the
// row's IM level; a bad record among good ones is reported in its rows and the
// rest finish; folders and list files name suites; a sweep gives one line per
// parameter value.
#include <doctest/doctest.h>
#include "sanitizers.hpp"
#include "close.hpp"
#include "temp_path.hpp"
#include <algorithm>
#include <cmath>
#include <set>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>
#include <unistd.h>
#include "run_program.hpp"
#include "gnuplot_columns.hpp"
#include "csv_table.hpp"
#include "records.hpp"
import rocking.intensity;
import rocking.ground_motion;
import rocking.records;

namespace fs = std::filesystem;
using namespace rocking;

namespace {

// A one-sine pulse, 0.15 g and 0.6 s, then rest, to 4 s: t [s], a [g].
std::string pulse_record(const fs::path& dir) {
  const fs::path file = dir / "pulse.txt";
  std::ofstream out(file);
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.01 * i;
    out << t << ' ' << (t <= 0.6 ? 0.15 * std::sin(2 * std::numbers::pi * t / 0.6) : 0.0) << '\n';
  }
  return file.string();
}

bool have_mpirun() {
  if (std::system("command -v mpirun >/dev/null 2>&1") == 0) return true;
  const char* ci = std::getenv("CI");
  if (ci != nullptr && std::string(ci) == "true") FAIL("mpirun not found (scripts/setup.sh installs openmpi-bin)");
  WARN_MESSAGE(false, "SKIPPED: mpirun not found");
  return false;
}

// A ladder's first overturning level of each variant that overturned (its ida.csv).
std::map<std::string, double> first_overturnings(const fs::path& ida_csv) {
  std::map<std::string, double> first;
  const CsvTable ladder = csv_table(file_text(ida_csv));
  for (std::size_t i = 0; i < ladder.rows.size(); ++i)
    if (ladder.at(i, "outcome") == "overturned" && !first.contains(ladder.at(i, "variant")))
      first[ladder.at(i, "variant")] = std::stod(ladder.at(i, "level"));
  return first;
}

}  // namespace

TEST_CASE("an IDA's CSV is byte-identical with 1 thread, 2 threads and mpirun -np 2") {
  const fs::path dir = scratch_dir("study_cli_identical");
  const std::string study = "-q ida --record " + pulse_record(dir) + " --scales 1:4:1 --no-plot --out ";
  REQUIRE(run(study + (dir / "one").string() + " --threads 1").code == 0);
  REQUIRE(run(study + (dir / "two").string() + " --threads 2").code == 0);
  const std::string one = file_text(dir / "one" / "ida.csv");
  CHECK(lines(one) == 1 + 4 * 3);  // header, 4 scales x 3 variants
  CHECK(one.find("overturned") == std::string::npos);
  CHECK(one == file_text(dir / "two" / "ida.csv"));
  if (!have_mpirun()) return;
  const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
  // Under `make sanitize` the ranks run without leak detection: OpenMPI
  // unloads its components before the check, so its own leaks come without
  // names that a suppression could match. Every single-process test checks
  // the same code for leaks.
  const std::string mpirun = "ASAN_OPTIONS=detect_leaks=0:halt_on_error=1 mpirun";
  const std::string mpi = mpirun + root + " --oversubscribe -np 2 " + std::string(ROCKING_BIN) + " " + study +
                          (dir / "mpi").string() + " --threads 1";
  REQUIRE(std::system(mpi.c_str()) == 0);
  CHECK(one == file_text(dir / "mpi" / "ida.csv"));
  CHECK(lines(file_text(dir / "mpi" / "timing.csv")) == 1 + 12);
  // Under mpirun, rank 0 draws the figure a single process draws, from the same data.
  const std::string drawn = "-q ida --record " + pulse_record(dir) + " --scales 1:4:1 --formats png --threads 1 --out ";
  REQUIRE(run(drawn + (dir / "one_fig").string()).code == 0);
  const std::string mpi_fig = mpirun + root + " --oversubscribe -np 2 " + std::string(ROCKING_BIN) + " " + drawn +
                              (dir / "mpi_fig").string();
  REQUIRE(std::system(mpi_fig.c_str()) == 0);
  CHECK(fs::is_regular_file(dir / "mpi_fig" / "ida_pulse.png"));
  const std::string script = file_text(dir / "one_fig" / "ida_pulse.gp");
  CHECK_MESSAGE(numbered_column(script).empty(), numbered_column(script));  // columns by header name
  for (const char* data : {"ida_pulse.data/0.csv", "ida_pulse.data/1.csv", "ida_pulse.data/2.csv", "ida_pulse.gp"})
    CHECK_MESSAGE(file_text(dir / "one_fig" / data) == file_text(dir / "mpi_fig" / data), data);
}

TEST_CASE("a bad record among good ones is reported in its rows, the study finishes, and exits 4 with the count") {
  const fs::path dir = scratch_dir("study_cli_bad_record");
  std::ofstream(dir / "broken.txt") << "0 0.1\n0.01 abc\n";
  const Result r = run("-q ida --record " + pulse_record(dir) + " " + (dir / "broken.txt").string() +
                       " --scales 1:2:1 --variants damper --out " + dir.string() + " --formats png");
  CHECK(r.code == 4);
  const std::string csv = file_text(dir / "ida.csv");
  CHECK(lines(csv) == 1 + 4);
  CHECK(csv.find("pulse.txt,1,damper,") != std::string::npos);
  CHECK(csv.find("broken.txt:2") != std::string::npos);  // the reader's error, with its line
  CHECK(r.err.find("2 of 4 runs failed") != std::string::npos);
  CHECK(lines(r.err) == 1);
  CHECK(fs::is_regular_file(dir / "ida_pulse.png"));  // the good record still gets its figure
}

TEST_CASE("a sweep writes one line per value of the swept key") {
  const fs::path dir = scratch_dir("study_cli_sweep");
  const Result r = run("-q sweep --record " + pulse_record(dir) + " --scales 1,2 --no-plot --out " + dir.string() +
                       " --set damper.thickness=1,2,3 --set structure.damping_ratio=0.05");
  REQUIRE(r.code == 0);
  const std::string csv = file_text(dir / "sweep.csv");
  CHECK(lines(csv) == 1 + 2 * 3);
  for (const char* v : {",damper.thickness=1,", ",damper.thickness=2,", ",damper.thickness=3,"})
    CHECK(csv.find(v) != std::string::npos);
  const Result two = run("-q sweep --record x --set damper.thickness=1,2 --set structure.EI_scale=1,2");
  CHECK(two.code == 2);
  CHECK(lines(two.err) == 1);
}

TEST_CASE("bad fragility options are refused in one line before any run") {
  const fs::path dir = scratch_dir("study_cli_fragility_options");
  const std::string study = "-q ida --record " + pulse_record(dir) + " --scales 1,2 --no-plot --out " + (dir / "x").string();
  for (const auto& [option, says] : {std::pair{"--resurrection sometimes", "--resurrection 'sometimes'"},
                                     std::pair{"--bootstrap -5", "--bootstrap -5"},
                                     std::pair{"--bootstrap 2000000", "--bootstrap 2000000"},
                                     std::pair{"--beta-modelling -0.2", "--beta-modelling -0.2"},
                                     std::pair{"--beta-modelling nan", "--beta-modelling"}}) {
    CAPTURE(option);
    const Result r = run(study + " " + option);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find(says) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "x" / "ida.csv"));
  }
}

TEST_CASE("a suite scaled to PGA: rows meet their levels exactly, summaries are the same on 1, 2 threads and 2 ranks") {
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("study_cli_suite");
  // A list file naming three records, relative to the records folder.
  std::ofstream(dir / "three.txt") << "# three records\n" << *records << "/elcentro_1940_ns.at2\n"
                                   << *records << "/kobe1995_kjma_000.at2\n\n"
                                   << *records << "/christchurch2011_pphs_s57e.at2\n";
  const std::string study = "-q ida --record " + (dir / "three.txt").string() +
                            " --im pga --levels 0.5:2.5:0.5 --variants damper,no-damper --limit theta_over_alpha=0.5"
                            " --no-plot --out ";
  const Result one = run(study + (dir / "one").string() + " --threads 1");
  REQUIRE_MESSAGE(one.code == 0, one.err);
  CHECK(one.out.find("no-damper: overturning median pga") != std::string::npos);
  REQUIRE(run(study + (dir / "two").string() + " --threads 2").code == 0);
  const char* outputs[] = {"ida.csv", "summary.csv", "fragility.csv", "fragility_points.csv", "summary.json"};
  for (const char* f : outputs) CHECK_MESSAGE(file_text(dir / "one" / f) == file_text(dir / "two" / f), f);
  // Every row: the record read again and scaled by the row's factor has the row's PGA.
  const CsvTable ida = csv_table(file_text(dir / "one" / "ida.csv"));
  REQUIRE(ida.rows.size() == 3 * 5 * 2);
  const IntensityMeasure pga = parse_intensity_measure("pga");
  std::size_t overturned = 0;
  for (std::size_t i = 0; i < ida.rows.size(); ++i) {
    CHECK(ida.at(i, "im") == "pga");
    const GroundMotion g = read_record(*records + "/" + ida.at(i, "record"));
    const double level = std::stod(ida.at(i, "level")), scale = std::stod(ida.at(i, "scale"));
    CHECK(intensity(g.scaled(scale), pga) == close_to(level, 1e-9));
    CHECK(std::stod(ida.at(i, "record_im")) == close_to(intensity(g, pga), 1e-15));
    overturned += ida.at(i, "outcome") == "overturned" ? 1 : 0;
  }
  CHECK(overturned > 0);
  const std::string summary = file_text(dir / "one" / "summary.csv");
  CHECK(summary.starts_with("variant,quantity,im,level,runs,collapsed,p16,p50,p84\n"));
  CHECK(summary.find("no-damper,theta_over_alpha,pga,0.5,3,") != std::string::npos);
  const std::string fragility = file_text(dir / "one" / "fragility.csv");
  CHECK(fragility.find("damper,overturning,pga,") != std::string::npos);
  CHECK(fragility.find("damper,theta_over_alpha>=0.5,pga,") != std::string::npos);
  CHECK(fragility.find("stripes-mle") != std::string::npos);
  if (!have_mpirun()) return;
  const std::string root = ::geteuid() == 0 ? " --allow-run-as-root" : "";
  const std::string mpi = "ASAN_OPTIONS=detect_leaks=0:halt_on_error=1 mpirun" + root + " --oversubscribe -np 2 " +
                          std::string(ROCKING_BIN) + " " + study + (dir / "mpi").string() + " --threads 1";
  REQUIRE(std::system(mpi.c_str()) == 0);
  for (const char* f : outputs) CHECK_MESSAGE(file_text(dir / "one" / f) == file_text(dir / "mpi" / f), f);
}

TEST_CASE("a folder of records: unrecognised files are skipped, an unreadable record fails alone, the rest finish") {
  const fs::path dir = scratch_dir("study_cli_folder");
  fs::create_directories(dir / "suite");
  pulse_record(dir / "suite");
  std::ofstream(dir / "suite" / "NOTES.md") << "# notes about these records\n";
  // Two columns whose second row is not a number: recognised as columns, unreadable.
  std::ofstream(dir / "suite" / "zz_bad.txt") << "0 0.1\n0.01 abc\n";
  const Result r = run("-q ida --record " + (dir / "suite").string() +
                       " --im pga --levels 0.1,0.2 --variants no-damper --formats png --out " + (dir / "out").string());
  CHECK(r.code == 4);
  const std::string csv = file_text(dir / "out" / "ida.csv");
  CHECK(csv.find("NOTES.md") == std::string::npos);
  CHECK(csv.find("pulse.txt,") != std::string::npos);
  CHECK(csv.find("zz_bad.txt,") != std::string::npos);
  CHECK(r.err.find("2 of 4 runs failed (records that could not be read: zz_bad.txt)") != std::string::npos);
  CHECK(lines(r.err) == 1);
  CHECK(fs::is_regular_file(dir / "out" / "summary.csv"));
  // The suite figures, one per quantity, and the fragility.
  CHECK(fs::is_regular_file(dir / "out" / "ida_theta_over_alpha.png"));
  CHECK(fs::is_regular_file(dir / "out" / "ida_fragility.png"));
  const Result none = run("-q ida --suite nosuch --out " + (dir / "x").string());
  CHECK(none.code == 2);
  CHECK(none.err.find("--suite nosuch: no such suite (suites: horizontal)") != std::string::npos);
  const Result no_levels = run("-q ida --record " + (dir / "suite" / "pulse.txt").string() + " --im pga --out " +
                               (dir / "x").string());
  CHECK(no_levels.code == 2);
  CHECK(no_levels.err.find("--im pga: give the levels to scale to as --levels") != std::string::npos);
}

TEST_CASE("the hunt finds the first overturning that a 0.05 g ladder finds, where the growing trace jumps over it") {
  skip_under_sanitizers("a hunt and a 0.05 g ladder of a real record");
  // christchurch2011_rehs_n02e under Sa(T1): without dampers the trace up
  // (0.5, 1, 1.75, ..., 10.9, 16.6 g) survives every level it runs below
  // --hunt-max 25 although a window opens near 7.5 g; with dampers the first
  // overturning is near 13.9 g. Each hunt's collapse is the ladder's first
  // overturning to within the fill step (0.05 g), from above.
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("study_hunt_windows");
  const std::string rec = *records + "/christchurch2011_rehs_n02e.at2";
  const std::string common = "-q ida --record " + rec + " --im sa:T1 --variants damper,no-damper --no-plot --out ";
  REQUIRE(run(common + (dir / "ladder").string() + " --levels 0.05:14:0.05").code == 0);
  REQUIRE(run(common + (dir / "hunt").string() + " --levels 0.5 --hunt --hunt-max 25").code == 0);
  const std::map<std::string, double> first = first_overturnings(dir / "ladder" / "ida.csv");
  REQUIRE(first.size() == 2);
  const CsvTable hunt = csv_table(file_text(dir / "hunt" / "hunt.csv"));
  for (std::size_t i = 0; i < hunt.rows.size(); ++i) {
    const std::string& variant = hunt.at(i, "variant");
    CAPTURE(variant);
    REQUIRE(!hunt.at(i, "collapse_level").empty());  // not censored
    REQUIRE(first.contains(variant));
    const double collapse = std::stod(hunt.at(i, "collapse_level"));
    CHECK(collapse <= first.at(variant) + 1e-9);
    CHECK(collapse > first.at(variant) - 0.05 - 1e-9);
  }
  CHECK(hunt.rows.size() == 2);
  // Every level run is listed with its reason, the fill among them.
  const std::string points = file_text(dir / "hunt" / "hunt_points.csv");
  CHECK(points.find(",fill,") != std::string::npos);
  CHECK(points.find(",25,trace,") != std::string::npos);  // the trace tried --hunt-max itself
}

TEST_CASE("two more records: a collapse the old trace censored, and a window a 0.05 g ladder steps over") {
  skip_under_sanitizers("hunts of two real records");
  // Under Sa(T1) (fill step 0.05 g, precision 0.025 g):
  // - christchurch2011_cbgs_s01w with dampers survives every level below
  //   17.5 g; the trace (..., 10.9, 16.6, 25 g) overturns only at --hunt-max,
  //   and a hunt that filled nothing below 16.6 g called it censored. Its
  //   collapse is the ladder's first overturning to within the fill step.
  // - darfield2010_cacs_n40e without dampers overturns between about 1.215
  //   and 1.24 g while 1.2, 1.25 and the levels next to them survive (a
  //   0.005 g ladder shows it), so the 0.05 g ladder's first overturning is
  //   1.3 g. The hunt's bisection lands in that window: its collapse is an
  //   overturning it ran, below the ladder's by more than the fill step.
  // In both, every level the hunt ran below its collapse survived, and the
  // collapse is never above the ladder's first overturning by more than the fill step.
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("study_hunt_more_windows");
  struct Case {
    std::string record, variant, ladder, hunt_max;
    bool below_ladder;  // the hunt finds a window the ladder steps over
  };
  const std::vector<Case> cases{{"christchurch2011_cbgs_s01w.at2", "damper", "0.05:17.6:0.05", "25", false},
                                {"darfield2010_cacs_n40e.at2", "no-damper", "0.05:1.5:0.05", "2", true}};
  constexpr double fill = 0.05;
  for (const Case& c : cases) {
    CAPTURE(c.record);
    const std::string common = "-q ida --record " + *records + "/" + c.record + " --im sa:T1 --variants " + c.variant +
                               " --no-plot --out ";
    const fs::path ladder_dir = dir / (c.record + "_ladder"), hunt_dir = dir / (c.record + "_hunt");
    REQUIRE(run(common + ladder_dir.string() + " --levels " + c.ladder).code == 0);
    REQUIRE(run(common + hunt_dir.string() + " --levels 0.5 --hunt --hunt-max " + c.hunt_max).code == 0);
    const std::map<std::string, double> firsts = first_overturnings(ladder_dir / "ida.csv");
    REQUIRE(firsts.contains(c.variant));
    const double first = firsts.at(c.variant);
    const CsvTable hunt = csv_table(file_text(hunt_dir / "hunt.csv"));
    REQUIRE(hunt.rows.size() == 1);
    REQUIRE(!hunt.at(0, "collapse_level").empty());  // not censored
    const double collapse = std::stod(hunt.at(0, "collapse_level"));
    CAPTURE(collapse);
    CAPTURE(first);
    CHECK(collapse <= first + fill + 1e-9);
    if (c.below_ladder) CHECK(collapse < first - fill);
    else CHECK(collapse > first - fill - 1e-9);
    // The collapse is a run that overturned; every run below it survived
    // (hunt_points.csv writes levels to 9 significant digits).
    const CsvTable points = csv_table(file_text(hunt_dir / "hunt_points.csv"));
    bool ran_collapse = false;
    for (std::size_t i = 0; i < points.rows.size(); ++i) {
      const double level = std::stod(points.at(i, "level"));
      const bool same = std::abs(level - collapse) <= 1e-8 * collapse;
      if (same) ran_collapse = points.at(i, "overturned") == "1";
      else if (level < collapse) CHECK_MESSAGE(points.at(i, "overturned") == "0", level);
    }
    CHECK(ran_collapse);
  }
}

TEST_CASE("every shipped scene runs its default study with no failed row, and the wall's variants are with and without its dampers") {
  const fs::path dir = scratch_dir("study_cli_every_scene");
  const std::string record = pulse_record(dir);
  std::vector<fs::path> scenes;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(ROCKING_SOURCE_DIR) / "data" / "scenes"))
    if (e.path().extension() == ".toml") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  REQUIRE(scenes.size() >= 3);
  for (const fs::path& scene : scenes) {
    CAPTURE(scene.string());
    const fs::path out = dir / scene.stem();
    const Result r = run("-q ida " + scene.string() + " --record " + record + " --scales 1,2 --no-plot --out " + out.string());
    CHECK(r.code == 0);
    CHECK(r.err.empty());
    const CsvTable ida = csv_table(file_text(out / "ida.csv"));
    REQUIRE(!ida.rows.empty());
    for (std::size_t i = 0; i < ida.rows.size(); ++i) {
      CAPTURE(ida.at(i, "variant"));
      CHECK(ida.at(i, "error").empty());
      CHECK(ida.at(i, "outcome") != "failed");
    }
    if (scene.stem() == "controlled_rocking_wall") {
      std::map<std::string, bool> dampers;  // variant: its rows report the dampers' force
      for (std::size_t i = 0; i < ida.rows.size(); ++i)
        dampers[ida.at(i, "variant")] = !ida.at(i, "dampers_left.force").empty();
      // a fixed base does not rock, so no device stretches: its rows leave the columns empty
      CHECK(dampers == std::map<std::string, bool>{{"scene", true}, {"without:dampers", false}, {"fixed-base", false}});
    }
    if (scene.stem() == "christchurch_chimney") {
      std::set<std::string> variants;
      for (std::size_t i = 0; i < ida.rows.size(); ++i) variants.insert(ida.at(i, "variant"));
      CHECK(variants == std::set<std::string>{"scene", "without:damper", "fixed-base"});
    }
    if (scene.stem() == "rigid_block") CHECK(ida.rows.size() == 2);  // as built only: no device, no fixed base
  }
}
