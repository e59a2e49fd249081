// The stiff part of the phases' equations and its linear solve (contact.cppm,
// StiffPart): the elastic forces' rows of the Jacobian at u = 0, solved with
// the eigenvectors of P K.
module;
#include <rocking/eigen.hpp>
#include <Eigen/Eigenvalues>
module rocking.contact;

namespace rocking {

StiffPart::StiffPart(const ContactModel& m) : m_(&m) {
  const Layout& l = m.layout;
  if (l.u < 0) return;
  const Structure& st = m.body.structure;
  const Eigen::MatrixXd& K = m.body.matrices.K;
  const Eigen::VectorXd& mass = st.masses;
  const auto build = [&](Phase& p, const Eigen::MatrixXd& P_inverse) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(K, P_inverse);
    p.Psi = eig.eigenvectors();  // Psi' P^-1 Psi = I
    p.lambda = eig.eigenvalues();
    p.Q = p.Psi.transpose() * P_inverse;
    p.QH = p.Q * st.heights;
    p.theta_row = P_inverse * st.heights * p.inverse_D0;
  };
  build(full_, Eigen::MatrixXd(mass.asDiagonal()));
  if (l.theta >= 0) {
    const double B = st.half_width;
    const double D0 = m.body.base_inertia + B * B * mass.sum();
    const Eigen::VectorXd MH = mass.cwiseProduct(st.heights);
    rocking_.inverse_D0 = 1.0 / D0;
    build(rocking_, Eigen::MatrixXd(mass.asDiagonal()) - MH * MH.transpose() / (D0 + st.heights.dot(MH)));
  }
  work_.setZero(l.n);
  modal_.setZero(l.n);
}

void StiffPart::prepare(Phase& p, double g) {
  if (g == p.cached_g) return;
  const Rayleigh& ray = m_->body.matrices.rayleigh;
  const double beta = g * ray.a1 + g * g;
  p.d = (1.0 / ((1.0 + g * ray.a0) + beta * p.lambda.array())).matrix();
  if (p.inverse_D0 != 0) p.z = (g * ray.a0 * p.inverse_D0) * (p.Psi * p.d.cwiseProduct(p.QH));
  p.cached_g = g;
}

void StiffPart::solve(int pivot, double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x) {
  x = b;
  const Layout& l = m_->layout;
  if (l.u < 0) return;
  Phase& p = pivot == 0 ? full_ : rocking_;
  prepare(p, g);
  const Structure& st = m_->body.structure;
  const auto bu = b.segment(l.u, l.n), bv = b.segment(l.u_dot, l.n);
  auto xu = x.segment(l.u, l.n), xv = x.segment(l.u_dot, l.n);
  // The diagonal solve in the eigenvectors: with Q P K = Psi' K = Lambda Q,
  // Q (b_v - g P K b_u) = Q b_v - g Lambda Q b_u.
  work_.noalias() = p.Q * bu;
  modal_.noalias() = p.Q * bv;
  work_ = p.d.cwiseProduct(modal_ - g * p.lambda.cwiseProduct(work_));
  xv.noalias() = p.Psi * work_;
  // then the rank-one term
  if (p.inverse_D0 != 0) {
    const auto MH = st.masses.cwiseProduct(st.heights);
    xv -= p.z * (MH.dot(xv) / (1.0 + MH.dot(p.z)));
    x[l.theta_dot] = b[l.theta_dot] + p.theta_row.dot(bv - xv);
  }
  xu = bu + g * xv;
}

}  // namespace rocking
