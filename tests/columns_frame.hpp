// A structure on rocking columns for the tests of devices on columns
// (MODEL.md 16 with 11): a rigid deck on three uniform rigid columns, its
// devices and the rest of the scene given as TOML text.
#pragma once
#include <fmt/format.h>

#include <string>

namespace columns_frame {

// A rigid deck (a cap beam and one mass 2 m above it) on three columns 0.5 m
// wide, 4 m tall, 6 m apart, with the devices given.
constexpr double b = 0.25, h = 2.0, mc = 2000.0, beam = 6000.0, deck = 7000.0, spacing = 6.0;
constexpr int n = 3;
inline std::string frame(const std::string& devices, const std::string& more) {
  return fmt::format(R"(
[structure]
rigid = true
half_width = 0.25
heights = [2.0]
masses = [{}]
base_mass = {}

[columns]
count = {}
half_width = {}
half_height = {}
mass = {}
spacing = {}

[contact]
restitution = "momentum"
{}
{})",
                     deck, beam, n, b, h, mc, spacing, devices, more);
}

}  // namespace columns_frame
