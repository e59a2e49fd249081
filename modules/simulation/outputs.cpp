module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>
#include <fmt/format.h>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>
module rocking.simulation;
import rocking.modal;
import rocking.errors;

namespace rocking {

Presence presence(const ContactModel& m) {
  // A structure with joints reports its joints' rocking, the whole
  // structure's drift and its tendons' elongations and forces; its elastic
  // quantities are not computed (nor the devices' moment M_dev: rocking.report
  // leaves it out).
  if (m.jointed)
    return {.rocking = true, .elasticity = false, .dampers = false, .devices = !m.devices.empty(),
            .vertical = m.vertical_shaking, .energy = true};
  // A structure on rocking columns reports the columns' rocking (columns.*),
  // its own elastic quantities, no rocking of its own on the cap beam, and
  // the devices at the columns' bases.
  if (m.on_columns)
    return {.rocking = false, .elasticity = m.layout.u.present(), .dampers = false, .devices = !m.devices.empty(),
            .vertical = m.vertical_shaking, .energy = true, .columns = true};
  return {.rocking = m.kind != ModelKind::fixed_base,
          .elasticity = m.layout.u.present(),
          .dampers = m.has_damper,
          .devices = !m.devices.empty(),
          .vertical = m.vertical_shaking,
          .energy = m.layout.energy.present()};
}

std::string_view outcome_name(Outcome o) {
  switch (o) {
    case Outcome::completed: return "completed";
    case Outcome::overturned: return "overturned";
    case Outcome::failed: return "failed";
    case Outcome::separated: return "separated";
    case Outcome::sliding: return "sliding";
    case Outcome::undecided: return "undecided";
  }
  return "?";
}

std::optional<Outcome> outcome_named(std::string_view name) {
  for (Outcome o : {Outcome::completed, Outcome::overturned, Outcome::failed, Outcome::separated, Outcome::sliding,
                    Outcome::undecided})
    if (outcome_name(o) == name) return o;
  return std::nullopt;
}

std::string_view event_name(EventKind k) {
  switch (k) {
    case EventKind::uplift: return "uplift";
    case EventKind::impact: return "impact";
    case EventKind::overturn: return "overturn";
    case EventKind::fracture: return "fracture";
  }
  return "?";
}

void check_run_options(const RunOptions& o, std::string_view prefix) {
  auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  const ode::Options& t = o.tolerances;
  // Beyond these a step's error estimate is round-off (below) or no longer
  // bounds the state's motion (above: theta and u are of order 1e-3).
  if (!(t.rtol >= 1e-13 && t.rtol <= 0.1)) throw InputError(fmt::format("{}rtol {:g}: must be in [1e-13, 0.1]", prefix, t.rtol));
  if (!(t.atol >= 1e-16 && t.atol <= 1e-3)) throw InputError(fmt::format("{}atol {:g}: must be in [1e-16, 1e-3]", prefix, t.atol));
  if (o.duration != 0 && !(o.duration > 0 && o.duration <= 1e5))
    throw InputError(fmt::format("{}duration {}: must be positive and at most 1e5 s (omit it for the whole motion)",
                                 prefix, o.duration));
  if (o.max_events < 1) throw InputError(fmt::format("{}max-events {}: must be at least 1", prefix, o.max_events));
  if (t.max_steps < 1) throw InputError(fmt::format("{}max-steps {}: must be at least 1", prefix, t.max_steps));
  if (!positive(o.output_interval))
    throw InputError(fmt::format("{}every {}: must be positive", prefix, o.output_interval));
}

OutputScales output_scales(const ContactModel& m) {
  const Structure& st = m.body.structure;
  OutputScales sc;
  sc.H_N = st.heights[st.heights.size() - 1];
  sc.alpha_cg = slenderness(st);
  sc.inverse_H_N = 1.0 / sc.H_N;
  sc.inverse_alpha_cg = 1.0 / sc.alpha_cg;
  sc.has_forces = m.layout.u.present();
  if (sc.has_forces) {
    const ReferenceForces ref = reference_forces(st, m.body.matrices);
    sc.V_ref = ref.base_shear;
    sc.M_ref = ref.base_moment;
    // Shear above h = sum f_i, moment = sum f_i (H_i - h), f = K u (K symmetric).
    const Eigen::Index n = m.layout.n;
    const double mid = 0.5 * sc.H_N;
    const Eigen::ArrayXd above = (st.heights.array() > mid).cast<double>();
    Eigen::Matrix<double, 4, Eigen::Dynamic> w(4, n);
    w.row(0).setConstant(1.0 / sc.V_ref);
    w.row(1) = st.heights.transpose() / sc.M_ref;
    w.row(2) = above.matrix().transpose() / sc.V_ref;
    w.row(3) = (above * (st.heights.array() - mid)).matrix().transpose() / sc.M_ref;
    sc.force_rows = w * m.body.matrices.K;
    const double top_mass = st.masses[n - 1];
    sc.top_stiffness_row = -m.body.matrices.K.row(n - 1) / top_mass;
    sc.top_damping_row = -m.body.matrices.C.row(n - 1) / top_mass;
    if (m.body.coordinates == ElasticCoordinates::modal) {
      sc.force_rows = sc.force_rows * m.body.modes.Phi;
      sc.top_row = m.body.modes.Phi.row(n - 1);
      sc.top_stiffness_row = sc.top_stiffness_row * m.body.modes.Phi;
      sc.top_damping_row = sc.top_damping_row * m.body.modes.Phi;
    }
  }
  return sc;
}

Response evaluate(const ContactModel& m, const OutputScales& sc, const Discrete& d, double t,
                  Eigen::Ref<const Eigen::VectorXd> y) {
  const Layout& l = m.layout;
  const Structure& st = m.body.structure;
  Response r;
  r.t = t;
  r.phase = d.phase;
  r[Quantity::t] = t;
  r[Quantity::phase] = d.phase.sign();
  const Tilt tilt(!l.theta.present() ? 0.0 : y[l.theta.start]);
  const double th = tilt.theta, s = th > 0 ? 1.0 : th < 0 ? -1.0 : 0.0;
  const double u_top = !l.u.present() ? 0.0 : sc.top_row.size() == 0 ? y[l.u.start + l.n - 1] : sc.top_row.dot(y.segment(l.u.start, l.n));
  const double c = tilt.cos(), H = sc.H_N, B = st.half_width;
  const double one_minus_c = 2.0 * tilt.sin_half * tilt.sin_half;  // 1 - cos theta without cancellation
  auto set = [&](Quantity k, double v) { r[k] = v; };
  set(Quantity::u_top, u_top);
  set(Quantity::delta_t, (s * B * one_minus_c + u_top * c + H * tilt.sin()) * sc.inverse_H_N);
  set(Quantity::delta_e, u_top * c * sc.inverse_H_N);
  set(Quantity::theta, th);
  set(Quantity::theta_over_alpha, th * sc.inverse_alpha_cg);
  set(Quantity::theta_dot, !l.theta_dot.present() ? 0.0 : y[l.theta_dot.start]);
  const DamperState damper = active_damper(m, d, tilt, y);
  set(Quantity::damper_d, d.phase.sign() * damper.elongation);
  set(Quantity::damper_F, d.phase.sign() * damper.force);
  if (sc.has_forces) {
    Eigen::Vector4d f = Eigen::Vector4d::Zero();  // a column at a time: N is a handful
    if (l.n > max_static_size) f.noalias() = sc.force_rows * y.segment(l.u.start, l.n);
    else
      for (Eigen::Index j = 0; j < l.n; ++j) f += sc.force_rows.col(j) * y[l.u.start + j];
    set(Quantity::base_shear, f[0]);
    set(Quantity::base_moment, f[1]);
    set(Quantity::mid_shear, f[2]);
    set(Quantity::mid_moment, f[3]);
    set(Quantity::a_top, sc.top_stiffness_row.dot(y.segment(l.u.start, l.n)) + sc.top_damping_row.dot(y.segment(l.u_dot.start, l.n)) +
                             gravity * tilt.sin());
  }
  return r;
}

double node_value(const ContactModel& m, NodeQuantity q, int node, const Response& r,
                  Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot) {
  const Structure& st = m.body.structure;
  const Eigen::Index i = node - 1;
  const Tilt tilt(r[Quantity::theta]);
  const double th = tilt.theta, s = th > 0 ? 1.0 : th < 0 ? -1.0 : 0.0, B = st.half_width, H = st.heights[i];
  const double ui = u.size() > 0 ? u[i] : 0.0;
  const double one_minus_c = 2.0 * tilt.sin_half * tilt.sin_half;
  const double x = s * B * one_minus_c + ui * tilt.cos() + H * tilt.sin();
  switch (q) {
    case NodeQuantity::u: return ui;
    case NodeQuantity::x: return x;
    case NodeQuantity::y: return -H * one_minus_c - ui * tilt.sin() + s * B * tilt.sin();
    case NodeQuantity::x_abs: return x + r[Quantity::x_g];
    case NodeQuantity::a_abs: {
      if (u.size() == 0) return 0.0;
      const StructuralMatrices& k = m.body.matrices;
      return (-k.K.row(i).dot(u) - k.C.row(i).dot(u_dot)) / st.masses[i] + gravity * tilt.sin();
    }
    case NodeQuantity::count_: break;
  }
  return 0.0;
}

double element_value(const ContactModel& m, ElementQuantity q, int element, Eigen::Ref<const Eigen::VectorXd> u) {
  if (u.size() == 0) return 0.0;
  const Structure& st = m.body.structure;
  const Eigen::Index n = u.size(), first = element - 1;  // the nodes above the element's lower end
  // The end's height: the lower end's node E-1 (the base for element 1), the upper's node E.
  const Eigen::Index from = q == ElementQuantity::M_top ? first + 1 : first;
  const double h = q == ElementQuantity::M_top ? st.heights[first] : first == 0 ? 0.0 : st.heights[first - 1];
  double sum = 0;
  for (Eigen::Index j = from; j < n; ++j) {
    const double f = m.body.matrices.K.row(j).dot(u);
    sum += q == ElementQuantity::V ? f : f * (st.heights[j] - h);
  }
  return sum;
}

}  // namespace rocking
