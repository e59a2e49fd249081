// rocking.contact: the state holds only what a scene models, and the phase
// changes of MODEL.md 6 do what the equations say, one reset at a time.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>
import rocking.contact;
import rocking.scene;
import rocking.modal;
import rocking.simulation;
#include "spread_nodes.hpp"

using namespace rocking;

namespace {
Scene chimney(std::vector<std::string> overrides = {}) { return load_default_scene(overrides); }
const Phase all_phases[] = {Phase::full_contact(), Phase::rocking(Pivot::right), Phase::rocking(Pivot::left)};
}  // namespace

TEST_CASE("each scene's state holds only what it models") {
  const Eigen::Index n = 4;
  CHECK(make_contact_model(chimney(), false).layout.size == 2 * n + 3);  // u, u', theta, theta', z
  CHECK(make_contact_model(chimney({"damper.enabled=false"}), false).layout.size == 2 * n + 2);
  const ContactModel fixed = make_contact_model(chimney({"contact.rocking=false"}), false);
  CHECK(fixed.kind == ModelKind::fixed_base);
  CHECK(fixed.layout.size == 2 * n);  // u, u' only: linear, no events
  CHECK(phase_guards(fixed, Phase::full_contact()).empty());
  const ContactModel rigid = make_contact_model(chimney({"structure.rigid=true"}), false);
  CHECK(rigid.kind == ModelKind::rigid_block);
  CHECK(rigid.layout.size == 3);  // theta, theta', z
  CHECK(make_contact_model(chimney({"structure.rigid=true", "damper.enabled=false"}), true).layout.size == 2 + 3);
}

TEST_CASE("a rigid block lifts when the ground acceleration exceeds g tan(alpha) (Eq. 2 with u = 0)") {
  // Lumped on the centre line with a base beam, the static uplift acceleration is
  // g B (1'M1 + m0) / H'M1 = g tan(alpha_cg) exactly.
  const ContactModel m = make_contact_model(chimney({"structure.rigid=true", "damper.enabled=false"}), false);
  Discrete d;
  const Eigen::VectorXd y = Eigen::VectorXd::Zero(m.layout.size);
  const double a_up = m.body.g * std::tan(slenderness(m.body.structure));
  CHECK(uplift_now(m, d, -1.001 * a_up, y) == Pivot::right);  // ground pushed left: tips right
  CHECK(uplift_now(m, d, +1.001 * a_up, y) == Pivot::left);
  CHECK(uplift_now(m, d, 0.999 * a_up, y) == std::nullopt);
  CHECK(uplift_now(m, d, -0.999 * a_up, y) == std::nullopt);
}

TEST_CASE("a damper's residual force enters the uplift condition of the edge it holds") {
  const ContactModel m = make_contact_model(chimney({"structure.rigid=true"}), false);
  const Eigen::VectorXd y = Eigen::VectorXd::Zero(m.layout.size);
  const double a_up = m.body.g * std::tan(slenderness(m.body.structure));
  Discrete d;
  CHECK(uplift_now(m, d, -1.001 * a_up, y) == Pivot::right);
  d.set_z(0, 1.0);  // the damper that rocking about +1 stretches is already in tension
  CHECK(uplift_now(m, d, -1.001 * a_up, y) == std::nullopt);
  d.set_z(0, -1.0);  // ... or pushing the edge up: lifts below the rigid threshold
  CHECK(uplift_now(m, d, -0.999 * a_up, y) == Pivot::right);
}

TEST_CASE("uplift of the flexible chimney needs both the moment (Eq. 2) and L_s > 0 (Eq. 3)") {
  const ContactModel m = make_contact_model(chimney({"damper.enabled=false"}), false);
  Discrete d;
  const Layout& l = m.layout;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(l.size);
  // Push the first mode 20 % past the static uplift point c of MODEL.md 7
  // (M_ref = c H'K phi_1).
  const Eigen::VectorXd phi = m.body.matrices.fixed_base.shapes.col(0);
  const double c = reference_forces(m.body.structure, m.body.matrices).base_moment /
                   m.body.structure.heights.dot(m.body.matrices.K * phi);
  y.segment(l.u.start, l.n) = 1.2 * c * phi;
  CHECK(uplift_now(m, d, 0.0, y) == std::nullopt);  // at rest: L_s = 0, not > 0
  y.segment(l.u_dot.start, l.n) = 0.01 * phi;     // still moving right
  CHECK(uplift_now(m, d, 0.0, y) == Pivot::right);
  y.segment(l.u_dot.start, l.n) = -0.01 * phi;    // already coming back
  CHECK(uplift_now(m, d, 0.0, y) == std::nullopt);
}

