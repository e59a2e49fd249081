// Honest at every edge, round two (issue 56): empty and extreme values are
// refused before any run, in one line naming the option or key and the range
// it takes (exit 2); records are held to what their headers state; the
// program's own files are checked when read back; long commands stop within
// 2 s of SIGINT or SIGTERM with whole files; a full disk leaves whole rows and
// a summary.
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>
#include "records.hpp"
#include "rocking_record.hpp"
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

// The file's text with its line `n` (1-based) replaced by `f(line)`.
template <class F>
std::string edit_line(const std::string& text, int n, F f) {
  std::istringstream in(text);
  std::string out;
  int k = 0;
  for (std::string line; std::getline(in, line);) out += (++k == n ? f(line) : line) + "\n";
  return out;
}

// A device table for --set device=[...]: `count` elastic devices on the axis.
std::string devices(int count) {
  std::string list;
  for (int i = 0; i < count; ++i)
    list += (i ? "," : "") + std::string("{kind=\"elastic\", at=0, kinematics=\"vertical\", free_length=10, k=1e6, name=\"d") +
            std::to_string(i) + "\"}";
  return "'device=[" + list + "]'";
}

}  // namespace

TEST_CASE("an empty option value is refused naming the option, not run as if the option were left out") {
  const fs::path dir = scratch_dir("edges_empty");
  const std::string record = rocking_record(dir / "r.txt", 2);
  refused("simulate --record '' --out " + (dir / "a").string(), "--record '': an empty value; it takes FILE");
  CHECK_FALSE(fs::exists(dir / "a"));
  refused("ida --record " + record + " --levels '' --out " + (dir / "b").string(), "--levels '': an empty value");
  CHECK_FALSE(fs::exists(dir / "b"));
  refused("simulate --out ''", "--out '': an empty value; it takes DIR");
  refused("simulate --set ''", "--set '': an empty value");
}

TEST_CASE("a pulse period, an initial velocity and device values beyond what a structure can have are refused with their key") {
  refused("simulate --set excitation.period=1e300", "excitation.period: must be in [0.001, 1000] [s]");
  refused("simulate --set excitation.period=1e-300", "excitation.period: must be in [0.001, 1000] [s]");
  refused("simulate --set initial.theta_dot=1e300", "initial.theta_dot: must be within +-");
  refused("simulate --set 'initial.u_dot=[1e300,0,0,0]'", "initial.u_dot[0]: must be within +-100 [m/s]");
  refused("simulate --set 'initial.u=[0,0,0,1e9]'", "initial.u[3]: must be within +-");
  refused("simulate --set 'device+={kind=\"elastic\", at=0, kinematics=\"vertical\", free_length=1e-300, k=1e6}'",
          "free_length: must be in [0.001, 10000] m");
  refused("simulate --set 'device+={kind=\"bouc-wen\", at=\"edges\", k=2e7, eps=0.05, d_y=1e-300}'",
          "d_y: must be >= 1e-06 and <= 10 [m]");
  refused("simulate --set 'device+={kind=\"bouc-wen\", at=\"edges\", k=2e7, eps=0.05, d_y=0.004, n=1e300}'",
          "n: must be > 0 and <= 50");
  // The paper's dampers: their yield elongation 4B sin(theta_y/2) of a micron at least.
  refused("simulate --set damper.theta_y=1e-300", "damper.theta_y: must be in [1.52e-07, pi/2) [rad]");
}

TEST_CASE("more devices than a scene holds are refused naming the scene") {
  refused("simulate --set " + devices(15), "embedded:christchurch_chimney.toml: device: 17 devices (with the damper's two): "
                                           "a scene holds at most 16");
  const std::string block = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  refused("simulate " + block + " --set " + devices(203), block + ": device: 203 devices");
}

TEST_CASE("FIRST:LAST:STEP lists say which part is wrong") {
  const fs::path dir = scratch_dir("edges_lists");
  const std::string ida = "ida --record " + rocking_record(dir / "r.txt", 2) + " --no-plot --out " + dir.string() + "/o";
  refused(ida + " --levels 5:1:1", "--levels '5:1:1': LAST 1 is below FIRST 5");
  refused(ida + " --levels 1:5:0", "--levels '1:5:0': STEP 0 must be positive");
  refused(ida + " --levels 1:5:-1", "STEP -1 must be positive");
  refused(ida + " --levels 0:1e9:1", "--levels '0:1e9:1': 1e+09 values; a list holds at most 1000001");
  CHECK_FALSE(fs::exists(dir / "o" / "ida.csv"));
}

TEST_CASE("spectrum frequencies and amplitudes are pulses a ground can make: periods of 1 ms to 1000 s, at most 100 g") {
  refused("spectrum --frequencies 1e-300", "--frequencies 1e-300: ratio 1e-300 is a pulse period of");
  refused("spectrum --frequencies 1e-300", "(periods 1e-3 to 1e3 s)");
  refused("spectrum --amplitudes 999", "--amplitudes 999: ratio 999 is a pulse of");
}

