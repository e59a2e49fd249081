// The stiff part of a chain's equations for rosw (rocking.simulation's
// ChainStiff, docs/chain.md "Stiff steps"), held to
// - a closed form: at rest, a rigid segment rocking about its right corner
//   has the inertia sum m ((x - B)^2 + z^2) about it (chain_mass_at_rest),
//   and with every joint closed the elastic block of chain_mass_at_rest is
//   chain_at_rest's M; to 1e-12;
// - the Jacobian of the nonlinear equations: with gravity all but off (1e-6
//   m/s^2: a chain needs g > 0; its terms are below 1e-10 of the
//   stiffness's here), at rest in the
//   phases where a rigid segment rocks on a flexible shaft, central
//   differences of chain_acceleration in q and q' (step 1e-6 of the state's
//   scale, error of order 1e-12 of the entries) give -M^-1 K and -M^-1 C
//   exactly (Q = -K x - C x' + terms of second order in the motion), so T is
//   that Jacobian to 1e-6 of its largest entry;
// - its linear solve: x = ChainStiff::solve(b) satisfies (I - g T) x = b,
//   with T from those differences, to 1e-6 of |b| for g from 1e-5 to 1 s,
//   leaving every other component of the state as b has it.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <vector>

#include "chain_segment.hpp"
#include "close.hpp"
import rocking.chain;
import rocking.geometry;
import rocking.dynamics;
import rocking.simulation;

using namespace rocking;
using Vec = Eigen::VectorXd;
using Mat = Eigen::MatrixXd;

namespace {

ChainSegment segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses,
                     bool rigid = true, std::vector<double> EI = {}) {
  return chain_segment<ChainSegment>(h, B, m0, std::move(heights), std::move(masses), rigid, std::move(EI));
}

// A flexible shaft (nodes at 2, 4, 6 m) under a rigid segment from its top node.
ChainData shaft(double g) {
  ChainData d;
  d.g = g;
  d.rayleigh = {0.3, 0.002};
  d.segments.push_back(segment(0.0, 1.0, 3000.0, {2.0, 4.0, 6.0}, {2000.0, 1500.0, 1000.0}, false, {4e9, 3e9, 2e9}));
  d.segments.push_back(segment(6.0, 0.6, 400.0, {7.0, 8.0}, {600.0, 300.0}));
  return d;
}

// Central differences of q'' = chain_acceleration in (q, q') at rest: the
// rows of q'' (n x 2n).
Mat jacobian_at_rest(const Chain& c, ChainPhases phases, double step) {
  const int n = c.size;
  ChainWorkspace w = make_workspace(c);
  Mat J(n, 2 * n);
  Vec qdd_plus(n), qdd_minus(n);
  for (int k = 0; k < 2 * n; ++k) {
    Vec q = Vec::Zero(n), qd = Vec::Zero(n);
    (k < n ? q[k] : qd[k - n]) = step;
    chain_acceleration(c, phases, GroundAcceleration{0.0}, q, qd, qdd_plus, w);
    (k < n ? q[k] : qd[k - n]) = -step;
    chain_acceleration(c, phases, GroundAcceleration{0.0}, q, qd, qdd_minus, w);
    J.col(k) = (qdd_plus - qdd_minus) / (2 * step);
  }
  return J;
}

}  // namespace

TEST_CASE("at rest a rocking rigid segment's inertia is about its corner, and with every joint closed the elastic block is chain_at_rest's M, to 1e-12") {
  const Chain c = make_chain(shaft(gravity));
  const std::vector<Phase> top_rocks{Phase::full_contact(), Phase::rocking(Pivot::right)};
  const Mat M = chain_mass_at_rest(c, top_rocks);
  // The top segment: its slab (400 kg at 0) and nodes (600 kg at 1 m, 300 kg
  // at 2 m above it), about the corner at x = +0.6 m.
  double Jp = 0;
  for (const auto& [z, m] : std::vector<std::pair<double, double>>{{0.0, 400.0}, {1.0, 600.0}, {2.0, 300.0}})
    Jp += m * (0.6 * 0.6 + z * z);
  CHECK(M(1, 1) == close_to(Jp, 1e-12));
  const std::vector<Phase> closed(2);
  const Mat M0 = chain_mass_at_rest(c, closed);
  const ChainAtRest lin = chain_at_rest(c);
  const int J = c.joints, ne = c.size - J;
  const double tol = 1e-12 * lin.M.cwiseAbs().maxCoeff();
  for (int k = 0; k < ne; ++k)
    for (int l = 0; l < ne; ++l) CHECK(M0(J + k, J + l) == within(lin.M(k, l), tol));
}

TEST_CASE("with gravity all but off, the stiff part of a rigid segment rocking on a flexible shaft is the equations' Jacobian at rest, and its solve inverts I - g T, to 1e-6") {
  const Chain c = make_chain(shaft(1e-6));
  const int n = c.size;
  for (Pivot s : {Pivot::left, Pivot::right}) {
    const std::vector<Phase> phases{Phase::full_contact(), Phase::rocking(s)};
    const Mat J = jacobian_at_rest(c, phases, 1e-6);
    // T on the state (q, q', two more components T leaves alone).
    const int size = 2 * n + 2;
    Mat T = Mat::Zero(size, size);
    for (int k = 0; k < n; ++k)
      if (k != 0) T(k, n + k) = 1.0;  // q' = v, but for the closed base's theta
    T.block(n, 0, n, 2 * n) = J;
    // What ChainStiff's T is: q' = v, v' = -M^-1 (K x + C v) on the free
    // coordinates, from chain_mass_at_rest and the segments' K and C.
    const Mat M = chain_mass_at_rest(c, phases);
    std::vector<int> free{1};
    for (int k = c.joints; k < n; ++k) free.push_back(k);
    const auto nf = static_cast<Eigen::Index>(free.size());
    Mat Mf(nf, nf), Kf = Mat::Zero(nf, nf), Cf = Mat::Zero(nf, nf);
    const int o = c.elastic_offset[0];
    for (Eigen::Index a = 0; a < nf; ++a)
      for (Eigen::Index b = 0; b < nf; ++b) {
        Mf(a, b) = M(free[a], free[b]);
        const int ka = free[a] - o, kb = free[b] - o;
        if (ka >= 0 && kb >= 0) {
          Kf(a, b) = c.K[0](ka, kb);
          Cf(a, b) = c.C[0](ka, kb);
        }
      }
    const Mat stiff_q = -Mf.ldlt().solve(Kf), stiff_v = -Mf.ldlt().solve(Cf);
    const double scale = J.cwiseAbs().maxCoeff();
    for (Eigen::Index a = 0; a < nf; ++a)
      for (Eigen::Index b = 0; b < nf; ++b) {
        CHECK(J(free[a], free[b]) == within(stiff_q(a, b), 1e-6 * scale));
        CHECK(J(free[a], n + free[b]) == within(stiff_v(a, b), 1e-6 * scale));
      }
    ChainStiff stiff(c);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (double g : {1e-5, 1e-3, 1e-1, 1.0}) {
      Vec b(size), x(size);
      for (Eigen::Index i = 0; i < size; ++i) b[i] = u(rng);
      b[0] = b[n] = 0.0;  // the closed base: theta_0 and its rate stay 0
      stiff.solve(phases, g, b, x);
      const Vec residual = (Mat::Identity(size, size) - g * T) * x - b;
      CHECK(residual.norm() == within(0.0, 1e-6 * b.norm()));
      CHECK(x[2 * n] == b[2 * n]);
      CHECK(x[2 * n + 1] == b[2 * n + 1]);
    }
  }
}