TEST_CASE("guards say truly whether they read a_g and a_v (callers skip the record lookups when not)") {
  // Every scene kind and phase: the guard values at a_g = 0, a_g = 3 m/s^2 and a_v = 3 m/s^2
  // are equal exactly when guard_inputs says they do not read a_g, a_v.
  for (const auto& overrides : std::vector<std::vector<std::string>>{
           {}, {"structure.rigid=true"}, {"damper.enabled=false"}, {"structure.rigid=true", "damper.enabled=false"}}) {
    const ContactModel m = make_contact_model(chimney(overrides), false);
    for (Phase phase : all_phases) {
      Discrete d;
      Eigen::VectorXd y = Eigen::VectorXd::Constant(m.layout.size, 0.01);
      if (const std::optional<Pivot> p = phase.pivot()) begin_rocking(m, d, *p, y), y[m.layout.theta.start] = 0.01 * sign(*p);
      Eigen::VectorXd g0 = Eigen::VectorXd::Zero(2), g3 = g0, gv = g0;
      guard_values(m, d, 0.0, y, g0);
      guard_values(m, d, 3.0, y, g3);
      guard_values(m, d, GroundAcceleration{0.0, 3.0}, y, gv);  // vertical shaking (MODEL.md 14)
      CAPTURE(phase_name(phase));
      CAPTURE(m.layout.size);
      CHECK(guard_inputs(m, phase, false).horizontal == (g0 != g3));
      CHECK(!guard_inputs(m, phase, false).vertical);
      CHECK(guard_inputs(m, phase, true).horizontal == (g0 != g3));
      CHECK(guard_inputs(m, phase, true).vertical == (g0 != gv));
    }
  }
}

TEST_CASE("uplift guards equal Eq. 2 and Eq. 3 written out, at 4 nodes (unrolled) and 20 (general loops)") {
  for (Eigen::Index nodes : {4, 20}) {
    Scene scene = chimney();
    if (nodes != 4) spread_over_nodes(scene.structure, nodes);
    const ContactModel m = make_contact_model(scene, false);
    const Layout& l = m.layout;
    const Structure& st = m.body.structure;
    Discrete d;
    d.set_z(0, 0.3);
    d.set_z(1, -0.2);
    Eigen::VectorXd y = Eigen::VectorXd::Zero(l.size);
    y.segment(l.u.start, l.n) = Eigen::VectorXd::LinSpaced(l.n, 1e-3, 2e-2);
    y.segment(l.u_dot.start, l.n) = Eigen::VectorXd::LinSpaced(l.n, -0.05, 0.1);
    const auto u = y.segment(l.u.start, l.n), u_dot = y.segment(l.u_dot.start, l.n);
    const double moment = st.heights.dot(m.body.matrices.K * u + m.body.matrices.C * u_dot);
    const double momentum = st.heights.dot(st.masses.asDiagonal() * u_dot);
    Eigen::VectorXd g(2);
    guard_values(m, d, 0.0, y, g);
    for (int s : {+1, -1}) {
      const double f_res = law_force_at_rest(m.devices[s > 0 ? 0 : 1].law, d.z(s > 0 ? 0 : 1));
      const double eq2 = s * moment - (m.body.g * (st.half_width * total_mass(st) - s * st.masses.dot(u)) +
                                       f_res * 2 * st.half_width);
      const double expected = std::min(eq2, s * momentum);
      CAPTURE(nodes);
      CAPTURE(s);
      CHECK(g[s > 0 ? 0 : 1] == close_to(expected, 1e-12, 1e-12));
    }
  }
}

