// Clean stops (issue 21): SIGINT and SIGTERM on a running study keep every
// completed row, whole, write the timings and a one-line note, exit 130 / 143,
// and `--resume` ends with the byte-identical CSV of an uninterrupted run; on a
// running simulation they keep the history and mark the summary interrupted.
#include <doctest/doctest.h>
#include "sanitizers.hpp"
#include "temp_path.hpp"
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>
#include "rocking_record.hpp"
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

int lines_of(const fs::path& file) {
  std::ifstream in(file);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

// Starts the program with `args`, waits until `file` has `rows` lines (or the
// program has ended), sends `signal`; returns the exit status (-1: killed).
int run_and_stop(const std::vector<std::string>& args, const fs::path& file, int rows, int signal) {
  const pid_t pid = spawn(args, file.parent_path().string() + ".stderr.txt");  // beside the output folder
  int status = 0;
  for (int i = 0; i < 60000; ++i) {  // at most 60 s
    if (::waitpid(pid, &status, WNOHANG) == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (fs::exists(file) && lines_of(file) >= rows) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ::kill(pid, signal);
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("SIGINT and SIGTERM stop a study cleanly, and --resume ends with the CSV of an uninterrupted run") {
  skip_under_sanitizers("a study run whole and again with --resume");
  const fs::path dir = scratch_dir("stop_ida");
  const std::string record = rocking_record(dir / "long.txt", 30);
  const std::vector<std::string> study = {"-q", "ida", "--record", record, "--scales", "1:8:0.02", "--no-plot"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = study;
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
  };
  std::string whole;
  {
    std::string cmd = "-q ida --record " + record + " --scales 1:8:0.02 --no-plot --out " + (dir / "whole").string();
    REQUIRE(run(cmd).code == 0);
    whole = file_text(dir / "whole" / "ida.csv");
    REQUIRE(lines(whole) == 1 + 351 * 3);
  }
  for (const int signal : {SIGINT, SIGTERM}) {
    CAPTURE(signal);
    const fs::path out = dir / (signal == SIGINT ? "int" : "term");
    const int code = run_and_stop(with({"--out", out.string()}), out / "ida.csv.partial", 20, signal);
    CHECK(code == 128 + signal);
    const std::string note = file_text(out.string() + ".stderr.txt");
    CHECK(lines(note) == 1);  // one line: how far it got, and how to go on
    CHECK(note.find(signal == SIGINT ? "stopped by SIGINT after " : "stopped by SIGTERM after ") != std::string::npos);
    CHECK(note.find("--resume") != std::string::npos);
    const std::string part = file_text(out / "ida.csv");
    CHECK(lines(part) >= 20);
    CHECK(lines(part) < lines(whole));
    CHECK(whole.starts_with(part));  // every row kept is whole and as an uninterrupted run writes it
    CHECK(lines(file_text(out / "timing.csv")) == lines(part));
    CHECK_FALSE(fs::exists(out / "ida.csv.partial"));
    const Result resumed = run("-q ida --record " + record + " --scales 1:8:0.02 --no-plot --out " + out.string() +
                               " --resume");
    CHECK(resumed.code == 0);
    CHECK(file_text(out / "ida.csv") == whole);
    CHECK(lines(file_text(out / "timing.csv")) == lines(whole));
  }
  // A resume of another study is refused, naming what differs: the levels,
  // the scene, the integrator, the tolerance.
  const std::string again = "-q ida --record " + record + " --no-plot --out " + (dir / "int").string() + " --resume";
  for (const auto& [change, differs] : {std::pair{std::string(" --scales 2:8:0.02"), "another levels"},
                                        {" --scales 1:8:0.02 --set damper.thickness=2", "another scene"},
                                        {" --scales 1:8:0.02 --integrator cvode", "another integrator"},
                                        {" --scales 1:8:0.02 --rtol 1e-6", "another integrator"}}) {
    const Result other = run(again + change);
    CHECK(other.code == 2);
    CHECK(lines(other.err) == 1);
    CHECK_MESSAGE(other.err.find(differs) != std::string::npos, other.err);
  }
  // Rows of a study killed outright (a second signal) are in the .partial
  // files, the last one perhaps cut: --resume takes the whole rows from there.
  const fs::path killed = dir / "killed";
  fs::create_directories(killed);
  for (const char* f : {"ida.csv", "timing.csv", "inputs.txt"}) fs::copy_file(dir / "whole" / f, killed / f);
  fs::rename(killed / "ida.csv", killed / "ida.csv.partial");
  fs::rename(killed / "timing.csv", killed / "timing.csv.partial");
  std::string rows = whole.substr(0, whole.find('\n', whole.size() / 2) + 25);  // cut inside a row
  std::ofstream(killed / "ida.csv.partial", std::ios::trunc) << rows;
  const Result resumed = run("-q ida --record " + record + " --scales 1:8:0.02 --no-plot --out " + killed.string() +
                             " --resume");
  CHECK_MESSAGE(resumed.code == 0, resumed.err);
  CHECK(file_text(killed / "ida.csv") == whole);
}

TEST_CASE("one study at a time in a folder, and no folder where a study's file goes") {
  const fs::path dir = scratch_dir("stop_lock");
  const std::string record = rocking_record(dir / "short.txt", 2);
  const std::string ida = "-q ida --record " + record + " --scales 1,2 --no-plot --out " + (dir / "out").string();
  fs::create_directories(dir / "out");
  {
    // Another study holds the folder (the lock the program takes, taken here).
    const int fd = ::open((dir / "out" / ".lock").c_str(), O_RDWR | O_CREAT, 0644);
    REQUIRE(fd >= 0);
    REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
    const Result busy = run(ida);
    CHECK(busy.code == 2);
    CHECK(lines(busy.err) == 1);
    CHECK(busy.err.find("another study is writing there") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out" / "ida.csv"));
    ::close(fd);
  }
  CHECK(run(ida).code == 0);  // the lock is gone with its holder
  // A folder where ida.csv goes is refused before the first run.
  fs::create_directories(dir / "blocked" / "ida.csv");
  const Result blocked = run("-q ida --record " + record + " --scales 1,2 --no-plot --out " + (dir / "blocked").string());
  CHECK(blocked.code == 2);
  CHECK(blocked.err.find("ida.csv: a folder stands where the study writes this file") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "blocked" / "timing.csv.partial"));
}

TEST_CASE("SIGINT stops a simulation with its history up to there and a summary marked interrupted") {
  const fs::path dir = scratch_dir("stop_simulate");
  const std::string record = rocking_record(dir / "long.txt", 600);
  const int code = run_and_stop({"-q", "simulate", "--record", record, "--rtol", "1e-10", "--integrate-contact", "--out",
                                 dir.string()},
                                dir / "history.csv.partial", 2000, SIGINT);
  CHECK(code == 130);
  const std::string summary = file_text(dir / "summary.json");
  CHECK(summary.find("\"interrupted\": true") != std::string::npos);
  const std::string history = file_text(dir / "history.csv");
  CHECK(history.ends_with("\n"));  // no cut row
  CHECK_FALSE(fs::exists(dir / "history.csv.partial"));
  CHECK(lines(history) >= 2000);
  CHECK(lines(history) < 60000);
}

TEST_CASE("SIGINT stops a hunt with its finished hunts kept whole, and --resume ends with the hunt.csv of an uninterrupted run") {
  skip_under_sanitizers("hunts run whole and again with --resume");
  const fs::path dir = scratch_dir("stop_hunt");
  std::string records;
  for (int k = 1; k <= 6; ++k) records += " " + rocking_record(dir / ("r" + std::to_string(k) + ".txt"), 10 + k);
  const std::string hunt = "-q ida --record" + records + " --hunt --scales 1 --hunt-max 20 --variants damper,no-damper "
                           "--no-plot --threads 2 --out ";
  REQUIRE(run(hunt + (dir / "whole").string()).code == 0);
  const std::string whole = file_text(dir / "whole" / "hunt.csv");
  REQUIRE(lines(whole) == 1 + 12);
  std::vector<std::string> args{"-q", "ida", "--record"};
  for (int k = 1; k <= 6; ++k) args.push_back((dir / ("r" + std::to_string(k) + ".txt")).string());
  for (const char* a : {"--hunt", "--scales", "1", "--hunt-max", "20", "--variants", "damper,no-damper", "--no-plot",
                        "--threads", "2", "--out"})
    args.emplace_back(a);
  const fs::path out = dir / "stopped";
  args.push_back(out.string());
  const int code = run_and_stop(args, out / "hunt.csv.partial", 3, SIGINT);
  CHECK(code == 130);
  const std::string note = file_text(out.string() + ".stderr.txt");
  CHECK(lines(note) == 1);
  CHECK(note.find("stopped by SIGINT after ") != std::string::npos);
  CHECK(note.find("--resume") != std::string::npos);
  const std::string part = file_text(out / "hunt.csv");
  CHECK(lines(part) >= 3);
  CHECK(lines(part) < lines(whole));
  CHECK(whole.starts_with(part));
  const Result resumed = run(hunt + out.string() + " --resume");
  CHECK_MESSAGE(resumed.code == 0, resumed.err);
  CHECK(file_text(out / "hunt.csv") == whole);
  CHECK(file_text(out / "fragility.csv") == file_text(dir / "whole" / "fragility.csv"));
}

TEST_CASE("SIGINT stops a spectrum with the pulses done kept, and --resume ends with the spectrum of an uninterrupted run") {
  skip_under_sanitizers("a spectrum run whole and again with --resume");
  const fs::path dir = scratch_dir("stop_spectrum");
  const std::string grid = " --sizes 1,2 --frequencies 0.5:10:0.5 --amplitudes 0.5:8:0.05 --formats png --out ";
  REQUIRE(run("-q spectrum" + grid + (dir / "whole").string()).code == 0);
  const fs::path out = dir / "stopped";
  fs::create_directories(out);  // where run_and_stop puts the program's stderr
  // Stopped once the first size is written: in the middle of the second.
  const int code = run_and_stop({"-q", "spectrum", "--sizes", "1,2", "--frequencies", "0.5:10:0.5", "--amplitudes",
                                 "0.5:8:0.05", "--formats", "png", "--out", out.string()},
                                out / "spectrum.data" / "size_1.csv", 2, SIGINT);
  CHECK(code == 130);
  const std::string note = file_text((out / "spectrum.data").string() + ".stderr.txt");  // beside the file waited on
  CHECK(lines(note) == 1);
  CHECK(note.find("stopped by SIGINT after ") != std::string::npos);
  CHECK(note.find("--resume") != std::string::npos);
  CHECK_FALSE(fs::exists(out / "spectrum.data" / "size_2.csv"));
  const std::string part = file_text(out / "spectrum.data" / "size_2.csv.partial");
  const std::string whole2 = file_text(dir / "whole" / "spectrum.data" / "size_2.csv");
  CHECK(whole2.starts_with(part));
  CHECK(lines(part) < lines(whole2));
  const Result resumed = run("-q spectrum" + grid + out.string() + " --resume");
  CHECK_MESSAGE(resumed.code == 0, resumed.err);
  for (const char* f : {"size_1.csv", "size_2.csv"})
    CHECK(file_text(out / "spectrum.data" / f) == file_text(dir / "whole" / "spectrum.data" / f));
  CHECK_FALSE(fs::exists(out / "spectrum.data" / "size_2.csv.partial"));
  CHECK(fs::exists(out / "spectrum.png"));
  // Another grid is another spectrum: refused.
  const Result other = run("-q spectrum --sizes 1,2 --frequencies 0.5:10:1 --amplitudes 0.5:8:0.05 --formats png --out " +
                           out.string() + " --resume");
  CHECK(other.code == 2);
  CHECK(other.err.find("another frequencies") != std::string::npos);
}

TEST_CASE("SIGINT stops a tradeoff with the measurements done kept whole, and --resume measures the rest") {
  const fs::path dir = scratch_dir("stop_tradeoff");
  const fs::path out = dir / "tradeoff";
  const int code = run_and_stop({"-q", "tradeoff", "--backends", "rk45,cvode,arkode", "--repeats", "3", "--formats", "png",
                                 "--out", out.string()},
                                out / "tradeoff.csv", 3, SIGINT);
  CHECK(code == 130);
  const std::string note = file_text(out.string() + ".stderr.txt");
  CHECK(lines(note) == 1);
  CHECK(note.find("stopped by SIGINT after ") != std::string::npos);
  const std::string csv = file_text(out / "tradeoff.csv");
  CHECK(csv.ends_with("\n"));  // whole rows
  CHECK(lines(csv) >= 3);
  CHECK(lines(csv) < 1 + 3 * 8);  // not every measurement
  CHECK(csv.find("inf") == std::string::npos);
  CHECK(csv.find("nan") == std::string::npos);
  CHECK_FALSE(fs::exists(out / "work_precision.png"));
  const Result resumed = run("-q tradeoff --backends rk45,cvode,arkode --repeats 3 --formats png --out " + out.string() +
                             " --resume");
  CHECK_MESSAGE(resumed.code == 0, resumed.err);
  const std::string all = file_text(out / "tradeoff.csv");
  CHECK(all.starts_with(csv));  // the measurements done before, kept as they were
  CHECK(lines(all) == 1 + 3 * 8);
  CHECK(fs::exists(out / "work_precision.png"));
  // Another tolerance ladder is another tradeoff.
  const Result other = run("-q tradeoff --backends rk45,cvode,arkode --rtols 1e-3,1e-4 --repeats 3 --formats png --out " +
                           out.string() + " --resume");
  CHECK(other.code == 2);
  CHECK(other.err.find("another rtols") != std::string::npos);
}
