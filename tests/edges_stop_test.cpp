// Stops and faults (issue 56): every long command stops within 2 s of SIGINT
// or SIGTERM with exit 130 or 143 and whole files: a hunt in the middle of its
// runs, figure drawing, an animation (no GIF cut short under its name); a
// background job started with SIGINT ignored keeps it ignored; a full disk
// under simulate names the file, keeps whole rows and writes the summary.
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
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
#include "rocking_record.hpp"
#include "run_program.hpp"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

namespace {

// Ready once `file` has existed for `delay`: a study's partial file appears
// when its runs start.
auto once_there_for(fs::path file, std::chrono::milliseconds delay) {
  return [file = std::move(file), delay, seen = Clock::time_point{}]() mutable {
    if (seen == Clock::time_point{} && fs::exists(file)) seen = Clock::now();
    return seen != Clock::time_point{} && Clock::now() - seen > delay;
  };
}

// A hunt of the chimney without its damper under `record`, into `out`: its fill step makes it last some
// seconds on a fast machine, so that the signals the tests send fall in the middle of its runs.
std::vector<std::string> hunt_args(const std::string& record, const fs::path& out, const std::string& fill = "0.01") {
  return {"-q", "ida", "--record", record, "--hunt", "--scales", "0.5", "--hunt-step", "0.5", "--hunt-max", "10",
          "--fill-step", fill, "--variants", "damper", "--no-plot", "--out", out.string()};
}

struct Stopped {
  int code = -1;       // exit code (-1: killed by a signal, or still running at the limit)
  double seconds = 0;  // from the signal to the exit
  bool ended_before = false;  // the program ended before `ready` held
  std::string err;
};

// Starts the program with `args` (SIGINT ignored when `ignore_int`, as a
// shell starts a background job), waits until `ready()` (at most 120 s), then
// sends each of `signals` 0.5 s apart; returns how it ended, at most 10 s after.
template <class Ready>
Stopped run_and_signal(const std::vector<std::string>& args, Ready ready, const std::vector<int>& signals,
                       bool ignore_int = false) {
  const std::string err_file = temp_path("stop_stderr_" + std::to_string(::getpid()) + ".txt").string();
  const pid_t pid = spawn(args, err_file, ignore_int);
  Stopped s;
  int status = 0;
  auto finish = [&](bool ended) {
    s.code = ended && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    s.err = file_text(err_file);
    return s;
  };
  for (const auto start = Clock::now(); !ready();) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      s.ended_before = true;
      return finish(true);
    }
    if (Clock::now() - start > std::chrono::seconds(120)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  Clock::time_point sent;
  for (std::size_t k = 0; k < signals.size(); ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(500));
    sent = Clock::now();
    ::kill(pid, signals[k]);
  }
  for (;;) {
    if (::waitpid(pid, &status, WNOHANG) == pid) {
      s.seconds = std::chrono::duration<double>(Clock::now() - sent).count();
      return finish(true);
    }
    if (Clock::now() - sent > std::chrono::seconds(10)) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      s.seconds = 10;
      return finish(false);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}


// A whole CSV: ends with a newline, every row with the header's number of commas.
void check_whole_csv(const fs::path& file) {
  const std::string text = file_text(file);
  REQUIRE_MESSAGE(!text.empty(), file);
  CHECK(text.back() == '\n');
  std::istringstream in(text);
  std::string header, row;
  std::getline(in, header);
  const auto commas = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
  while (std::getline(in, row)) CHECK_MESSAGE(commas(row) == commas(header), file << ": " << row);
}

}  // namespace

TEST_CASE("SIGINT and SIGTERM stop a hunt within 2 s, in the middle of its runs, with no row of a hunt cut short") {
  const fs::path dir = scratch_dir("edges_stop_hunt");
  const std::string record = rocking_record(dir / "r.txt", 30);
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    const fs::path out = dir / ("hunt" + std::to_string(signal));
    // Stopped half a second into the one hunt (its runs under way).
    const Stopped s = run_and_signal(hunt_args(record, out), once_there_for(out / "hunt.csv.partial", 500ms), {signal});
    REQUIRE_FALSE(s.ended_before);
    CHECK(s.code == 128 + signal);
    CHECK(s.seconds < 2.0);
    CHECK(lines(s.err) == 1);
    CHECK(contains(s.err, "--resume"));
    check_whole_csv(out / "hunt.csv");
    CHECK(lines(file_text(out / "hunt.csv")) == 1);  // the hunt was cut short: no row of it
    const Result resumed = run("-q ida --record " + record + " --hunt --scales 0.5 --hunt-step 0.5 --hunt-max 10 --fill-step 0.01 "
                               "--variants damper --no-plot --out " + out.string() + " --resume");
    CHECK_MESSAGE(resumed.code == 0, resumed.err);
    CHECK(lines(file_text(out / "hunt.csv")) == 2);
  }
}