TEST_CASE("impact: continued rocking takes r and keeps u', full contact keeps the momentum H th'") {
  const ContactModel m = make_contact_model(chimney({"contact.restitution=0.9"}), false);
  const Layout& l = m.layout;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(l.size);
  Discrete d;
  begin_rocking(m, d, Pivot::right, y);
  y[l.theta_dot.start] = -0.05;  // falling back onto the left pivot
  y.segment(l.u_dot.start, l.n).setConstant(0.001);
  y[l.z.start] = 0.4;
  d.set_z(1, -0.3);  // what the other damper kept from its last cycle
  const ImpactResult r = impact(m, d, y);
  CHECK(r.continues);
  CHECK(d.phase == Phase::rocking(Pivot::left));
  CHECK(y[l.theta_dot.start] == close_to(0.9 * -0.05, 1e-15));
  CHECK(y.segment(l.u_dot.start, l.n).isApproxToConstant(0.001));
  CHECK(y[l.z.start] == -0.3);               // the left-pivot damper resumes its own z
  CHECK(d.z(0) == 0.4);       // and the other keeps its z for later

  // Below theta_dot_min the structure settles: th' = 0 and u' gains H th'-.
  y[l.theta_dot.start] = 0.001;  // rocking about -1, falling back (s th' > 0 means -th decreasing)
  const Eigen::VectorXd u_dot_before = y.segment(l.u_dot.start, l.n);
  const ImpactResult settle = impact(m, d, y);
  CHECK_FALSE(settle.continues);
  CHECK(d.phase == Phase::full_contact());
  CHECK(y[l.theta_dot.start] == 0.0);
  CHECK((y.segment(l.u_dot.start, l.n) - (u_dot_before + m.body.structure.heights * 0.001)).norm() < 1e-15);
}

TEST_CASE("Eq. 9 restitution equals Eq. 10 for an undeformed structure and stays in [0, 1]") {
  const ContactModel eq9 = make_contact_model(chimney({"contact.restitution=eq9"}), false);
  const Layout& l = eq9.layout;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(l.size);
  Discrete d;
  begin_rocking(eq9, d, Pivot::right, y);
  y[l.theta_dot.start] = -0.05;
  const ImpactResult r = impact(eq9, d, y);
  CHECK(r.r == close_to(eq9.r_eq10, 1e-12));
  // A deformed, moving structure: the ratio of the momenta about the new and
  // the old pivot, computed here from Eq. 9 as printed (upper sign: s = +1).
  begin_rocking(eq9, d, Pivot::right, y);
  const double th_dot = -0.05, u = 0.02, u_dot = -0.01;
  y[l.theta_dot.start] = th_dot;
  y.segment(l.u.start, l.n).setConstant(u);
  y.segment(l.u_dot.start, l.n).setConstant(u_dot);
  const Structure& st = eq9.body.structure;
  const double M1 = st.masses.sum(), uMu = M1 * u * u, HMu_dot = st.heights.dot(st.masses) * u_dot;
  const double B = st.half_width, J_p = pivot_inertia(st);
  const double l_new = (J_p - 2 * (M1 + st.base_mass) * B * B + uMu) * th_dot + HMu_dot;
  const double l_old = (J_p - 2 * B * M1 * u + uMu) * th_dot + HMu_dot;
  const ImpactResult r2 = impact(eq9, d, y);
  CHECK(r2.continues);
  CHECK(r2.r == close_to(l_new / l_old, 1e-12));
  CHECK(std::abs(r2.r - eq9.r_eq10) > 1e-4);  // the deformation matters
}

