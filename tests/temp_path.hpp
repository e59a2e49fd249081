// Files for the tests: a path in the temporary folder that no other test
// process uses (CTest runs test cases in parallel processes, and two checkouts
// may test at once), a fresh folder there, and a file's whole content.
#pragma once
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <unistd.h>

inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("rocking_" + std::to_string(::getpid()) + "_" + name);
}

// An empty folder of its own for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const std::filesystem::path dir = temp_path(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The bytes of a file ("" if it cannot be read).
inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}
