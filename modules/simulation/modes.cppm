// rocking.simulation:modes, a partition the drivers share (simulation.cpp's
// and columns_run.cpp's exact steps in full contact): the shortest period of
// the fixed-base modes that oscillate (MODEL.md 8's modes with the Rayleigh
// damping of MODEL.md 1), which sets how densely guards and peaks are sampled.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <numbers>
module rocking.simulation:modes;
import rocking.contact;

namespace rocking {

// The shortest period among the fixed-base modes that oscillate, those with
// Rayleigh damping ratio a0 / (2 omega) + a1 omega / 2 below 1 [s]. An
// overdamped mode (omega above about 2 / a1: many of a finely meshed
// structure's) only relaxes and turns nothing inside its period; the modes
// that oscillate set how densely guards and peaks are sampled.
inline double shortest_period(const ContactModel& m) {
  const Rayleigh& ray = m.body.matrices.rayleigh;
  const Eigen::VectorXd& omega = m.body.matrices.fixed_base.omega;
  double fastest = 0;
  for (double w : omega)
    if (0.5 * (ray.a0 / w + ray.a1 * w) < 1.0) fastest = std::max(fastest, w);
  return 2 * std::numbers::pi / (fastest > 0 ? fastest : omega.maxCoeff());
}

}  // namespace rocking
