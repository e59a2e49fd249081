// rocking.chain's linearisation about rest with every joint closed
// (chain_at_rest, docs/chain.md "Every joint closed"): M x'' + C x' + K x = f a_g
// on the elastic coordinates. Held to
// - closed forms: a flexible shaft under two closed rigid segments carries
//   them as one rigid body on its top face, of mass m_a, first moment S and
//   second moment I about the face, so that M(phi, phi) = I, M(u_top, phi) = S,
//   M(u_top, u_top) = m_top + m_a, f = -(the mass each coordinate carries
//   sideways: m_i, m_top + m_a on u_top, S on phi), and gravity's stiffness on
//   phi is -g S (P-delta: the body tips over its face), K being otherwise the
//   shaft's own; to 1e-12 (K's of the stiffness it changes);
// - the nonlinear equations (chain_acceleration with every joint closed): on
//   random states of size eps (displacements eps m, rotations eps rad, rates and
//   ground accelerations eps per s or s^2 of the shaft's first period), the
//   linear q'' differs from the nonlinear one by terms of second order, which
//   are at most 10 eps of it (the neglected terms are those of M, gravity's
//   moment and the velocity terms, each a factor phi or a rate squared over an
//   acceleration beyond the first order), and falls with eps^2: ten times
//   smaller eps, at least 30 times smaller difference.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "chain_segment.hpp"
#include "close.hpp"
import rocking.chain;
import rocking.geometry;
import rocking.dynamics;

using namespace rocking;
using Vec = Eigen::VectorXd;

namespace {

ChainSegment segment(double h, double B, double m0, std::vector<double> heights, std::vector<double> masses,
                     bool rigid = true, std::vector<double> EI = {}) {
  return chain_segment<ChainSegment>(h, B, m0, std::move(heights), std::move(masses), rigid, std::move(EI));
}

// A flexible shaft (nodes at 2, 4, 6 m) under two rigid segments from its top node.
ChainData shaft() {
  ChainData d;
  d.rayleigh = {0.3, 0.002};
  d.segments.push_back(segment(0.0, 1.0, 3000.0, {2.0, 4.0, 6.0}, {2000.0, 1500.0, 1000.0}, false, {4e9, 3e9, 2e9}));
  d.segments.push_back(segment(6.0, 0.6, 400.0, {7.0, 8.0}, {600.0, 300.0}));
  d.segments.push_back(segment(8.0, 0.3, 0.0, {8.5, 9.0}, {100.0, 80.0}));
  return d;
}

}  // namespace

TEST_CASE("with every joint closed, the chain linearised about rest carries the segments above a face as one rigid body: its mass, moments and P-delta to 1e-12") {
  const Chain c = make_chain(shaft());
  const ChainAtRest lin = chain_at_rest(c);
  const int J = c.joints;
  REQUIRE(lin.M.rows() == c.size - J);
  REQUIRE(lin.M.rows() == 4);  // u_1, u_2, u_3, phi
  const int u3 = c.elastic_offset[0] + 2 - J, phi = c.rotation_index[0] - J;
  double m_a = 0, S = 0, I = 0;  // everything above the face at 6 m
  for (const auto& [z, m] : std::vector<std::pair<double, double>>{
           {6.0, 400.0}, {7.0, 600.0}, {8.0, 300.0}, {8.0, 0.0}, {8.5, 100.0}, {9.0, 80.0}}) {
    m_a += m;
    S += m * (z - 6.0);
    I += m * (z - 6.0) * (z - 6.0);
  }
  const double tol = 1e-12;
  const Vec node_mass = (Vec(3) << 2000.0, 1500.0, 1000.0 + m_a).finished();
  for (int k = 0; k < 3; ++k) {
    CHECK(lin.M(k, k) == close_to(node_mass[k], tol));
    CHECK(lin.f[k] == close_to(-node_mass[k], tol));
    for (int l = 0; l < 3; ++l)
      if (l != k) CHECK(lin.M(k, l) == within(0.0, tol * m_a));
  }
  CHECK(lin.M(u3, phi) == close_to(S, tol));
  CHECK(lin.M(phi, u3) == close_to(S, tol));
  CHECK(lin.M(phi, phi) == close_to(I, tol));
  CHECK(lin.f[phi] == close_to(-S, tol));
  // K: the shaft's own, less g S on phi (to 1e-12 of the stiffness it lowers)
  CHECK(lin.K(phi, phi) == close_to(c.K[0](phi, phi) - c.data.g * S, tol));
  Eigen::MatrixXd gravity = lin.K - c.K[0];
  gravity(phi, phi) = 0.0;
  CHECK(gravity.cwiseAbs().maxCoeff() == within(0.0, tol * c.K[0].cwiseAbs().maxCoeff()));
  CHECK((lin.C - c.C[0]).cwiseAbs().maxCoeff() == within(0.0, tol * c.C[0].cwiseAbs().maxCoeff()));
}

TEST_CASE("with every joint closed, the linearised chain's accelerations differ from the nonlinear chain's by second-order terms only") {
  const Chain c = make_chain(shaft());
  const ChainAtRest lin = chain_at_rest(c);
  ChainWorkspace w = make_workspace(c);
  const int J = c.joints, n = c.size, ne = n - J;
  const std::vector<Phase> closed(J);
  // Scales: the shaft's first period T (of K and M), displacements of the
  // shaft's height L per unit eps.
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(lin.K, lin.M);
  const double omega = std::sqrt(modes.eigenvalues().minCoeff()), L = 6.0;
  std::mt19937 rng(54);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const Eigen::LLT<Eigen::MatrixXd> llt(lin.M);
  for (int trial = 0; trial < 8; ++trial) {
    Vec x(ne), v(ne);
    for (int k = 0; k < ne; ++k) {
      const bool rotation = k == c.rotation_index[0] - J;
      x[k] = (rotation ? 1.0 : L) * U(rng);
      v[k] = omega * (rotation ? 1.0 : L) * U(rng);
    }
    const double ag = omega * omega * L * U(rng);
    auto difference = [&](double eps) {
      Vec q = Vec::Zero(n), qd = Vec::Zero(n), acc(n);
      q.tail(ne) = eps * x;
      qd.tail(ne) = eps * v;
      chain_acceleration(c, closed, GroundAcceleration{eps * ag}, q, qd, acc, w);
      const Vec linear = llt.solve(lin.f * eps * ag - lin.C * eps * v - lin.K * eps * x);
      return (acc.tail(ne) - linear).norm() / linear.norm();
    };
    const double coarse = difference(1e-3), fine = difference(1e-4);
    CAPTURE(trial);
    CAPTURE(coarse);
    CAPTURE(fine);
    CHECK(coarse <= 10 * 1e-3);
    CHECK(fine <= 10 * 1e-4);
    CHECK(fine <= coarse / 30);
  }
}