TEST_CASE("modal coordinates: rhs, guards, energy, outputs and resets equal the nodal model's, mapped by u = Phi q") {
  // The same physics in the fixed-base modes (rocking.dynamics): every
  // function of the state agrees with the nodal model's at states mapped by
  // q = Phi^-1 u, to round-off (1e-9 relative), at 4 nodes and 20, with
  // devices, energy accumulators and Eq. 9 restitution.
  for (Eigen::Index nodes : {4, 20}) {
    Scene scene = chimney({"contact.restitution=eq9", "device+={name=\"tendon\", kind=\"elastic\", at=0, "
                           "kinematics=\"vertical\", free_length=33, P0=2e6, k=5e7}"});
    if (nodes != 4) spread_over_nodes(scene.structure, nodes);
    const ContactModel nodal = make_contact_model(scene, true);
    const ContactModel modal = in_modal_coordinates(nodal);
    const Layout& l = nodal.layout;
    REQUIRE(modal.layout.size == l.size);
    CHECK(modal.body.coordinates == ElasticCoordinates::modal);
    const Eigen::MatrixXd& Phi = modal.body.modes.Phi;
    // q = Phi^-1 u, and the whole state mapped
    const auto to_modal = [&](const Eigen::VectorXd& y) {
      Eigen::VectorXd out = y;
      from_nodal(modal.body, y.segment(l.u.start, l.n), out.segment(l.u.start, l.n));
      from_nodal(modal.body, y.segment(l.u_dot.start, l.n), out.segment(l.u_dot.start, l.n));
      return out;
    };
    const auto to_nodal_state = [&](const Eigen::VectorXd& y) {
      Eigen::VectorXd out = y;
      out.segment(l.u.start, l.n) = Phi * y.segment(l.u.start, l.n);
      out.segment(l.u_dot.start, l.n) = Phi * y.segment(l.u_dot.start, l.n);
      return out;
    };
    const auto close = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
      return (a - b).norm() <= 1e-9 * std::max(b.norm(), 1e-300);
    };
    CHECK(close(to_nodal_state(to_modal(Eigen::VectorXd::LinSpaced(l.size, -1, 1))),
                Eigen::VectorXd::LinSpaced(l.size, -1, 1)));
    const OutputScales sn = output_scales(nodal), sm = output_scales(modal);
    for (Phase phase : all_phases) {
      CAPTURE(nodes);
      CAPTURE(phase_name(phase));
      const int pivot = phase.sign();
      Discrete d;
      d.set_z(0, 0.3);
      d.set_z(1, -0.2);
      Eigen::VectorXd y = Eigen::VectorXd::Zero(l.size);
      if (phase.is_rocking()) {
        begin_rocking(nodal, d, *phase.pivot(), y);
        y[l.theta.start] = 0.004 * pivot;
        y[l.theta_dot.start] = -0.03 * pivot;
      }
      y.segment(l.u.start, l.n) = Eigen::VectorXd::LinSpaced(l.n, 1e-3, 2e-2);
      y.segment(l.u_dot.start, l.n) = Eigen::VectorXd::LinSpaced(l.n, -0.05, 0.1);
      const Eigen::VectorXd q = to_modal(y);
      Eigen::VectorXd fn(l.size), fm(l.size);
      phase_rhs(nodal, d, 1.3, y, fn);
      phase_rhs(modal, d, 1.3, q, fm);
      CHECK(close(to_nodal_state(fm), fn));
      CHECK(mechanical_energy(modal, phase, q) == close_to(mechanical_energy(nodal, phase, y), 1e-9));
      const std::size_t guards = phase_guards(nodal, phase).size();
      Eigen::VectorXd gn(guards), gm(guards);
      guard_values(nodal, d, 1.3, y, gn);
      guard_values(modal, d, 1.3, q, gm);
      CHECK(close(gm, gn));
      const Response rn = evaluate(nodal, sn, d, 0.0, y), rm = evaluate(modal, sm, d, 0.0, q);
      // Outputs that are differences of nodal values (drifts, section forces)
      // carry the 20-node modal basis's round-off times its conditioning: 6e-9 observed.
      for (std::size_t k = 0; k < quantity_count; ++k) CHECK(rm.q[k] == close_to(rn.q[k], 1e-8));
      StateView vn, vm;
      view(nodal, y, vn);
      view(modal, q, vm);
      CHECK(close(vm.u, vn.u));
      CHECK(close(vm.u_dot, vn.u_dot));
      if (phase.is_rocking()) {
        // an impact (Eq. 9 continued rocking), then one that settles (u' + H th')
        for (double theta_dot : {-0.03 * pivot, -0.001 * pivot}) {
          Eigen::VectorXd yn = y, ym = q;
          yn[l.theta_dot.start] = ym[l.theta_dot.start] = theta_dot;
          Discrete dn = d, dm = d;
          const ImpactResult in = impact(nodal, dn, yn), im = impact(modal, dm, ym);
          CHECK(in.continues == im.continues);
          CHECK(im.r == close_to(in.r, 1e-9));
          CHECK(dn.phase == dm.phase);
          CHECK(close(to_nodal_state(ym), yn));
        }
      }
    }
    // Full contact as a linear system: A and b map to the nodal ones.
    const LinearPhase pn = full_contact_matrices(nodal), pm = full_contact_matrices(modal);
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(2 * l.n, 2 * l.n);
    T.topLeftCorner(l.n, l.n) = Phi;
    T.bottomRightCorner(l.n, l.n) = Phi;
    CHECK((T * pm.A - pn.A * T).norm() <= 1e-9 * (pn.A * T).norm());
    CHECK((T * pm.b - pn.b).norm() <= 1e-9 * pn.b.norm());
  }
}

