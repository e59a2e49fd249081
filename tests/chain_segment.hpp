// A segment of a chain (rocking.chain's ChainSegment, MODEL.md 15) from
// plain numbers: its slab's height, half-width and mass, its nodes' heights
// and masses, and whether it is rigid (else its elements' EI). A template on
// the segment type because headers come before module imports (TOOLCHAIN.md
// pitfall 2).
#pragma once
#include <rocking/eigen.hpp>
#include <vector>

template <class Segment>
Segment chain_segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses,
                      bool rigid = true, std::vector<double> EI = {}) {
  Segment s;
  s.base_height = h;
  s.half_width = B;
  s.base_mass = m0;
  s.heights = Eigen::Map<Eigen::VectorXd>(heights.data(), static_cast<Eigen::Index>(heights.size()));
  s.masses = Eigen::Map<Eigen::VectorXd>(masses.data(), static_cast<Eigen::Index>(masses.size()));
  s.rigid = rigid;
  if (!rigid) s.EI = Eigen::Map<Eigen::VectorXd>(EI.data(), static_cast<Eigen::Index>(EI.size()));
  return s;
}
