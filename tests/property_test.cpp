// Property test (issue 21): random valid scenes within these bounds (1 to 20
// nodes over 10 to 60 m, 1 to 100 t a node, I 0.1 to 10 m^4, E 10 to 50 GPa,
// damping 0 to 10 %, widths 8 to 40 % of the height, dampers of 0.1 to 100 MN/m
// or none, restitution by Eq. 10 or 0.5 to 1, one-sine and Ricker pulses of
// 0.05 to 1.5 g and 0.1 to 3 s), from a fixed seed, each run to its end: no NaN in any output, the
// energy balance closing to its tolerance, and the same peaks whether the
// scenes run on one thread or two.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <cmath>
#include <random>
#include <string>
#include <vector>
import rocking.study;

using namespace rocking;

namespace {

std::string list(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? "," : "") + std::to_string(v[i]);
  return out + "]";
}

// The --set overrides of one random scene on the built-in chimney.
std::vector<std::string> random_scene(std::mt19937& rng) {
  auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
  auto log_uniform = [&](double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); };
  const int n = std::uniform_int_distribution<int>(1, 20)(rng);
  const double height = log_uniform(10, 60), width = height * uniform(0.08, 0.4);
  std::vector<double> heights, masses, moments;
  for (int i = 1; i <= n; ++i) {
    heights.push_back(height * i / n);
    masses.push_back(log_uniform(1e3, 1e5));
    moments.push_back(log_uniform(0.1, 10));
  }
  std::vector<std::string> set = {
      "structure.heights=" + list(heights),
      "structure.masses=" + list(masses),
      "structure.second_moments=" + list(moments),
      "structure.half_width=" + std::to_string(width / 2),
      "structure.base_mass=" + std::to_string(log_uniform(1e1, 1e5)),
      "structure.youngs_modulus=" + std::to_string(log_uniform(1e10, 5e10)),
      "structure.damping_ratio=" + std::to_string(uniform(0, 0.1)),
      "excitation.pulse=" + std::string(uniform(0, 1) < 0.5 ? "one-sine" : "ricker"),
      "excitation.amplitude_g=" + std::to_string(uniform(0.05, 1.5)),
      "excitation.period=" + std::to_string(log_uniform(0.1, 3)),
      "excitation.duration=4",
  };
  set.push_back(uniform(0, 1) < 0.5 ? "contact.restitution=eq10"
                                    : "contact.restitution=" + std::to_string(uniform(0.5, 1.0)));
  if (uniform(0, 1) < 0.3) {
    set.push_back("damper.enabled=false");
  } else {
    set.push_back("damper.stiffness=" + std::to_string(log_uniform(1e5, 1e8)));
    set.push_back("damper.post_yield_ratio=" + std::to_string(uniform(0, 0.3)));
    set.push_back("damper.theta_y=" + std::to_string(log_uniform(1e-4, 1e-2)));
  }
  return set;
}

struct Outcome3 {
  RunResult run;
  std::string scene;
};

}  // namespace

TEST_CASE("random valid scenes run to their end: no NaN, the energy balance closes, one thread or two alike") {
  std::mt19937 rng(20261123);
  constexpr std::size_t scenes = 24;
  std::vector<std::vector<std::string>> sets;
  for (std::size_t k = 0; k < scenes; ++k) sets.push_back(random_scene(rng));
  RunOptions o;
  o.tolerances.rtol = 1e-8;
  o.tolerances.atol = 1e-11;
  auto work = [&](std::size_t k) {
    const Scene scene = load_default_scene(sets[k]);
    return simulate(make_contact_model(scene, true), default_ground_motion(scene), o);
  };
  std::vector<RunResult> one, two;
  parallel_ordered<RunResult>(scenes, 1, work, [&](std::size_t, const RunResult& r) { one.push_back(r); });
  parallel_ordered<RunResult>(scenes, 2, work, [&](std::size_t, const RunResult& r) { two.push_back(r); });
  REQUIRE(one.size() == scenes);
  int rocked = 0;
  for (std::size_t k = 0; k < scenes; ++k) {
    CAPTURE(k);
    const RunResult& r = one[k];
    INFO(sets[k][0] << " " << sets[k][8] << " " << sets[k][9] << ": " << r.failure);
    CHECK(r.outcome != Outcome::failed);
    for (double p : r.peaks) CHECK(std::isfinite(p));
    const EnergyBalance& e = r.energy;
    if (r.outcome == Outcome::completed) {  // an overturned run ends in the middle of a fall
      const double scale = std::max({e.ground, std::abs(e.initial), std::abs(e.final), 1e-9});
      CHECK(std::abs(e.residual()) <= 1e-5 * scale);
    }
    CHECK(two[k].peaks == r.peaks);  // deterministic, whichever thread ran it
    CHECK(two[k].counts.impacts == r.counts.impacts);
    rocked += r.counts.uplifts > 0;
  }
  CHECK(rocked >= 6);  // the draw covers rocking, not only elastic response
}