TEST_CASE("each acting device's kernels are its law and kinematics: terms, z' and state equal stretch() and the law's own functions") {
  // Each law, chord and vertical, intact and broken, the kernels chosen when
  // the model was built against stretch(), law_force_and_rate() and
  // law_force() written out (bit for bit: the same arithmetic).
  const std::vector<std::string> devices = {
      R"(device+={name="d", kind="bouc-wen", at="edges", k=1e7, eps=0.06, d_y=0.0185, alpha=1, beta=0})",
      R"(device+={name="d", kind="elastic", at=0, kinematics="vertical", free_length=33, P0=2e6, k=5e7})",
      R"(device+={name="d", kind="elastic", at="edges", P0=1e5, k=5e7})",
      R"(device+={name="d", kind="viscous", at="edges", c=3e5, a=0.3})",
      R"(device+={name="d", kind="friction", at="edges", kinematics="vertical", free_length=2, F_s=5e4})",
      R"(device+={name="d", kind="bouc-wen", at="edges", kinematics="vertical", free_length=2, k=1e7, eps=0.06, d_y=0.0185})"};
  for (const std::string& device : devices) {
    CAPTURE(device);
    const ContactModel m = make_contact_model(chimney({"damper.enabled=false", device}), false);
    const Layout& l = m.layout;
    const double B = m.body.structure.half_width;
    for (Pivot p : pivots) {
      const int s = sign(p);
      for (bool broken : {false, true}) {
        CAPTURE(s);
        CAPTURE(broken);
        const ContactModel::Acting& a = m.acting[index(p)].front();
        Discrete d;
        Eigen::VectorXd y = Eigen::VectorXd::LinSpaced(l.size, 0.002, 0.02);
        begin_rocking(m, d, p, y);
        y[l.theta.start] = 0.01 * s;
        y[l.theta_dot.start] = 0.05 * s;
        if (a.slot) y[*a.slot] = 0.3;
        if (broken) fracture(d, a.device);
        const Tilt tilt(y[l.theta.start]);
        const double thd = y[l.theta_dot.start];
        Eigen::VectorXd dydt = Eigen::VectorXd::Constant(l.size, 7.0);
        const ContactModel::DeviceTerms t = a.terms(a, d, B, p, tilt, thd, y.data(), dydt.data());
        const DamperState state = a.state(a, d, B, p, tilt, thd, y.data());
        const Stretch st = stretch(a.geometry, B, p, tilt);
        const double e_dot = st.de_dtheta * s * thd, z = a.slot ? y[*a.slot] : 0.0;
        const LawResponse r = law_force_and_rate(a.law, st.e, e_dot, z);
        const bool chord = a.geometry.kinematics == Kinematics::chord;
        CHECK(state.elongation == st.e);
        CHECK(state.force == (broken ? 0.0 : law_force(a.law, st.e, e_dot, z)));
        CHECK(t.moment == (broken ? 0.0 : chord ? r.F * a.lever * tilt.cos_half : r.F * st.de_dtheta));
        CHECK(t.power == (broken ? 0.0 : r.F * e_dot));
        if (a.slot) CHECK(dydt[*a.slot] == (broken ? 0.0 : r.rate));
        CHECK(st.e > 0);
      }
    }
  }
}
