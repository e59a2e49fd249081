// The stiff part of the phases' equations and its linear solve (contact.cppm,
// StiffPart): the elastic forces' rows of the Jacobian at u = 0 in modal
// coordinates, a diagonal plus a rank-one term.
module;
#include <rocking/eigen.hpp>
module rocking.contact;
import rocking.errors;

namespace rocking {

StiffPart::StiffPart(const ContactModel& m) : m_(&m) {
  const Layout& l = m.layout;
  if (!l.u.present()) return;
  if (m.body.coordinates != ElasticCoordinates::modal)
    throw InputError("StiffPart: the linear solve needs the model in modal coordinates (in_modal_coordinates)");
  const Structure& st = m.body.structure;
  const double B = st.half_width, mu = m.body.modes.mu;
  if (l.theta.present()) a_ = mu / (m.body.base_inertia + B * B * mu);
}

void StiffPart::prepare(double g) {
  if (g == cached_g_) return;
  const ModalBasis& md = m_->body.modes;
  const Eigen::ArrayXd D = g * md.c.array() + g * g * md.k.array();
  e_ = (1.0 / (1.0 + D)).matrix();
  z_ = e_.cwiseProduct(md.h);
  Dh_ = (D * md.h.array()).matrix();
  hDz_ = Dh_.dot(z_);
  cached_g_ = g;
}

// Whole-vector expressions: Eigen vectorises their dot products with several
// partial sums, where a loop's sum would be one chain of dependent additions.
void StiffPart::solve(Phase phase, double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x) {
  x = b;
  const Layout& l = m_->layout;
  if (!l.u.present()) return;
  prepare(g);
  const ModalBasis& md = m_->body.modes;
  const double a = phase.is_rocking() ? a_ : 0.0;
  const auto bu = b.segment(l.u.start, l.n), bv = b.segment(l.u_dot.start, l.n);
  auto xu = x.segment(l.u.start, l.n), xv = x.segment(l.u_dot.start, l.n);
  // y0 = E^-1 (b_v - g P k b_u), E = I + D, P (k b_u) = k b_u + a h (hk'b_u)
  const double hkb = a != 0 ? md.hk.dot(bu) : 0.0;
  xv.array() = e_.array() * (bv.array() - g * md.k.array() * bu.array() - (g * a * hkb) * md.h.array());
  // Sherman-Morrison for the rank-one term a h (D h)'; then x_u and th'
  if (a != 0) xv -= (a * Dh_.dot(xv) / (1.0 + a * hDz_)) * z_;
  xu = bu + g * xv;
  if (phase.is_rocking()) x[l.theta_dot.start] = b[l.theta_dot.start] + g * a * (md.hk.dot(xu) + md.hc.dot(xv));
}

}  // namespace rocking
