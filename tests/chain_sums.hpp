// Mass, first moment (sum m z) and pivot inertia about joint j's corner of
// everything above joint j of a chain (rocking.chain's ChainData): the
// closed forms' ingredients (MODEL.md 15). A template on the data type
// because headers come before module imports (TOOLCHAIN.md pitfall 2).
#pragma once
#include <cmath>
#include <cstddef>

struct SegmentSums {
  double J = 0, mass = 0, first = 0;
};

template <class Data>
SegmentSums sums_above(const Data& d, int j) {
  SegmentSums out;
  const auto& base = d.segments[static_cast<std::size_t>(j)];
  const double h = base.base_height, B = base.half_width;
  for (std::size_t k = static_cast<std::size_t>(j); k < d.segments.size(); ++k) {
    const auto& s = d.segments[k];
    out.mass += s.base_mass + s.masses.sum();
    out.first += s.base_mass * (s.base_height - h) + s.masses.dot((s.heights.array() - h).matrix());
    out.J += s.base_mass * (std::pow(s.base_height - h, 2) + B * B) +
             (s.masses.array() * ((s.heights.array() - h).square() + B * B)).sum();
  }
  return out;
}
