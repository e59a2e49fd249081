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

TEST_CASE("scene values at the edges of their ranges run soundly: finite peaks, the energy balance closing, or a run that says why it stopped") {
  // Each corner of what the scene reader accepts, on the built-in chimney
  // under its pulse for 2 s: masses and lengths at their bounds, plates from
  // vanishing to a hundred times thicker, a yield rotation near pi/2, devices
  // at their largest values, the loosest tolerances.
  const std::vector<std::vector<std::string>> corners = {
      {"structure.masses=[0.001,0.001,0.001,0.001]", "structure.base_mass=0.001"},
      {"structure.masses=[1e12,1e12,1e12,1e12]"},
      {"structure.half_width=0.05"},  // slenderness 300 (a 1 mm base takes millions of steps to overturn)
      {"structure.heights=[0.001,0.002,0.003,0.004]", "structure.half_width=0.001"},
      {"structure.youngs_modulus=1000"},
      {"damper.thickness=0.001"},
      {"damper.thickness=100"},
      {"damper.theta_y=1.57"},
      {"damper.stiffness=1e13"},
      {"device+={name=\"t\", kind=\"elastic\", at=0, kinematics=\"vertical\", free_length=33, P0=1e10, k=1e13}"},
      {"device+={name=\"v\", kind=\"viscous\", at=\"edges\", c=1e12, a=3}"},
      {"device+={name=\"f\", kind=\"friction\", at=\"edges\", F_s=1e10, v_r=10}"},
      {"device+={name=\"p\", kind=\"bouc-wen\", at=\"edges\", k=1e13, eps=1, d_y=10, alpha=100, beta=100, n=50}"},
      {"excitation.scale=250"},  // 87.5 g: the largest scale under the 100 g bound
  };
  for (const std::vector<std::string>& corner : corners) {
    CAPTURE(corner.front());
    const Scene scene = load_default_scene(corner);
    RunOptions o;
    o.duration = 2;
    o.tolerances.rtol = 0.1;  // the loosest rtol, and the largest atol
    o.tolerances.atol = 1e-3;
    for (double rtol : {0.1, 1e-6}) {
      o.tolerances.rtol = rtol;
      o.tolerances.atol = rtol == 0.1 ? 1e-3 : 1e-9;
      const RunResult r = simulate(make_contact_model(scene, true), default_ground_motion(scene), o);
      if (r.outcome == Outcome::failed) {  // allowed only as a run that says where and why it stopped
        CHECK_MESSAGE(r.failure.find("t = ") != std::string::npos, r.failure);
        continue;
      }
      for (double p : r.peaks) CHECK(!std::isnan(p));
      CHECK(r.final_state.allFinite());
      const EnergyBalance& e = r.energy;
      if (rtol == 1e-6 && r.outcome == Outcome::completed) {
        // The accumulators are integrated to atol in joules too: a structure
        // whose energies are of that order (millimetres tall) closes to it.
        const double scale = std::max({e.ground, std::abs(e.initial), std::abs(e.final), 1e-9});
        CHECK_MESSAGE(std::abs(e.residual()) <= 1e-3 * scale + 100 * o.tolerances.atol,
                      "residual " << e.residual() << " of " << scale);
      }
    }
  }
}