TEST_CASE("animate: a speed or exaggeration that cannot be drawn is refused naming the option") {
  const fs::path dir = scratch_dir("edges_animate");
  const std::string block = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  const std::string animate = "animate " + block + " --frames 4 --out " + (dir / "a.gif").string();
  refused(animate + " --speed inf", "--speed inf: at most");
  refused(animate + " --exaggerate 1e300", "--exaggerate 1e+300: draws the peak top displacement");
  refused(animate + " --exaggerate-rotation 1e300", "--exaggerate-rotation 1e+300: draws the peak rocking angle");
  refused(animate + " --exaggerate-rotation 1e300", "(the structure on its side at pi/2)");
  CHECK_FALSE(fs::exists(dir / "a.gif"));
}

TEST_CASE("fit: an anchor off the base, a test that never loads the device and data beyond any device are refused") {
  const fs::path dir = scratch_dir("edges_fit");
  const std::string test = std::string(ROCKING_SOURCE_DIR) + "/data/tests/bouc_wen_cyclic.csv";
  refused("fit " + test + " --at 100", "--at 100: x must lie on the base of the built-in chimney, -B <= x <= B = ");
  const std::string block = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  refused("fit " + test + " --at 100 --scene " + block, "--at 100: x must lie on the base of " + block);
  refused("fit " + test + " --fix d_y=1e-300", "--fix d_y=1e-300: must be >= 1e-06");
  {
    std::ofstream out(dir / "constant.csv");
    out << "time [s],displacement [mm],force [kN]\n";
    for (int i = 0; i < 50; ++i) out << 0.1 * i << ',' << 10 * std::sin(0.3 * i) << ",5\n";
  }
  refused("fit " + (dir / "constant.csv").string() + " --law elastic",
          "constant.csv: column 'force' holds 5000 N in every row: a cyclic test must move and load the device");
  {
    std::ofstream out(dir / "huge.csv");
    out << "time [s],displacement [mm],force [kN]\n";
    for (int i = 0; i < 50; ++i) out << 0.1 * i << ',' << 10 * std::sin(0.3 * i) << ',' << 1e300 * std::sin(0.3 * i) << "\n";
  }
  refused("fit " + (dir / "huge.csv").string(), "huge.csv:3: ");
  refused("fit " + (dir / "huge.csv").string(), "in column 'force' is beyond 1e+10 N");
}

TEST_CASE("a COSMOS file's time step field and its stated length are checks: a zero or negative step, or NPTS x dt against approx secs, is refused") {
  const auto records = records_dir();
  if (!records) return;
  const std::string v2c = file_text(fs::path(*records) / "formats" / "us1000hyfh_akbmrp_bnz.V2c");
  REQUIRE(contains(v2c, "approx  210 secs"));
  const fs::path dir = scratch_dir("edges_cosmos");
  // Real-header field 62 (the time step in ms) is the second of line 38's five.
  auto with_field_62 = [&](const std::string& value) {
    return edit_line(v2c, 38, [&](const std::string& line) {
      std::string l = line;
      const std::string field = std::string(15 - value.size(), ' ') + value;
      l.replace(15, 15, field);
      return l;
    });
  };
  REQUIRE(contains(with_field_62("5.000000"), "       5.000000     210.000000"));
  std::ofstream(dir / "zero.V2c") << with_field_62("0.000000");
  std::ofstream(dir / "negative.V2c") << with_field_62("-5.000000");
  std::ofstream(dir / "long.V2c") << with_field_62("20.000000");
  const std::string sim = "simulate --out " + (dir / "o").string() + " --record ";
  refused(sim + (dir / "zero.V2c").string(), "zero.V2c:38: real header field 62 (the time step) = 0 ms: must be positive");
  refused(sim + (dir / "negative.V2c").string(), "negative.V2c:38: real header field 62 (the time step) = -5 ms");
  refused(sim + (dir / "long.V2c").string(),
          "42000 points of 0.02 s (the header's time step) last 840 s, but the file states approx 210 secs");
  CHECK_FALSE(fs::exists(dir / "o" / "history.csv"));
  // The file as it is still reads.
  CHECK(run("record " + (fs::path(*records) / "formats" / "us1000hyfh_akbmrp_bnz.V2c").string()).code == 0);
}

TEST_CASE("a GeoNet file's stated duration is checked against NPTS x dt") {
  const auto records = records_dir();
  if (!records) return;
  const std::string v2a = file_text(fs::path(*records) / "formats" / "20161113_110259_WTMC_20.V2A");
  REQUIRE(contains(v2a, "Duration 163.82 sec"));
  const fs::path dir = scratch_dir("edges_geonet");
  std::string wrong = v2a;
  wrong.replace(wrong.find("Duration 163.82 sec"), 19, "Duration 655.28 sec");
  std::ofstream(dir / "long.V2A") << wrong;
  refused("simulate --out " + (dir / "o").string() + " --record " + (dir / "long.V2A").string(),
          "8192 points of 0.02 s (the numeric header's time step) last 163.82 s, but the file states a Duration of 655.28 sec");
}

