// rocking.modal: linearised modal analysis of the chimney (MODEL.md 8, the
// paper's Fig. 3) and the reference forces that normalise its response
// (MODEL.md 7, after Acikgoz and DeJong 2012).
// Fixed base: K phi = w^2 M phi. Rocking phase linearised about theta = 0 in
// generalised coordinates (u, theta): mass [[M, M H], [H'M, J_p]], stiffness
// [[K, -g M1], [-g 1'M, -g H'M1 + k_theta]] (symmetric with the Lagrangian
// gravity sign, MODEL.md 9.2). A negative eigenvalue -p^2 is the rocking mode
// with frequency parameter p. k_theta = 0 (free rocking) or the devices'
// sum_k k_k (de_k/dth)^2 at rest or yielded (rocking.devices; the paper's
// edge damper: k (2B)^2 pre-yield, eps k (2B)^2 post-yield), about each
// pivot. SI units, frequencies in Hz.
module;
#include <rocking/eigen.hpp>
#include <array>
#include <vector>
export module rocking.modal;
import rocking.geometry;
import rocking.beam;
import rocking.devices;

export namespace rocking {

struct LinearisedRocking {
  Eigen::MatrixXd mass;       // (N+1) x (N+1)
  Eigen::MatrixXd stiffness;  // (N+1) x (N+1), symmetric
};
LinearisedRocking linearise_rocking(const Structure& s, const StructuralMatrices& sm,
                                    double k_theta);

// Generalised eigen-solution of a linearised rocking phase, eigenvalues
// lambda = w^2 ascending (negative: unstable, lambda = -p^2); shapes in
// (u_1..u_N, theta), mass-normalised.
struct RockingModes {
  Eigen::VectorXd lambda;
  Eigen::MatrixXd shapes;
};
RockingModes rocking_modes(const LinearisedRocking& lin);

// First-mode static push u = c phi_1 at which uplift starts with no damper:
// c H'K phi_1 = g 1'M (B1 - c phi_1) + m0 g B; M_ref = c H'K phi_1,
// V_ref = c 1'K phi_1.
struct ReferenceForces {
  double base_moment = 0;  // M_ref [N m]
  double base_shear = 0;   // V_ref [N]
};
ReferenceForces reference_forces(const Structure& s, const StructuralMatrices& sm);

// Everything `rocking modal` reports.
struct ModalSummary {
  std::vector<double> fixed_base_hz;  // all fixed-base modes
  std::vector<double> rocking_hz;     // stable modes of free rocking
  double rocking_p = 0;               // p of free rocking [rad/s] (0 if none)
  // With the devices (the lower frequency and the larger p of the two pivots;
  // a pivot no device stretches rocks freely):
  double damper_pre_yield_hz = 0;     // lowest mode, devices at rest (0: unstable about a pivot, or no device)
  double damper_post_yield_p = 0;     // p with the devices yielded (0: stable about both, or no device)
  std::array<RockingStiffness, 2> devices;  // about pivot -1, +1
  double r_eq10 = 0, J_p = 0, H_cg = 0, alpha_cg = 0;
  ReferenceForces reference;
  Modes fixed_base;                   // shapes for the mode-shape figure
  RockingModes free_rocking;
};
ModalSummary modal_analysis(const Structure& s, const std::vector<Device>& devices);

}  // namespace rocking
