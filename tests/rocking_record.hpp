// A two-column record (t [s], a [g]) of `seconds` that makes the chimney
// rock: a 1.7 s sine of 0.25 g under a half-sine envelope, every 0.01 s.
#pragma once
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

inline std::string rocking_record(const std::filesystem::path& file, double seconds) {
  std::ofstream out(file);
  for (int i = 0; 0.01 * i <= seconds + 1e-9; ++i) {
    const double t = 0.01 * i;
    out << t << ' ' << 0.25 * std::sin(2 * std::numbers::pi * t / 1.7) * std::sin(std::numbers::pi * t / seconds) << '\n';
  }
  return file.string();
}
