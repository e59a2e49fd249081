// rocking.beam: condensation, mass, modes and damping against closed forms of
// Euler-Bernoulli cantilevers (Timoshenko & Gere; Chopra, Dynamics of Structures).
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <cmath>
#include <initializer_list>
#include <numbers>
import rocking.geometry;
import rocking.beam;

using namespace rocking;

namespace {
// A uniform cantilever of length L cut into n equal elements.
Eigen::VectorXd even_heights(int n, double L) {
  return Eigen::VectorXd::LinSpaced(n, L / n, L);
}

Structure chimney() {
  Structure s;
  s.half_width = 3.3;
  s.heights = Eigen::Vector4d(10.4, 17.95, 25.5, 33.05);
  s.masses = Eigen::Vector4d(78.6e3, 60.8e3, 53.8e3, 31.0e3);
  s.base_mass = 62.4e3;
  s.EI = 20e9 * Eigen::Vector4d(9.84, 4.03, 3.45, 3.01);
  s.damping_ratio = 0.035;
  return s;
}
}  // namespace

TEST_CASE("condensed stiffness of a uniform cantilever gives the exact flexibility x^2 (3L - x) / 6EI") {
  const double L = 12.0, EI = 3.0e8;
  for (int n : {1, 3, 8}) {
    const Eigen::VectorXd h = even_heights(n, L);
    const Eigen::MatrixXd F = condensed_stiffness(h, Eigen::VectorXd::Constant(n, EI)).inverse();
    // Tip: L^3 / 3EI exactly (cubic elements are exact for end loads), to the
    // round-off of inverting a stiffness whose condition grows as n^4: 1e-10.
    CHECK(F(n - 1, n - 1) == close_to(L * L * L / (3 * EI), 1e-10));
    for (int i = 0; i < n; ++i) {
      const double x = h[i];
      CHECK(F(i, n - 1) == close_to(x * x * (3 * L - x) / (6 * EI), 1e-10));
    }
  }
}

TEST_CASE("lumped-mass cantilever converges to 1.875^2 sqrt(EI / (m L^4)) / 2pi") {
  const double L = 20.0, EI = 5.0e9, mbar = 2000.0;  // mass per length [kg/m]
  const double beta_L = 1.8751040687119611;
  const double exact_hz = beta_L * beta_L * std::sqrt(EI / (mbar * std::pow(L, 4))) / (2 * std::numbers::pi);
  double previous_error = 1.0;
  for (int n : {5, 20, 80}) {
    Structure s;
    s.half_width = 1.0;
    s.heights = even_heights(n, L);
    s.masses = Eigen::VectorXd::Constant(n, mbar * L / n);
    s.masses[n - 1] *= 0.5;  // the tip node carries half an element
    s.EI = Eigen::VectorXd::Constant(n, EI);
    const double f1 = assemble(s).fixed_base.omega[0] / (2 * std::numbers::pi);
    const double error = std::abs(f1 / exact_hz - 1.0);
    CHECK(error < previous_error);
    previous_error = error;
  }
  CHECK(previous_error < 1e-3);  // 80 lumped masses: within 0.1 %
}

TEST_CASE("the chimney's stiffness is symmetric positive definite") {
  const Eigen::MatrixXd K = assemble(chimney()).K;
  CHECK((K - K.transpose()).norm() == 0.0);
  Eigen::LLT<Eigen::MatrixXd> llt(K);
  CHECK(llt.info() == Eigen::Success);
}

TEST_CASE("fixed-base modes are M-orthonormal and diagonalise K") {
  const StructuralMatrices sm = assemble(chimney());
  const Eigen::MatrixXd& P = sm.fixed_base.shapes;
  const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(4, 4);
  CHECK((P.transpose() * sm.M * P - identity).norm() < 1e-12);
  const Eigen::MatrixXd w2 = sm.fixed_base.omega.array().square().matrix().asDiagonal();
  CHECK((P.transpose() * sm.K * P - w2).norm() < 1e-9 * w2.norm());
}

TEST_CASE("Rayleigh damping gives the target ratio on both target modes") {
  const StructuralMatrices sm = assemble(chimney());
  for (int j : {0, 1}) {
    const Eigen::VectorXd phi = sm.fixed_base.shapes.col(j);
    const double zeta = phi.dot(sm.C * phi) / (2.0 * sm.fixed_base.omega[j]);
    CHECK(zeta == close_to(0.035, 1e-12));
  }
  // and more than the target on the third mode (Rayleigh grows with frequency)
  const Eigen::VectorXd phi3 = sm.fixed_base.shapes.col(2);
  CHECK(phi3.dot(sm.C * phi3) / (2.0 * sm.fixed_base.omega[2]) > 0.035);
}

TEST_CASE("EI_scale scales every frequency by its square root") {
  Structure s = chimney();
  const double f = assemble(s).fixed_base.omega[0];
  s.EI_scale = 0.25;
  CHECK(assemble(s).fixed_base.omega[0] == close_to(0.5 * f, 1e-12));
}
