// Hostile and careless input (issue 21): every one of these once ended in an
// "internal error", unbounded work or output, a silently wrong run, or a
// message pointing the wrong way. Each must now end in one line naming what
// and where, with exit code 2 (bad input) or 3 (a run that cannot finish),
// before any work it would waste.
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include <filesystem>
#include <fstream>
#include <string>
#include "records.hpp"
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

// A PEER-style file: three header lines, the NPTS/DT line, then the values.
std::string at2(const fs::path& file, const std::string& header_line, const std::string& values = "0.1 0.2 0.1 0.0\n") {
  std::ofstream(file) << "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, STATION, N\n"
                         "ACCELERATION TIME SERIES IN UNITS OF G\n"
                      << header_line << "\n"
                      << values;
  return file.string();
}

}  // namespace

TEST_CASE("record headers that lie or overflow are refused at their line, before memory is reserved") {
  const fs::path dir = scratch_dir("hostile_headers");
  const std::string sim = "simulate --out " + (dir / "out").string() + " --record ";
  refused(sim + at2(dir / "a.at2", "NPTS= 99999999999999, DT= .01 SEC"), "a.at2:4: NPTS = 99999999999999 but the file holds 4 values");
  refused(sim + at2(dir / "b.at2", "NPTS= 99999999999999999999999, DT= .01 SEC"), "b.at2:4: NPTS = 99999999999999999999999 is not a count");
  refused(sim + at2(dir / "c.at2", "NPTS= -4, DT= .01 SEC"), "c.at2:4: NPTS = -4 is not a count");
  refused(sim + at2(dir / "d.at2", "NPTS= 4, DT= 1e"), "d.at2:4: DT = '1e' is not a number");
  refused(sim + at2(dir / "e.at2", "NPTS= 4, DT= nan"), "e.at2:4: DT = 'nan' is not a number");
  refused(sim + at2(dir / "f.at2", "NPTS= 4"), "f.at2:4: no DT= on the NPTS line");
  refused(sim + at2(dir / "g.at2", "NPTS= 4, DT= 1e300 SEC"), "g.at2:4: DT x NPTS = 4e+300 s is beyond");
  refused(sim + at2(dir / "h.at2", "NPTS= 4, DT= .01 SEC", "0.1 1e308 0.1 0\n"), "h.at2:5: acceleration");
  refused(sim + at2(dir / "i.at2", "NPTS= 4, DT= .01 SEC") + " --dt 0.02", "i.at2:4: --dt 0.02: the file states its own time step");
}

TEST_CASE("column records: wrong column counts, negative start times and stray --dt are named") {
  const fs::path dir = scratch_dir("hostile_columns");
  const std::string sim = "simulate --out " + (dir / "out").string() + " --record ";
  std::ofstream(dir / "three.txt") << "0 0.1 7\n0.01 0.2 7\n";
  refused(sim + (dir / "three.txt").string(), "three.txt:1: 3 columns: a record has one");
  std::ofstream(dir / "early.txt") << "-10 0.1\n0 0.2\n1 0\n";
  refused(sim + (dir / "early.txt").string(), "early.txt:1: the record starts at t = -10 s");
  std::ofstream(dir / "two.txt") << "0 0.1\n0.01 0.2\n0.02 0\n";
  refused(sim + (dir / "two.txt").string() + " --dt 0.01", "two.txt:1: --dt 0.01: a two-column record gives its own times");
  refused(sim + dir.string(), "is a folder, not a record file");
  refused("simulate " + dir.string(), "is a folder, not a scene file");
}

TEST_CASE("absurd scene values are refused with their key, not met as a failed eigenproblem") {
  refused("modal --set structure.EI_scale=1e300", "structure.EI_scale: must be in [1e-6, 1e6]");
  refused("modal --set structure.youngs_modulus=1e308", "structure.youngs_modulus: must be in [1000, 1e+13] Pa");
  refused("modal --set structure.masses=[1e15,1,1,1]", "structure.masses[0]: must be in [0.001, 1e+12] kg");
  refused("simulate --set excitation.duration=1e9", "excitation.duration: must be positive and at most 100000");
}

