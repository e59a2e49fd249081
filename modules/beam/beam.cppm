// rocking.beam: the elastic superstructure in the frame of the foundation beam
// (MODEL.md 1). Euler-Bernoulli elements (4x4 stiffness in (u, phi) per node,
// e.g. Przemieniecki, Theory of Matrix Structural Analysis, ch. 5), assembled
// on nodes 0..N, clamped at node 0, rotations condensed out statically since
// they carry no mass: K = K_uu - K_uphi K_phiphi^-1 K_phiu (N x N, lateral
// displacements only). Lumped mass M = diag(m). Rayleigh damping C = a0 M + a1 K
// with ratio zeta on the first two fixed-base modes (Chopra, Dynamics of
// Structures, 11.4). SI units.
module;
#include <rocking/eigen.hpp>
export module rocking.beam;
import rocking.geometry;

export namespace rocking {

// Stiffness of one element of length L in (u1, phi1, u2, phi2).
Eigen::Matrix4d element_stiffness(double EI, double length);

// Lateral stiffness of a cantilever clamped at height 0 with nodes at
// `heights`, after condensing the nodal rotations out. EI per element.
Eigen::MatrixXd condensed_stiffness(const Eigen::VectorXd& heights, const Eigen::VectorXd& EI);

// Undamped modes of K phi = omega^2 M phi, omega ascending, shapes
// mass-normalised (phi' M phi = 1) and signed so that the top node moves +.
struct Modes {
  Eigen::VectorXd omega;   // [rad/s]
  Eigen::MatrixXd shapes;  // one column per mode
};
Modes fixed_base_modes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K);

// a0, a1 of C = a0 M + a1 K giving ratio zeta at omega1 and omega2
// (zeta(omega) = a0 / (2 omega) + a1 omega / 2). With one mode only
// (omega2 <= 0), the ratio is split evenly between M and K at omega1.
struct Rayleigh {
  double a0 = 0;
  double a1 = 0;
};
Rayleigh rayleigh_coefficients(double zeta, double omega1, double omega2);

// Everything the dynamics needs of the elastic structure, built once.
struct StructuralMatrices {
  Eigen::MatrixXd M, K, C;
  Modes fixed_base;
  Rayleigh rayleigh;
};
StructuralMatrices assemble(const Structure& s);

}  // namespace rocking
