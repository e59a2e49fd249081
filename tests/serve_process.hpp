// `rocking serve --port 0 ARGS` (ROCKING_BIN) in a process of its own, for
// the lab's server tests: the port it printed, its memory, and SIGINT to
// stop it (at the latest when the object goes).
#pragma once
#include <doctest/doctest.h>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <sys/wait.h>
#include <unistd.h>

// `rocking serve --port 0` in a process of its own: its address, and SIGINT to stop it.
struct Server {
  pid_t pid = -1;
  int port = 0;
  std::string first_line;
  FILE* out = nullptr;
  explicit Server(const std::string& args) {
    int pipe_fd[2];
    REQUIRE(::pipe(pipe_fd) == 0);
    pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
      ::dup2(pipe_fd[1], STDOUT_FILENO);
      ::close(pipe_fd[0]);
      ::execl("/bin/sh", "sh", "-c", (std::string("exec ") + ROCKING_BIN + " serve --port 0 " + args).c_str(),
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(pipe_fd[1]);
    out = ::fdopen(pipe_fd[0], "r");
    char line[512] = {};
    if (std::fgets(line, sizeof line, out) != nullptr) first_line = line;
    const auto at = first_line.find("http://127.0.0.1:");
    if (at != std::string::npos) port = std::stoi(first_line.substr(at + 17));
  }
  // The server's peak resident memory so far [MB] (the kernel's VmHWM).
  double peak_mb() const {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    while (std::getline(status, line))
      if (line.starts_with("VmHWM:")) return std::stod(line.substr(6)) / 1024;
    return -1;
  }
  // SIGINT; the exit code and what it printed after the address.
  std::pair<int, std::string> stop() {
    ::kill(pid, SIGINT);
    std::string rest;
    char line[512];
    while (std::fgets(line, sizeof line, out) != nullptr) rest += line;
    int status = 0;
    ::waitpid(pid, &status, 0);
    std::fclose(out);
    pid = -1;
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, rest};
  }
  // SIGINT, and the exit status if the server ends within `limit`; a server
  // that does not is killed, and the answer is empty.
  std::optional<int> stop_within(std::chrono::milliseconds limit) {
    ::kill(pid, SIGINT);
    int status = 0;
    pid_t done = 0;
    for (auto waited = std::chrono::milliseconds(0); done == 0 && waited < limit; waited += std::chrono::milliseconds(10)) {
      done = ::waitpid(pid, &status, WNOHANG);
      if (done == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (done == 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
    }
    std::fclose(out);
    pid = -1;
    if (done == 0) return std::nullopt;
    return status;
  }
  ~Server() {
    if (pid > 0) stop();
  }
};