TEST_CASE("requests for unbounded output or work are refused up front with the number they would produce") {
  const fs::path dir = scratch_dir("hostile_bounds");
  refused("simulate --every 1e-9 --out " + dir.string(), "--every 1e-09: 8e+09 rows of history");
  CHECK_FALSE(fs::exists(dir / "history.csv"));
  std::ofstream(dir / "r.txt") << "0 0.1\n0.01 0.2\n0.02 0\n";
  const std::string ida = "ida --record " + (dir / "r.txt").string() + " --out " + (dir / "ida").string();
  refused(ida + " --hunt --hunt-step 1e-6", "--hunt-step 1e-06, --fill-step 1e-07: up to");
  refused(ida + " --hunt --scales 5 --hunt-max 2", "--hunt-max 2: below the first level 5");
  refused(ida + " --scales 1,2,", "--scales '1,2,'");
  refused("simulate --duration 0 --out " + dir.string(), "--duration 0: must be positive");
  refused("simulate --duration -5 --out " + dir.string(), "--duration -5: must be positive");
}

TEST_CASE("a thread count beyond the machine is capped with a warning, and the study completes") {
  const fs::path dir = scratch_dir("hostile_threads");
  std::ofstream(dir / "r.txt") << "0 0.1\n0.01 0.2\n0.02 0\n";
  const Result r = run("ida --record " + (dir / "r.txt").string() + " --scales 1,2 --variants damper --no-plot --threads 100000 --out " +
                       dir.string());
  CHECK(r.code == 0);
  CHECK(contains(r.err, "--threads 100000: this machine has"));
  CHECK(lines(file_text(dir / "ida.csv")) == 1 + 2);
}

TEST_CASE("a full disk under history.csv ends the run with exit 3 naming the file, and the summary is still written") {
  if (!fs::exists("/dev/full")) {
    WARN_MESSAGE(false, "SKIPPED: no /dev/full");
    return;
  }
  const fs::path dir = scratch_dir("hostile_full");
  fs::create_symlink("/dev/full", dir / "history.csv.partial");  // where the rows go until the history is whole
  const Result r = run("-q simulate --out " + dir.string());
  CHECK(r.code == 3);
  CHECK(lines(r.err) == 1);
  CHECK(contains(r.err, (dir / "history.csv").string() + ": cannot write: No space left on device"));
  CHECK(contains(file_text(dir / "summary.json"), "\"outcome\": \"failed\""));
  CHECK_FALSE(fs::exists(dir / "history.csv"));  // no file under the history's name that looks whole
}

