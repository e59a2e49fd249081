// rocking.simulation:peaks, a partition the drivers share (the one-joint
// structure's in simulation.cpp, the chain's in chain_run.cpp): the running
// absolute peaks of the peak quantities (rocking.quantities) over the
// samples of the continuous response, refined at local extrema.
module;
#include <array>
#include <cstddef>
module rocking.simulation:peaks;
import rocking.quantities;

namespace rocking {

// The peak quantities a driver's structure can have: peak_quantities without
// those that need `absent` (the one-joint structure's driver has no columns:
// its tracker spends no lanes on them, and their peaks stay 0).
template <Needs absent>
constexpr auto peak_quantities_without() {
  constexpr std::size_t n = [] {
    std::size_t k = 0;
    for (Quantity q : peak_quantities) k += info(q).needs != absent ? 1 : 0;
    return k;
  }();
  std::array<Quantity, n> out{};
  std::size_t k = 0;
  for (Quantity q : peak_quantities)
    if (info(q).needs != absent) out[k++] = q;
  return out;
}

// Absolute peaks over samples of the continuous response; an interior local
// maximum of |q| is refined by the parabola through its neighbours. It runs
// at every sample of every step, so the quantities go four at a time through
// vector registers (the GCC/Clang vector extension), and the parabola, with
// its divisions, is computed only when some quantity's middle sample is a
// local maximum: every lane is treated alike, the condition selecting rather
// than branching. It tracks the quantities `tracked_list`; the others' peaks are 0.
template <auto tracked_list = peak_quantities>
class PeakTracker {
  using Lanes = double __attribute__((vector_size(4 * sizeof(double))));
  using Mask = long __attribute__((vector_size(4 * sizeof(long))));  // a comparison's lanes: -1 or 0
  static constexpr std::size_t tracked = tracked_list.size();
  static constexpr std::size_t lanes = 4, groups = (tracked + lanes - 1) / lanes;
  using Group = std::array<Lanes, groups>;

 public:
  void add(double t, const std::array<double, quantity_count>& q) {
    Group a{};
    Mask local_max{};  // some lane's middle sample above one neighbour and below neither
    for (std::size_t g = 0; g < groups; ++g) {
      for (std::size_t j = 0; j < lanes && g * lanes + j < tracked; ++j) a[g][j] = q[index(tracked_list[g * lanes + j])];
      a[g] = __builtin_elementwise_abs(a[g]);
      const Lanes v1 = v1_[g], v2 = v2_[g];
      local_max |= (v1 >= v2) & (v1 >= a[g]) & ((v1 > v2) | (v1 > a[g]));
    }
    if (count_ >= 2 && t1_ > t2_ && t > t1_ && __builtin_reduce_or(local_max) != 0) refine(t, a);
    for (std::size_t g = 0; g < groups; ++g) {
      peak_[g] = peak_[g] < a[g] ? a[g] : peak_[g];
      v2_[g] = v1_[g];
      v1_[g] = a[g];
    }
    t2_ = t1_;
    t1_ = t;
    ++count_;
  }
  // Velocities (and so the shape of the response) jump at an event.
  void break_continuity() { count_ = 0; }
  std::array<double, quantity_count> peaks() const {
    std::array<double, quantity_count> out{};
    for (std::size_t i = 0; i < tracked; ++i) out[index(tracked_list[i])] = peak_[i / lanes][i % lanes];
    return out;
  }

 private:
  // The vertex of the parabola through the last two samples and a (at t),
  // where it lies between them and is a maximum above a. A lane whose middle
  // sample is no local maximum has c >= 0 and is rejected.
  void refine(double t, const Group& a) {
    const double i21 = 1.0 / (t1_ - t2_), i10 = 1.0 / (t - t1_), i20 = 1.0 / (t - t2_);
    const double mid = 0.5 * (t2_ + t1_), t1 = t1_, t2 = t2_;
    for (std::size_t g = 0; g < groups; ++g) {
      const Lanes v1 = v1_[g], v2 = v2_[g];
      const Lanes f21 = (v1 - v2) * i21, c = ((a[g] - v1) * i10 - f21) * i20;
      const Lanes x = mid - 0.5 * f21 / c;  // the vertex (inf or NaN when c = 0: rejected)
      const Lanes top = v2 + f21 * (x - t2) + c * (x - t2) * (x - t1);
      const Mask vertex = (v1 >= v2) & (v1 >= a[g]) & (c < 0) & (x >= t2) & (x <= t) & (a[g] < top);
      peak_[g] = (vertex & (peak_[g] < top)) ? top : peak_[g];
    }
  }

  Group peak_{}, v1_{}, v2_{};
  double t1_ = 0, t2_ = 0;
  long count_ = 0;
};

}  // namespace rocking
