// Scenes of two rigid blocks, one standing on the other (MODEL.md 15), for
// the tests of structures with joints.
#pragma once
#include <fmt/format.h>

#include <string>

// Two rigid blocks with their masses on the centre line: a lower one
// (half-width B0, two nodes of m_lower each at 0.25 and 0.75 m, a 1 kg cap at
// 1 m, the joint's face) and an upper one standing on node 3 (half-width B1,
// a 10 kg slab at 1 m, three 30 kg nodes at 1 + height (1/6, 1/2, 5/6)).
inline std::string two_blocks(double B0, double m_lower, double B1, double height, const std::string& more = "") {
  return fmt::format(R"(
[structure]
rigid = true
half_width = {}
heights = [0.25, 0.75, 1.0, {}, {}, {}]
masses = [{}, {}, 1.0, 30.0, 30.0, 30.0]
base_mass = 10.0

[contact]
restitution = "momentum"

[[joint]]
node = 3
half_width = {}
base_mass = 10.0
{}
)",
                     B0, 1 + height / 6, 1 + height / 2, 1 + 5 * height / 6, m_lower, m_lower, B1, more);
}

// No ground motion for `duration` seconds.
inline std::string still(double duration) {
  return fmt::format("\n[excitation]\nkind = \"none\"\nduration = {}\n", duration);
}