TEST_CASE("values beyond what the model answers are refused with their key and range, before any run") {
  const fs::path dir = scratch_dir("hostile_ranges");
  const auto records = records_dir();
  if (!records) return;
  const std::string elcentro = *records + "/elcentro_1940_ns.at2";
  // Tolerances whose error estimate is round-off, or bounds nothing.
  refused("simulate --atol 1e300 --out " + dir.string(), "--atol 1e+300: must be in [1e-16, 1e-3]");
  refused("simulate --rtol 1e-20 --out " + dir.string(), "--rtol 1e-20: must be in [1e-13, 0.1]");
  // A yield rotation past pi/2, device values beyond any device, a Bouc-Wen device without bounded hysteresis.
  refused("modal --set damper.theta_y=7", "damper.theta_y: must be in [1.52e-07, pi/2) [rad]");
  refused("modal --set 'device+={name=\"t\", kind=\"elastic\", at=0, kinematics=\"vertical\", free_length=33, P0=1e300, k=5e7}'",
          "device[0].P0: must be >= 0 and <= 1e+10 [N]");
  refused("modal --set 'device+={name=\"v\", kind=\"viscous\", at=\"edges\", c=1e5, a=1e300}'", "device[0].a: must be > 0 and <= 3");
  refused("modal --set 'device+={name=\"p\", kind=\"bouc-wen\", at=\"edges\", k=1e7, eps=0.05, d_y=1e300}'",
          "device[0].d_y: must be >= 1e-06 and <= 10 [m]");
  refused("modal --set 'device+={name=\"p\", kind=\"bouc-wen\", at=\"edges\", k=1e7, eps=0.05, d_y=0.02, alpha=0, beta=0}'",
          "device[0]: bouc-wen law: beta: alpha + beta must be positive (bounded hysteresis)");
  // Masses and lengths too small for the eigenproblems; more nodes than seconds of work.
  refused("modal --set structure.masses=[1e-300,1,1,1]", "structure.masses[0]: must be in [0.001, 1e+12] kg");
  refused("modal --set structure.heights=[1e-300,10,20,30]", "structure.heights[0]: must be in [0.001, 10000] m");
  std::string many = "[";
  for (int i = 1; i <= 1001; ++i) many += std::to_string(i) + (i < 1001 ? "," : "]");
  refused("modal --set structure.heights=" + many, "structure.heights: 1001 nodes (at most 1000)");
  // Scale factors on a pulse, and scaling that takes a motion beyond 100 g.
  refused("simulate --set excitation.scale=1e300 --out " + dir.string(), "excitation.scale: must be non-zero and within +-1000");
  refused("simulate --set excitation.scale=0 --out " + dir.string(), "excitation.scale: must be non-zero");
  refused("simulate --set excitation.amplitude_g=1e300 --out " + dir.string(), "excitation.amplitude_g: must be within +-100 [g]");
  refused("simulate --scale 1e300 --out " + dir.string(), "scale factor 1e+300 takes one-sine pulse");
  refused("simulate --record " + elcentro + " --scale 400 --out " + dir.string(), "beyond 100 g");
  refused("ida --record " + elcentro + " --scales 1,1e300 --out " + (dir / "ida").string(), "--scales 1e+300: ");
  refused("ida --record " + elcentro + " --im sa:1 --levels 1,1e9 --out " + (dir / "ida").string(), "--levels 1e+09: ");
  CHECK_FALSE(fs::exists(dir / "ida" / "ida.csv"));
  // Time steps no record has.
  refused("simulate --record " + elcentro + " --dt 1e-300 --out " + dir.string(), "--dt 1e-300: must be in [1e-06, 10] s");
  std::ofstream(dir / "tiny.txt") << "0 0.1\n1e-300 0.2\n0.01 0\n";
  refused("simulate --record " + (dir / "tiny.txt").string() + " --out " + dir.string(), "tiny.txt:2: t = 1e-300 s is 1e-300 s after");
}

TEST_CASE("requests for endless work are refused up front: bisection to round-off, millions of runs or periods") {
  const fs::path dir = scratch_dir("hostile_work");
  const auto records = records_dir();
  if (!records) return;
  const std::string elcentro = *records + "/elcentro_1940_ns.at2";
  refused("ida --record " + elcentro + " --hunt --precision 1e-15 --out " + dir.string(), "--precision 1e-15: at least 1e-9 x --hunt-max");
  refused("ida --record " + elcentro + " --scales 0.0001:100:0.0001 --out " + dir.string(), "more than --max-runs 100000");
  refused("record " + elcentro + " --periods 0.01:10:1e-5", "--periods 0.01:10:1e-5: 999001 periods (at most 10000)");
  refused("record " + elcentro + " --periods 1e-300", "--periods 1e-300: period 1e-300 s: must be in [0.001, 1000] s");
  refused("ida --record " + elcentro + " --im sa:1e-300 --levels 1 --out " + dir.string(), "period 1e-300 s must be in [0.001, 1000] s");
  refused("tradeoff --repeats 1000000000 --out " + dir.string(), "--repeats 1000000000: must be in [1, 100]");
  refused("tradeoff --rtols 1e-20 --out " + dir.string(), "--rtols 1e-20: 1e-20 is not in [1e-12, 0.1]");
  refused("spectrum --frequencies 0.5:10:0.001 --amplitudes 0.5:8:0.001 --out " + dir.string(), "pulses (at most 200000)");
  refused("spectrum --sizes 1e300 --out " + dir.string(), "--sizes 1e300: every size factor must be in [0.01, 100]");
}

