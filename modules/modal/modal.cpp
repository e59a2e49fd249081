module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>
module rocking.modal;

namespace rocking {

namespace {
constexpr double two_pi = 2.0 * std::numbers::pi;

double unstable_p(const RockingModes& m) { return m.lambda[0] < 0 ? std::sqrt(-m.lambda[0]) : 0.0; }
}  // namespace

LinearisedRocking linearise_rocking(const Structure& s, const StructuralMatrices& sm,
                                    double k_theta) {
  const Eigen::Index n = node_count(s);
  const Eigen::VectorXd MH = sm.M * s.heights;
  const Eigen::VectorXd M1 = s.masses;  // M 1 for a lumped (diagonal) mass
  LinearisedRocking lin{Eigen::MatrixXd::Zero(n + 1, n + 1), Eigen::MatrixXd::Zero(n + 1, n + 1)};
  lin.mass.topLeftCorner(n, n) = sm.M;
  lin.mass.topRightCorner(n, 1) = MH;
  lin.mass.bottomLeftCorner(1, n) = MH.transpose();
  lin.mass(n, n) = pivot_inertia(s);
  lin.stiffness.topLeftCorner(n, n) = sm.K;
  lin.stiffness.topRightCorner(n, 1) = -gravity * M1;
  lin.stiffness.bottomLeftCorner(1, n) = -gravity * M1.transpose();
  lin.stiffness(n, n) = -gravity * s.heights.dot(M1) + k_theta;
  return lin;
}

RockingModes rocking_modes(const LinearisedRocking& lin) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(lin.stiffness, lin.mass);
  if (eig.info() != Eigen::Success) throw std::runtime_error("rocking eigenproblem failed");
  return {eig.eigenvalues(), eig.eigenvectors()};
}

ReferenceForces reference_forces(const Structure& s, const StructuralMatrices& sm) {
  const Eigen::VectorXd phi = sm.fixed_base.shapes.col(0);
  const Eigen::VectorXd Kphi = sm.K * phi;
  const double B = s.half_width;
  // c (H'K phi + g 1'M phi) = g B (1'M1 + m0)
  const double c = gravity * B * total_mass(s) / (s.heights.dot(Kphi) + gravity * s.masses.dot(phi));
  return {c * s.heights.dot(Kphi), c * Kphi.sum()};
}

ModalSummary modal_analysis(const Structure& s, const std::vector<Device>& devices) {
  const StructuralMatrices sm = assemble(s);
  ModalSummary out;
  for (double w : sm.fixed_base.omega) out.fixed_base_hz.push_back(w / two_pi);
  out.free_rocking = rocking_modes(linearise_rocking(s, sm, 0.0));
  for (double l : out.free_rocking.lambda)
    if (l > 0) out.rocking_hz.push_back(std::sqrt(l) / two_pi);
  out.rocking_p = unstable_p(out.free_rocking);
  for (Pivot p : pivots) out.devices[index(p)] = rocking_stiffness(devices, s.half_width, p);
  // The structure rocks about either pivot, and a pivot that no device
  // stretches rocks freely: with devices anywhere, both pivots count. At rest
  // the lower frequency of the two, none when either is unstable; yielded the
  // larger growth rate p.
  if (out.devices[0].any || out.devices[1].any) {
    bool unstable_at_rest = false;
    for (const RockingStiffness& k : out.devices) {
      const RockingModes at_rest = rocking_modes(linearise_rocking(s, sm, k.at_rest));
      if (at_rest.lambda[0] > 0) {
        const double hz = std::sqrt(at_rest.lambda[0]) / two_pi;
        out.damper_pre_yield_hz = out.damper_pre_yield_hz > 0 ? std::min(out.damper_pre_yield_hz, hz) : hz;
      } else {
        unstable_at_rest = true;
      }
      out.damper_post_yield_p =
          std::max(out.damper_post_yield_p, unstable_p(rocking_modes(linearise_rocking(s, sm, k.yielded))));
    }
    if (unstable_at_rest) out.damper_pre_yield_hz = 0;
  }
  out.r_eq10 = restitution_eq10(s);
  out.J_p = pivot_inertia(s);
  out.H_cg = centre_of_gravity_height(s);
  out.alpha_cg = slenderness(s);
  out.reference = reference_forces(s, sm);
  out.fixed_base = sm.fixed_base;
  return out;
}

}  // namespace rocking
