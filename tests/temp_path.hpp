// Files for the tests: a path in a temporary folder that no other test
// process uses (CTest runs test cases in parallel processes, and two checkouts
// may test at once) and that is removed when the process exits, a fresh folder
// there, and a file's whole content.
#pragma once
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>

// This process's folder, TMPDIR/rocking_PID, removed with everything in it at exit.
inline const std::filesystem::path& test_process_dir() {
  struct Owned {
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ("rocking_" + std::to_string(::getpid()));
    pid_t owner = ::getpid();
    ~Owned() {
      std::error_code ec;
      if (::getpid() == owner) std::filesystem::remove_all(dir, ec);  // not from a forked child
    }
  };
  static const Owned owned;
  std::filesystem::create_directories(owned.dir);
  return owned.dir;
}

inline std::filesystem::path temp_path(const std::string& name) { return test_process_dir() / name; }

// An empty folder of its own for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const std::filesystem::path dir = temp_path(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes `text` to a file of this name in the process's folder; its path.
inline std::string write_temp(const std::string& name, const std::string& text) {
  const std::filesystem::path path = temp_path(name);
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

// The bytes of a file ("" if it cannot be read).
inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
