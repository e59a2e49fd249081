// Runs the `rocking` program (ROCKING_BIN) as a user would, capturing stdout,
// stderr and the exit code, for the command-line tests.
#pragma once
#include <doctest/doctest.h>
#include <array>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>
#include <sys/wait.h>
#include <unistd.h>

namespace cli {

struct Result {
  int code = -1;
  std::string out, err;
};

// Runs the program with `args` (shell words), capturing stdout and stderr.
// Given `limit_s`, a program still running after that many seconds is killed
// (exit code 137), so that a test of something that must end cannot hang.
inline Result run(const std::string& args, int limit_s = 0) {
  const std::string err_file = std::string(std::tmpnam(nullptr));
  const std::string limit = limit_s > 0 ? "timeout -s KILL " + std::to_string(limit_s) + " " : "";
  const std::string cmd = limit + ROCKING_BIN + " " + args + " 2>" + err_file;
  Result r;
  FILE* pipe = popen(cmd.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe) != nullptr) r.out += buf.data();
  const int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (FILE* f = std::fopen(err_file.c_str(), "r")) {
    while (std::fgets(buf.data(), buf.size(), f) != nullptr) r.err += buf.data();
    std::fclose(f);
  }
  std::remove(err_file.c_str());
  return r;
}

inline int lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Runs the program and checks: exit `code`, one line on stderr holding `says`.
inline void refused(const std::string& args, const std::string& says, int code = 2) {
  const Result r = run(args);
  CHECK_MESSAGE(r.code == code, args << " -> " << r.code << " " << r.err);
  CHECK_MESSAGE(lines(r.err) == 1, args << " -> " << r.err);
  CHECK_MESSAGE(contains(r.err, says), args << " -> " << r.err);
  CHECK_MESSAGE(!contains(r.err, "internal error"), args);
}

// Starts the program with `args` (argument words, no shell) in a process of
// its own, stdout to /dev/null and stderr to `err_file`, SIGINT ignored when
// `ignore_int` (as a shell starts a background job); returns its pid.
inline pid_t spawn(const std::vector<std::string>& args, const std::string& err_file, bool ignore_int = false) {
  std::fflush(nullptr);  // the child would write the test's buffered output again
  const pid_t pid = ::fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {
    std::vector<char*> argv{const_cast<char*>(ROCKING_BIN)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (ignore_int) ::signal(SIGINT, SIG_IGN);
    (void)std::freopen("/dev/null", "w", stdout);
    (void)std::freopen(err_file.c_str(), "w", stderr);
    ::execv(ROCKING_BIN, argv.data());
    std::_Exit(127);
  }
  return pid;
}

}  // namespace cli

using cli::Result;
using cli::run;
using cli::lines;
using cli::contains;
using cli::refused;
using cli::spawn;