TEST_CASE("fit options that would write NaN or infinity into a scene table are refused") {
  const std::string test = std::string(ROCKING_SOURCE_DIR) + "/data/tests/bouc_wen_cyclic.csv";
  refused("fit " + test + " --at nan", "--at nan: edges, or x [m] from the centre line");
  refused("fit " + test + " --name 'a\"b'", "--name a\"b: letters, digits, _ or -");
  refused("fit " + test + " --thickness 1e300", "--thickness 1e+300: must be a ratio in (0, 100]");
  refused("fit " + test + " --fix k=1e300", "--fix k=1e+300: must be > 0 and <= 1e+13 [N/m]");
  refused("fit " + test + " --stiffness 1e300", "plate scaling gives k = 1e+300");
}

TEST_CASE("a summary that cannot be written ends with exit 3 naming the file and the cause, and leaves no partial file") {
  if (!fs::exists("/dev/full")) {
    WARN_MESSAGE(false, "SKIPPED: no /dev/full");
    return;
  }
  const fs::path dir = scratch_dir("hostile_full_summary");
  fs::create_symlink("/dev/full", dir / "summary.json.reserved");  // the room the summary is written into before its rename
  const Result r = run("-q simulate --duration 1 --out " + dir.string());
  CHECK(r.code == 3);
  CHECK(lines(r.err) == 1);
  CHECK(contains(r.err, (dir / "summary.json").string() + ": cannot write: No space left on device"));
  CHECK_FALSE(fs::exists(dir / "summary.json"));
}

TEST_CASE("a CVODE study with a fixed-base variant runs without SUNDIALS' own error lines") {
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("hostile_cvode");
  const Result r = run("-q ida --record " + *records + "/elcentro_1940_ns.at2 --scales 1 --variants fixed-base "
                       "--integrator cvode --duration 5 --no-plot --out " + dir.string());
  CHECK(r.code == 0);
  CHECK_MESSAGE(!contains(r.err, "CVLS"), r.err);
  CHECK_MESSAGE(!contains(r.err, "ERROR"), r.err);
}

TEST_CASE("a folder of records with notes beside them, a list with a missing entry, and a byte-order mark") {
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("hostile_folders");
  fs::create_directories(dir / "suite");
  fs::copy_file(*records + "/elcentro_1940_ns.at2", dir / "suite" / "elcentro_1940_ns.at2");
  // Prose whose first line has commas and a word "a": no table of numbers follows it.
  std::ofstream(dir / "suite" / "README.md") << "# Records, a suite, and where they come from\n\n"
                                                "Each file is a record, scaled as the study says.\n";
  fs::copy_file(*records + "/SOURCES.md", dir / "suite" / "SOURCES.md");
  const Result folder = run("-q ida --record " + (dir / "suite").string() + " --scales 1 --variants no-damper "
                            "--no-plot --out " + (dir / "out").string());
  CHECK_MESSAGE(folder.code == 0, folder.err);
  CHECK(lines(file_text(dir / "out" / "ida.csv")) == 2);  // the header and El Centro's row
  // A list naming one file that is missing: that entry, at its line.
  std::ofstream(dir / "list.txt") << "# suite\n" << *records << "/elcentro_1940_ns.at2\n" << *records << "/no_such.at2\n";
  refused("ida --record " + (dir / "list.txt").string() + " --scales 1 --out " + (dir / "out2").string(),
          "list.txt:3: " + *records + "/no_such.at2: record file not found");
  // A CSV saved with a UTF-8 byte-order mark reads as the same file without it.
  std::ofstream(dir / "bom.csv") << "\xEF\xBB\xBFtime (s),acc (g)\n0,0\n0.01,0.1\n0.02,0.2\n0.03,0\n";
  std::ofstream(dir / "plain.csv") << "time (s),acc (g)\n0,0\n0.01,0.1\n0.02,0.2\n0.03,0\n";
  const Result bom = run("record " + (dir / "bom.csv").string() + " --json");
  const Result plain = run("record " + (dir / "plain.csv").string() + " --json");
  CHECK_MESSAGE(bom.code == 0, bom.err);
  CHECK(bom.out.substr(bom.out.find("pga")) == plain.out.substr(plain.out.find("pga")));
}
