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
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// A PEER-style file: three header lines, the NPTS/DT line, then the values.
std::string at2(const fs::path& file, const std::string& header_line, const std::string& values = "0.1 0.2 0.1 0.0\n") {
  std::ofstream(file) << "PEER NGA STRONG MOTION DATABASE RECORD\nTest, 1/1/2000, STATION, N\n"
                         "ACCELERATION TIME SERIES IN UNITS OF G\n"
                      << header_line << "\n"
                      << values;
  return file.string();
}

// Runs the program and checks: exit `code`, one line on stderr holding `says`.
void refused(const std::string& args, const std::string& says, int code = 2) {
  const Result r = run(args);
  CHECK_MESSAGE(r.code == code, args << " -> " << r.code << " " << r.err);
  CHECK_MESSAGE(lines(r.err) == 1, args << " -> " << r.err);
  CHECK_MESSAGE(contains(r.err, says), args << " -> " << r.err);
  CHECK_MESSAGE(!contains(r.err, "internal error"), args);
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
  refused("modal --set structure.youngs_modulus=1e308", "structure.youngs_modulus: must be positive and at most 1e+13 Pa");
  refused("modal --set structure.masses=[1e15,1,1,1]", "structure.masses[0]: must be positive and at most 1e+12 kg");
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
  fs::create_symlink("/dev/full", dir / "history.csv");
  const Result r = run("-q simulate --out " + dir.string());
  CHECK(r.code == 3);
  CHECK(lines(r.err) == 1);
  CHECK(contains(r.err, (dir / "history.csv").string() + ": cannot write: No space left on device"));
  CHECK(contains(file_text(dir / "summary.json"), "\"outcome\": \"failed\""));
}
