// The independent reference's chain (tests/chain_reference.hpp, rigid
// segments of lumped masses) built from a model's chain data: each
// segment's joint height, half-width, slab mass and masses, and g. Devices
// and tendons are the caller's to add, in the reference's own form.
#pragma once
#include <rocking/eigen.hpp>
#include "chain_reference.hpp"
import rocking.chain;

inline chainref::Chain reference_from(const rocking::ChainData& d) {
  chainref::Chain ref;
  for (const rocking::ChainSegment& sg : d.segments) {
    chainref::Segment s;
    s.h = sg.base_height;
    s.B = sg.half_width;
    s.m0 = sg.base_mass;
    for (Eigen::Index i = 0; i < sg.masses.size(); ++i) s.masses.emplace_back(sg.heights[i], sg.masses[i]);
    ref.seg.push_back(s);
  }
  ref.g = d.g;
  return ref;
}
