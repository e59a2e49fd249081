// Runs the `rocking` program (ROCKING_BIN) as a user would, capturing stdout,
// stderr and the exit code, for the command-line tests.
#pragma once
#include <doctest/doctest.h>
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

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

}  // namespace cli

using cli::Result;
using cli::run;
using cli::lines;