TEST_CASE("SIGINT stops a study of a tall tower within 2 s, its runs in flight cut short and left for --resume") {
  const fs::path dir = scratch_dir("edges_stop_tower");
  const std::string record = rocking_record(dir / "r.txt", 30);
  const fs::path out = dir / "tower";
  const std::string tower = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/towers/tower_64.toml";
  const Stopped s = run_and_signal({"-q", "ida", tower, "--record", record, "--scales", "1,2", "--integrator", "rk45",
                                    "--threads", "2", "--no-plot", "--out", out.string()},
                                   once_there_for(out / "ida.csv.partial", 1500ms), {SIGINT});
  REQUIRE_FALSE(s.ended_before);
  CHECK(s.code == 130);
  CHECK(s.seconds < 2.0);
  check_whole_csv(out / "ida.csv");
}

TEST_CASE("a background job started with SIGINT ignored keeps it ignored, and stops on SIGTERM") {
  const fs::path dir = scratch_dir("edges_stop_background");
  const std::string record = rocking_record(dir / "r.txt", 30);
  const fs::path out = dir / "hunt";
  // SIGINT, then half a second later SIGTERM: only the second stops it. The job is stopped, never finished,
  // so its fill is ten times finer than the other tests': it cannot end between the signals on a fast machine.
  const Stopped s = run_and_signal(hunt_args(record, out, "0.001"), once_there_for(out / "hunt.csv.partial", 300ms),
                                   {SIGINT, SIGTERM}, true);
  REQUIRE_FALSE(s.ended_before);
  CHECK(s.code == 143);
  CHECK(contains(s.err, "SIGTERM"));
  CHECK(s.seconds < 2.0);
}

TEST_CASE("SIGINT and SIGTERM while a study draws its figures exit 130 or 143 within 2 s, its tables whole") {
  const fs::path dir = scratch_dir("edges_stop_figures");
  const std::string record = rocking_record(dir / "r.txt", 2);
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    const fs::path out = dir / ("ida" + std::to_string(signal));
    const Stopped s = run_and_signal({"-q", "ida", "--record", record, "--scales", "1:3:1", "--formats", "png,pdf,svg",
                                      "--out", out.string()},
                                     [&] { return fs::exists(out / "ida.csv"); }, {signal});
    REQUIRE_FALSE(s.ended_before);
    CHECK_MESSAGE(s.code == 128 + signal, s.err);
    CHECK(s.seconds < 2.0);
    CHECK_FALSE(contains(s.err, "gnuplot failed"));
    CHECK(contains(s.err, signal == SIGINT ? "stopped by SIGINT" : "stopped by SIGTERM"));
    check_whole_csv(out / "ida.csv");
    CHECK(lines(file_text(out / "ida.csv")) == 1 + 3 * 3);
  }
}

TEST_CASE("SIGINT and SIGTERM on animate exit 130 or 143 within 2 s and leave no GIF cut short under its name") {
  const fs::path dir = scratch_dir("edges_stop_animate");
  const std::string record = rocking_record(dir / "r.txt", 12);
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    const fs::path gif = dir / ("a" + std::to_string(signal) + ".gif");
    const fs::path frames = dir / ("a" + std::to_string(signal) + ".data") / "traces.dat";
    const Stopped s = run_and_signal({"-q", "animate", "--record", record, "--frames", "600", "--speed", "0.2", "--size", "1600x1100",
                                      "--out", gif.string()},
                                     [&] { return fs::exists(gif) && fs::file_size(gif) > 0; }, {signal});
    REQUIRE_FALSE(s.ended_before);
    CHECK(fs::exists(frames));
    CHECK_MESSAGE(s.code == 128 + signal, s.err);
    CHECK(s.seconds < 2.0);
    CHECK_FALSE(fs::exists(gif));
  }
}

TEST_CASE("simulate on a full disk names the history, keeps its whole rows and writes the summary (a 2 MB tmpfs)") {
  const fs::path dir = scratch_dir("edges_full_disk");
  const std::string record = rocking_record(dir / "r.txt", 60);
  const fs::path disk = dir / "disk";
  fs::create_directories(disk);
  if (::geteuid() != 0 || ::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=2m") != 0) {
    WARN_MESSAGE(false, "SKIPPED: cannot mount a 2 MB tmpfs here (not root, or no mount permission)");
    return;
  }
  struct Unmount {
    fs::path at;
    ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
  } unmount{disk};
  const Result r = run("-q simulate --record " + record + " --every 0.0005 --out " + (disk / "run").string());
  CHECK(r.code == 3);
  CHECK(lines(r.err) == 1);
  CHECK_MESSAGE(contains(r.err, (disk / "run" / "history.csv").string() + ": cannot write: No space left on device"), r.err);
  CHECK_FALSE(fs::exists(disk / "run" / "history.csv"));
  check_whole_csv(disk / "run" / "history.csv.partial");
  CHECK(lines(file_text(disk / "run" / "history.csv.partial")) > 1000);
  const auto summary = nlohmann::json::parse(file_text(disk / "run" / "summary.json"), nullptr, false);
  REQUIRE_FALSE(summary.is_discarded());
  CHECK(summary["outcome"] == "failed");
  CHECK_FALSE(fs::exists(disk / "run" / "summary.json.reserved"));
}