TEST_CASE("plot --from refuses a history that is cut, holds nan or inf, or lacks the drift, naming the file and line") {
  const fs::path dir = scratch_dir("edges_from");
  const std::string record = rocking_record(dir / "r.txt", 3);
  REQUIRE(run("-q simulate --record " + record + " --out " + (dir / "run").string()).code == 0);
  const std::string history = file_text(dir / "run" / "history.csv");
  const int rows = lines(history);
  REQUIRE(rows > 100);
  auto from = [&](const std::string& name, const std::string& text) {
    fs::create_directories(dir / name);
    std::ofstream(dir / name / "history.csv", std::ios::binary) << text;
    fs::copy_file(dir / "run" / "summary.json", dir / name / "summary.json", fs::copy_options::overwrite_existing);
    return "plot response --formats png --from " + (dir / name).string() + " --out " + (dir / name / "fig").string();
  };
  // Cut in the middle of a row.
  const std::string cut = history.substr(0, history.size() / 2);
  REQUIRE(cut.back() != '\n');
  refused(from("cut", cut), "cut/history.csv:" + std::to_string(lines(cut) + 1) + ": the file ends inside this row");
  // nan and inf where a number was.
  const std::string with_nan = edit_line(history, 40, [](const std::string& line) { return line.substr(0, line.rfind(',')) + ",nan"; });
  refused(from("nan", with_nan), "nan/history.csv:40: 'nan' in column");
  const std::string with_inf = edit_line(history, 41, [](const std::string& line) { return "inf" + line.substr(line.find(',')); });
  refused(from("inf", with_inf), "inf/history.csv:41: 'inf' in column t: not a finite number");
  // A row of another file.
  const std::string short_row = edit_line(history, 50, [](const std::string&) { return "1,2,3"; });
  refused(from("short", short_row), "short/history.csv:50: 3 fields where the header has");
  // Three columns, none of them the drift the figure draws.
  refused(from("three", "t [s],x [m],y [m]\n0,1,2\n0.1,2,3\n0.2,3,4\n"), "three/history.csv:1: no delta_t column");
  CHECK_FALSE(fs::exists(dir / "three" / "fig" / "response.png"));
  // The whole history still draws; a cut summary only loses the title, with a warning.
  std::ofstream(dir / "run" / "summary.json", std::ios::trunc) << "{\"scene\": \"chim";
  const Result whole = run("plot response --formats png --from " + (dir / "run").string() + " --out " + (dir / "fig").string());
  CHECK_MESSAGE(whole.code == 0, whole.err);
  CHECK(contains(whole.err, "summary.json: not a whole run summary"));
  CHECK(fs::exists(dir / "fig" / "response.png"));
}

TEST_CASE("--resume runs again a kept row that holds a value that is not finite, and ends with the CSV of an uninterrupted run") {
  const fs::path dir = scratch_dir("edges_resume");
  const std::string ida = "-q ida --record " + rocking_record(dir / "r.txt", 3) + " --scales 1:4:1 --no-plot --out ";
  REQUIRE(run(ida + (dir / "whole").string()).code == 0);
  const std::string whole = file_text(dir / "whole" / "ida.csv");
  REQUIRE(lines(whole) >= 6);
  REQUIRE(run(ida + (dir / "edited").string()).code == 0);
  REQUIRE(file_text(dir / "edited" / "ida.csv") == whole);
  // Row 3 (job 2): its first peak becomes nan.
  const std::string edited = edit_line(whole, 3, [](const std::string& line) {
    std::string l = line;
    std::size_t at = 0;
    for (int c = 0; c < 6; ++c) at = l.find(',', at) + 1;
    return l.substr(0, at) + "nan" + l.substr(l.find(',', at));
  });
  REQUIRE(contains(edited, ",nan,"));
  std::ofstream(dir / "edited" / "ida.csv", std::ios::trunc) << edited;
  const Result resumed = run(ida + (dir / "edited").string() + " --resume");
  CHECK_MESSAGE(resumed.code == 0, resumed.err);
  CHECK(contains(resumed.err, "ida.csv:3: 'nan' in column 7: job 2 runs again"));
  CHECK(file_text(dir / "edited" / "ida.csv") == whole);
}

TEST_CASE("a study whose every run fails writes a header with as many fields as its rows") {
  const fs::path dir = scratch_dir("edges_all_fail");
  // Each variant of the sweep is a scene its checks refuse: no run can start.
  const Result r = run("-q sweep --record " + rocking_record(dir / "r.txt", 1) + " --scales 1,2 --no-plot --set "
                       "structure.EI_scale=1e300,1e301 --out " + (dir / "o").string());
  CHECK_MESSAGE(r.code == 4, r.err);
  const std::string csv = file_text(dir / "o" / "sweep.csv");
  REQUIRE(lines(csv) == 5);
  // Fields of a CSV line, a quoted field (the error) taken whole.
  auto fields = [](const std::string& line) {
    int n = 1;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) ++n;
    }
    return n;
  };
  std::istringstream in(csv);
  std::string header, row;
  std::getline(in, header);
  CHECK_FALSE(contains(header, ",,"));
  while (std::getline(in, row)) {
    CHECK_MESSAGE(fields(row) == fields(header), header << "\n" << row);
    CHECK(contains(row, "EI_scale"));
  }
}
