// A path in the temporary folder that no other test process uses: CTest runs
// test cases in parallel processes (and two checkouts may test at once).
#pragma once
#include <filesystem>
#include <string>
#include <unistd.h>

inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("rocking_" + std::to_string(::getpid()) + "_" + name);
}
