module;
#include <rocking/eigen.hpp>
#include <stdexcept>
module rocking.beam;

namespace rocking {

Eigen::Matrix4d element_stiffness(double EI, double L) {
  Eigen::Matrix4d k;
  k << 12, 6 * L, -12, 6 * L,
       6 * L, 4 * L * L, -6 * L, 2 * L * L,
       -12, -6 * L, 12, -6 * L,
       6 * L, 2 * L * L, -6 * L, 4 * L * L;
  return (EI / (L * L * L)) * k;
}

Eigen::MatrixXd condensed_stiffness(const Eigen::VectorXd& heights, const Eigen::VectorXd& EI) {
  const Eigen::Index n = heights.size();
  // Free DOFs after clamping node 0: u_1..u_N then phi_1..phi_N.
  // Node j (0..N) maps to u index j-1 and phi index N+j-1; node 0 is dropped.
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (Eigen::Index e = 0; e < n; ++e) {
    const double below = e == 0 ? 0.0 : heights[e - 1];
    const Eigen::Matrix4d ke = element_stiffness(EI[e], heights[e] - below);
    const Eigen::Index dof[4] = {e - 1, n + e - 1, e, n + e};  // u_e-1, phi_e-1, u_e, phi_e
    for (int a = 0; a < 4; ++a) {
      if (e == 0 && a < 2) continue;  // clamped base
      for (int b = 0; b < 4; ++b) {
        if (e == 0 && b < 2) continue;
        k(dof[a], dof[b]) += ke(a, b);
      }
    }
  }
  const auto kuu = k.topLeftCorner(n, n);
  const auto kup = k.topRightCorner(n, n);
  const auto kpp = k.bottomRightCorner(n, n);
  Eigen::MatrixXd condensed = kuu - kup * kpp.llt().solve(kup.transpose());
  return 0.5 * (condensed + condensed.transpose());  // exact symmetry
}

Modes fixed_base_modes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, M);
  if (eig.info() != Eigen::Success) throw std::runtime_error("fixed-base eigenproblem failed");
  Modes modes{eig.eigenvalues().cwiseMax(0.0).cwiseSqrt(), eig.eigenvectors()};
  for (Eigen::Index j = 0; j < modes.shapes.cols(); ++j)
    if (modes.shapes(modes.shapes.rows() - 1, j) < 0) modes.shapes.col(j) *= -1.0;
  return modes;
}

Rayleigh rayleigh_coefficients(double zeta, double w1, double w2) {
  if (w2 <= 0) return {zeta * w1, zeta / w1};
  return {2.0 * zeta * w1 * w2 / (w1 + w2), 2.0 * zeta / (w1 + w2)};
}

StructuralMatrices assemble(const Structure& s) {
  StructuralMatrices out;
  out.M = s.masses.asDiagonal();
  out.K = condensed_stiffness(s.heights, s.EI_scale * s.EI);
  out.fixed_base = fixed_base_modes(out.M, out.K);
  const auto& w = out.fixed_base.omega;
  out.rayleigh = rayleigh_coefficients(s.damping_ratio, w[0], w.size() > 1 ? w[1] : 0.0);
  out.C = out.rayleigh.a0 * out.M + out.rayleigh.a1 * out.K;
  return out;
}

}  // namespace rocking
