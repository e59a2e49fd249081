module;
#include <rocking/eigen.hpp>
#include <cmath>
module rocking.dynamics;

namespace rocking {

namespace {

// out = -(K u + C u'), column by column: with a handful of nodes a general
// matrix-vector kernel costs more in dispatch than in arithmetic, and this
// runs in every right-hand side.
void restoring_force(const StructuralMatrices& sm, Eigen::Ref<const Eigen::VectorXd> u,
                     Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> out) {
  const Eigen::Index n = u.size();
  const double* K = sm.K.data();  // column-major, n x n
  const double* C = sm.C.data();
  double* f = out.data();
  for (Eigen::Index i = 0; i < n; ++i) f[i] = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double uj = u[j], vj = u_dot[j];
    for (Eigen::Index i = 0; i < n; ++i) f[i] -= K[j * n + i] * uj + C[j * n + i] * vj;
  }
}

}  // namespace

RockingBody make_body(const Structure& s, double g) {
  if (!s.rigid) return {s, assemble(s), g};
  StructuralMatrices none;
  none.M = s.masses.asDiagonal();
  return {s, none, g};
}

void full_contact_acceleration(const RockingBody& b, double a_g, Eigen::Ref<const Eigen::VectorXd> u,
                               Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> u_ddot) {
  restoring_force(b.matrices, u, u_dot, u_ddot);
  u_ddot.array() /= b.structure.masses.array();
  u_ddot.array() -= a_g;
}

double rocking_acceleration(const RockingBody& b, int s, double a_g, double F_hd, const Coordinates& q,
                            Eigen::Ref<Eigen::VectorXd> u_ddot, Eigen::Ref<Eigen::VectorXd> work) {
  const Structure& st = b.structure;
  const auto& m = st.masses.array();
  const auto& H = st.heights;
  const double B = st.half_width, g = b.g, th = q.theta, thd = q.theta_dot;
  const double c = std::cos(th), sn = std::sin(th);
  // work = w = B1 - s u (lever arms)
  work = (B - s * q.u.array()).matrix();
  const double Mw = (m * work.array()).sum();   // 1'M w
  const double wMw = (m * work.array().square()).sum();
  const double HM1 = H.dot(st.masses);           // H'M1
  // rhs_u = -M1 a_g cos th - M (sB1 - u) th'^2 - C u' - K u + M1 g sin th, with sB1 - u = s w
  restoring_force(b.matrices, q.u, q.u_dot, u_ddot);
  u_ddot.array() += m * (-a_g * c - s * work.array() * thd * thd + g * sn);
  const double rhs_th = 2.0 * s * (m * q.u_dot.array() * work.array()).sum() * thd
                        - s * F_hd * 2.0 * B * std::cos(0.5 * th)
                        - a_g * (HM1 * c + s * Mw * sn + s * st.base_mass * B * sn)
                        - g * (-HM1 * sn + s * Mw * c + s * st.base_mass * B * c);
  // Schur complement of the diagonal M: J - H'MH = m0 B^2 + w'Mw > 0
  const double th_ddot = (rhs_th - H.dot(u_ddot)) / (st.base_mass * B * B + wMw);
  u_ddot.array() = u_ddot.array() / m - H.array() * th_ddot;
  return th_ddot;
}

double rigid_rocking_acceleration(const RockingBody& b, int s, double a_g, double F_hd, double theta,
                                  double theta_dot) {
  (void)theta_dot;  // no Coriolis term without elastic motion
  const Structure& st = b.structure;
  const double B = st.half_width, c = std::cos(theta), sn = std::sin(theta);
  const double HM1 = st.heights.dot(st.masses), BM = B * (st.masses.sum() + st.base_mass);
  const double rhs_th = -s * F_hd * 2.0 * B * std::cos(0.5 * theta) - a_g * (HM1 * c + s * BM * sn) -
                        b.g * (-HM1 * sn + s * BM * c);
  return rhs_th / pivot_inertia(st);
}

double ground_input_power(const RockingBody& b, int s, double a_g, const Coordinates& q) {
  const Structure& st = b.structure;
  const auto& m = st.masses.array();
  const double B = st.half_width, c = std::cos(q.theta), sn = std::sin(q.theta);
  const double Mw = (m * (B - s * q.u.array())).sum();
  const double on_u = -a_g * c * (m * q.u_dot.array()).sum();
  const double on_theta = -a_g * (st.heights.dot(st.masses) * c + s * (Mw + st.base_mass * B) * sn);
  return on_u + on_theta * q.theta_dot;
}

double mechanical_energy(const RockingBody& b, int s, const Coordinates& q) {
  const Structure& st = b.structure;
  const auto& m = st.masses.array();
  const double B = st.half_width, th = q.theta, thd = q.theta_dot;
  const Eigen::ArrayXd w = B - s * q.u.array();
  const double J = st.base_mass * B * B + (m * (w.square() + st.heights.array().square())).sum();  // J(u)
  const double kinetic = 0.5 * (m * q.u_dot.array().square()).sum() + 0.5 * J * thd * thd +
                         thd * (m * st.heights.array() * q.u_dot.array()).sum();
  // heights: Y = s w sin th + H cos th for the nodes, s B sin th for the foundation beam
  const double gravity = b.g * ((m * (s * w * std::sin(th) + st.heights.array() * (std::cos(th) - 1.0))).sum() +
                                st.base_mass * s * B * std::sin(th));
  const double elastic = b.structure.rigid ? 0.0 : 0.5 * q.u.dot(b.matrices.K * q.u);
  return kinetic + gravity + elastic;
}

}  // namespace rocking
