module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>
#include <algorithm>
#include <optional>
#include <cmath>
#include <string>
#include <variant>
#include <vector>
#include <fmt/format.h>
module rocking.contact;
import rocking.errors;

namespace rocking {

namespace {

Layout make_layout(ModelKind kind, Eigen::Index n, Eigen::Index z_count, Eigen::Index devices, bool energy) {
  Layout l;
  Eigen::Index next = 0;
  if (kind != ModelKind::rigid_block) {
    l.n = n;
    l.u = {next, n};
    l.u_dot = {next + n, n};
    next += 2 * n;
  }
  if (kind != ModelKind::fixed_base) {
    l.theta = {next++, 1};
    l.theta_dot = {next++, 1};
    if (z_count > 0) {
      l.z.start = next;
      l.z.count = z_count;
      next += z_count;
    }
  }
  if (energy) {
    l.energy.start = next;
    l.energy.count = 3 + devices;
    next += l.energy.count;
  }
  l.size = next;
  return l;
}

// The kernels of an acting device (ContactModel::TermsFn and StateFn) for
// its law and kinematics: the chord's stretch with its lever arm l = a.lever,
// else stretch(); the law's force and z' at (e, e', z); nothing once broken.
template <bool Chord>
Stretch stretch_of(const ContactModel::Acting& a, double half_width, Pivot p, const Tilt& tilt) {
  if constexpr (Chord) return {2.0 * a.lever * std::abs(tilt.sin_half), a.lever * tilt.cos_half};
  else return stretch(a.geometry, half_width, p, tilt);
}

template <class Law, bool Chord>
ContactModel::DeviceTerms device_terms(const ContactModel::Acting& a, const Discrete& d, double half_width, Pivot p,
                                       const Tilt& tilt, double thd, const double* y, double* dydt) {
  if (d.broken != 0 && d.is_broken(a.device)) {
    if constexpr (Law::states > 0) dydt[*a.slot] = 0.0;
    return {};
  }
  const Law& law = *std::get_if<Law>(&a.law);
  const Stretch st = stretch_of<Chord>(a, half_width, p, tilt);
  const double e_dot = st.de_dtheta * sign(p) * thd;
  const double z = Law::states > 0 ? y[*a.slot] : 0.0;  // a law with a state has a slot
  const double F = law.force(st.e, e_dot, z);
  if constexpr (Law::states > 0) dydt[*a.slot] = law.rate(st.e, e_dot, z);
  return {Chord ? F * a.lever * tilt.cos_half : F * st.de_dtheta, F * e_dot};
}

template <class Law, bool Chord>
DamperState device_state(const ContactModel::Acting& a, const Discrete& d, double half_width, Pivot p, const Tilt& tilt,
                         double thd, const double* y) {
  const Stretch st = stretch_of<Chord>(a, half_width, p, tilt);
  if (d.broken != 0 && d.is_broken(a.device)) return {st.e, 0.0};
  const double e_dot = st.de_dtheta * sign(p) * thd;
  return {st.e, std::get_if<Law>(&a.law)->force(st.e, e_dot, Law::states > 0 ? y[*a.slot] : 0.0)};
}

template <std::size_t I = 0>
void choose_kernels(ContactModel::Acting& a) {
  if constexpr (I < std::variant_size_v<DeviceLaw>) {
    using Law = std::variant_alternative_t<I, DeviceLaw>;
    if (a.law.index() != I) return choose_kernels<I + 1>(a);
    const bool chord = a.geometry.kinematics == Kinematics::chord;
    a.terms = chord ? &device_terms<Law, true> : &device_terms<Law, false>;
    a.state = chord ? &device_state<Law, true> : &device_state<Law, false>;
  }
}

double theta_of(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y) {
  return !m.layout.theta.present() ? 0.0 : y[m.layout.theta.start];
}
double theta_dot_of(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y) {
  return !m.layout.theta_dot.present() ? 0.0 : y[m.layout.theta_dot.start];
}

// The elastic displacements and velocities of a state (zeros for a rigid block).
Eigen::Ref<const Eigen::VectorXd> u_of(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y) {
  if (!m.layout.u.present()) return m.zero_motion;
  return y.segment(m.layout.u.start, m.layout.n);
}
Eigen::Ref<const Eigen::VectorXd> u_dot_of(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y) {
  if (!m.layout.u.present()) return m.zero_motion;
  return y.segment(m.layout.u_dot.start, m.layout.n);
}

// H'M u' (momentum moment of the elastic velocities).
double moment_of_velocities(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y) {
  return moment_sum(m.body, u_dot_of(m, y));
}

// The rows of the uplift guards' dot products on [q; q'] (contact.cppm).
void set_guard_rows(ContactModel& m) {
  if (!m.layout.u.present()) return;
  const Eigen::Index n = m.layout.n;
  const RockingBody& b = m.body;
  const bool modal = b.coordinates == ElasticCoordinates::modal;
  const Structure& st = b.structure;
  m.mass_row.setZero(2 * n);
  m.mass_row.head(n) = modal ? Eigen::VectorXd(b.modes.mu * b.modes.r) : st.masses;
  m.momentum_row.setZero(2 * n);
  m.momentum_row.tail(n) = modal ? Eigen::VectorXd(b.modes.mu * b.modes.h) : st.heights.cwiseProduct(st.masses);
}

// The parts of both uplift guards that do not depend on the pivot, from one
// pass over the state. In full contact the inertia forces equal K u + C u'
// (flexible) or -M1 a_g (rigid, u = 0).
struct UpliftTerms {
  double moment = 0;    // H'(K u + C u') (flexible) or -a_g H'M1 (rigid) [N m]
  double Mu = 0;        // 1'M u [kg m]
  double momentum = 0;  // H'M u' [kg m^2/s]
  double g = 0;         // the gravity felt, g + a_v [m/s^2]
};
UpliftTerms uplift_terms(const ContactModel& m, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y) {
  if (!m.layout.u.present()) return {-a.h * m.body.HM1, 0.0, 0.0, m.body.g + a.v};
  UpliftTerms t;
  t.g = m.body.g + a.v;
  const double* x = y.data() + m.layout.u.start;  // [u; u'], adjacent in the layout
  const double *r0 = m.body.moment_row.data(), *r1 = m.mass_row.data(), *r2 = m.momentum_row.data();
  with_static_size(2 * m.layout.n, [&](auto size) {
    constexpr int S = decltype(size)::value;
    if constexpr (S > 0) {  // Eigen's fixed-size dot products: vectorised, with short chains
      using Row = Eigen::Matrix<double, S, 1>;
      const Eigen::Map<const Row> state(x);
      t.moment = Eigen::Map<const Row>(r0).dot(state);
      t.Mu = Eigen::Map<const Row>(r1).dot(state);
      t.momentum = Eigen::Map<const Row>(r2).dot(state);
    } else {  // Eigen's dot products: vectorised, several partial sums each
      const long n2 = 2 * m.layout.n;
      const Eigen::Map<const Eigen::VectorXd> state(x, n2);
      t.moment = Eigen::Map<const Eigen::VectorXd>(r0, n2).dot(state);
      t.Mu = Eigen::Map<const Eigen::VectorXd>(r1, n2).dot(state);
      t.momentum = Eigen::Map<const Eigen::VectorXd>(r2, n2).dot(state);
    }
  });
  return t;
}

// The uplift guard about s: min(g_s, L_s) crosses zero upwards when both
// become positive, g_s being Eq. 2 as a smooth moment guard [N m] (MODEL.md 6)
// and L_s = s H'M u' Eq. 3. A rigid block has no elastic momentum: g_s alone.
double uplift_guard(const ContactModel& m, const Discrete& d, Pivot p, const UpliftTerms& t) {
  const int s = sign(p);
  const Structure& st = m.body.structure;
  const double B = st.half_width;
  const double restoring = t.g * (B * m.body.total_mass - s * t.Mu);
  const double gs = s * t.moment - (restoring + held_moment(m, d, p));
  if (!m.layout.u.present()) return gs;
  return std::min(gs, s * t.momentum);
}

double restitution(const ContactModel& m, Pivot p, Eigen::Ref<const Eigen::VectorXd> y, double l_new,
                   double theta_dot) {
  switch (m.contact.restitution_rule) {
    case RestitutionRule::constant: return m.contact.restitution;
    case RestitutionRule::eq10: return m.r_eq10;
    case RestitutionRule::eq9: break;
  }
  // Eq. 9: r = L_new / L_old, L_old = J(u) th'- + H'M u' (momentum about the old pivot)
  const Structure& st = m.body.structure;
  const Eigen::Ref<const Eigen::VectorXd> u = u_of(m, y);
  double j = pivot_inertia(st);
  j += mass_dot(m.body, u, u) - 2.0 * sign(p) * st.half_width * mass_sum(m.body, u);
  const double hmu = moment_of_velocities(m, y);
  const double l_old = j * theta_dot + hmu;
  const double scale = std::abs(j * theta_dot) + std::abs(hmu);
  // Guard against a vanishing denominator: fall back to the geometric Eq. 10.
  if (!(std::abs(l_old) > 1e-9 * scale)) return m.r_eq10;
  return std::clamp(l_new / l_old, 0.0, 1.0);
}

}  // namespace

ContactModel make_contact_model(const Structure& st, const Contact& contact, std::vector<Device> devices,
                                bool track_energy) {
  ContactModel m;
  m.kind = st.rigid ? ModelKind::rigid_block : contact.rocking ? ModelKind::flexible : ModelKind::fixed_base;
  m.body = make_body(st);
  m.zero_motion.setZero(node_count(st));
  if (m.kind != ModelKind::fixed_base) {
    for (Device& dev : devices) {
      if (dev.geometry.kinematics == Kinematics::beam)
        throw InputError(fmt::format("device {}: kinematics = beam joins the ground to the cap beam of a structure on "
                                     "[columns]; this structure rocks on its own base", dev.name));
      if (!(std::abs(dev.geometry.x) <= st.half_width))
        throw InputError(fmt::format("device {}: anchor x = {} m lies outside the base (|x| <= B = {} m)", dev.name,
                                     dev.geometry.x, st.half_width));
      m.devices.push_back(std::move(dev));
    }
  }
  m.has_damper = std::ranges::any_of(m.devices, &Device::edge_damper);
  if (m.devices.size() > static_cast<std::size_t>(max_device_states))
    throw InputError(fmt::format("{} devices: at most {}", m.devices.size(), max_device_states));
  for (const Device& dev : m.devices)
    if (!(dev.capacity >= 0) || !std::isfinite(dev.capacity))
      throw InputError(fmt::format("device {}: capacity {} m: must be positive (0: never breaks)", dev.name, dev.capacity));
  m.contact = contact;
  m.r_eq10 = restitution_eq10(st);
  m.overturn_angle = contact.overturn_angle > 0 ? contact.overturn_angle : slenderness(st);
  std::array<Eigen::Index, 2> states{0, 0};
  for (Pivot p : pivots)
    for (std::size_t k = 0; k < m.devices.size(); ++k) {
      const Device& dev = m.devices[k];
      const double lever = lever_arm(dev.geometry, st.half_width, p);
      if (!(lever > 0)) continue;
      const std::size_t i = index(p);
      if (dev.capacity > 0) m.breakable[i].push_back(static_cast<int>(m.acting[i].size()));
      if (dev.edge_damper && !m.damper[i]) m.damper[i] = m.acting[i].size();
      m.acting[i].push_back({static_cast<int>(k), law_states(dev.law) > 0 ? std::optional<Eigen::Index>(states[i]++) : std::nullopt, lever,
                             dev.geometry, dev.law, dev.capacity});
    }
  // The work on each device needs its own accumulator only where a pivot
  // stretches several; with one at most, the total's increase over a rocking
  // phase is that device's (the driver splits it), and the state stays as small.
  const bool split = m.acting[0].size() > 1 || m.acting[1].size() > 1;
  m.layout = make_layout(m.kind, node_count(st), std::max(states[0], states[1]),
                         split ? static_cast<Eigen::Index>(m.devices.size()) : 0, track_energy);
  for (std::size_t i : {0, 1}) {
    for (ContactModel::Acting& a : m.acting[i]) {
      if (a.slot) *a.slot += m.layout.z.start;
      choose_kernels(a);
    }
    m.idle_slots[i] = states[i] < m.layout.z.count;
  }
  set_guard_rows(m);
  return m;
}

ContactModel in_modal_coordinates(ContactModel m) {
  m.body = in_modal_coordinates(std::move(m.body));
  set_guard_rows(m);
  return m;
}

namespace {
// The full-contact power forms of LinearPhase on z = (u, u'): the input power
// is linear in z at a_g = 1 (its entries are its values at the unit vectors),
// the viscous power a quadratic form in u' (its entries by polarisation).
void full_contact_power(const ContactModel& m, LinearPhase& sys) {
  const Eigen::Index n = m.layout.n;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd e = zero, f = zero;
  sys.ground = Eigen::VectorXd::Zero(2 * n);
  sys.viscous = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    e.setZero();
    e[i] = 1;
    // Full contact has no pivot; at theta = theta' = 0 either pivot's power is -a_g 1'M u'.
    sys.ground[i] = ground_input_power(m.body, Pivot::right, 1.0, Coordinates{e, zero, Tilt(0.0), 0.0});
    sys.ground[n + i] = ground_input_power(m.body, Pivot::right, 1.0, Coordinates{zero, e, Tilt(0.0), 0.0});
    sys.viscous(n + i, n + i) = viscous_power(m.body, e);
  }
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = i + 1; j < n; ++j) {
      f.setZero();
      f[i] = f[j] = 1;
      const double v = 0.5 * (viscous_power(m.body, f) - sys.viscous(n + i, n + i) - sys.viscous(n + j, n + j));
      sys.viscous(n + i, n + j) = sys.viscous(n + j, n + i) = v;
    }
}
}  // namespace

LinearPhase full_contact_matrices(const ContactModel& m) {
  const Eigen::Index n = m.layout.n;
  if (!m.layout.u.present()) throw InputError("full_contact_matrices: a rigid block has no elastic coordinates");
  const StructuralMatrices& sm = m.body.matrices;
  const Eigen::VectorXd minus_inverse_mass = -m.body.structure.masses.cwiseInverse();
  LinearPhase sys;
  full_contact_power(m, sys);
  sys.first = m.layout.u.start;  // u_dot follows u
  sys.A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  sys.A.topRightCorner(n, n).setIdentity();
  if (m.body.coordinates == ElasticCoordinates::modal) {  // q'' = -(k q + c q') - r a_g
    const ModalBasis& md = m.body.modes;
    sys.A.bottomLeftCorner(n, n).diagonal() = -md.k;
    sys.A.bottomRightCorner(n, n).diagonal() = -md.c;
    sys.b = Eigen::VectorXd::Zero(2 * n);
    sys.b.tail(n) = -md.r;
    return sys;
  }
  sys.A.bottomLeftCorner(n, n) = minus_inverse_mass.asDiagonal() * sm.K;   // u'' = -M^-1 (K u + C u') - 1 a_g
  sys.A.bottomRightCorner(n, n) = minus_inverse_mass.asDiagonal() * sm.C;
  sys.b = Eigen::VectorXd::Zero(2 * n);
  sys.b.tail(n).setConstant(-1.0);
  return sys;
}

DamperState active_damper(const ContactModel& m, const Discrete& d, const Tilt& tilt,
                          Eigen::Ref<const Eigen::VectorXd> y) {
  const std::optional<Pivot> p = d.phase.pivot();
  if (!p) return {};
  const std::optional<std::size_t>& k = m.damper[index(*p)];
  if (!k) return {};
  const ContactModel::Acting& a = m.acting[index(*p)][*k];
  if (d.broken != 0 && d.is_broken(a.device)) return {};
  return a.state(a, d, m.body.structure.half_width, *p, tilt, theta_dot_of(m, y), y.data());
}

void phase_rhs(const ContactModel& m, const Discrete& d, GroundAcceleration a, const Eigen::Ref<const Eigen::VectorXd>& y,
               Eigen::Ref<Eigen::VectorXd> dydt) {
  const Layout& l = m.layout;
  const int s = d.phase.sign();
  const double B = m.body.structure.half_width;
  const Tilt tilt(theta_of(m, y));  // the only trig of the evaluation
  const double thd = theta_dot_of(m, y);
  // The devices this pivot stretches: their generalised moment sum F de/d|th|
  // (a chord device's as (F l) cos(th/2)), their state rates and their power.
  double device_moment = 0, damper_power = 0;
  if (s != 0) {
    const Pivot p = *d.phase.pivot();
    const std::size_t i = index(p);
    if (m.idle_slots[i])  // a slot this pivot leaves unused rests
      for (Eigen::Index k = 0; k < l.z.count; ++k) dydt[l.z.start + k] = 0.0;
    const bool split_work = l.energy.count > 3;
    if (split_work) std::fill(dydt.data() + l.energy.start + 3, dydt.data() + l.energy.start + l.energy.count, 0.0);
    const std::vector<ContactModel::Acting>& acting = m.acting[i];
    if (acting.size() == 1 && !split_work) {  // the paper's case: one damper per pivot
      const ContactModel::Acting& a = acting.front();
      const ContactModel::DeviceTerms t = a.terms(a, d, B, p, tilt, thd, y.data(), dydt.data());
      device_moment = t.moment;
      damper_power = t.power;
    } else {
      for (const ContactModel::Acting& a : acting) {
        const ContactModel::DeviceTerms t = a.terms(a, d, B, p, tilt, thd, y.data(), dydt.data());
        device_moment += t.moment;
        damper_power += t.power;
        if (split_work) dydt[l.energy.start + 3 + a.device] = t.power;
      }
    }
  }
  if (s != 0) {
    const Pivot p = *d.phase.pivot();
    dydt[l.theta.start] = thd;
    if (!l.u.present()) {
      dydt[l.theta_dot.start] = rigid_rocking_acceleration(m.body, p, a, device_moment, tilt);
    } else {
      const Coordinates q{y.segment(l.u.start, l.n), y.segment(l.u_dot.start, l.n), tilt, thd};
      dydt[l.theta_dot.start] = rocking_acceleration(m.body, p, a, device_moment, q, dydt.segment(l.u.start, 2 * l.n));
    }

  } else {
    if (l.theta.present())  // theta, theta', z, device work rest
      std::fill(dydt.data() + l.theta.start, dydt.data() + l.size, 0.0);
    if (l.u.present())
      full_contact_acceleration(m.body, a.h, y.segment(l.u.start, l.n), y.segment(l.u_dot.start, l.n), dydt.segment(l.u.start, 2 * l.n));
  }
  if (l.energy.present()) {
    double input = 0, viscous = 0;
    const Coordinates q{u_of(m, y), u_dot_of(m, y), tilt, thd};
    // Full contact has no pivot; at theta = theta' = 0 either pivot's power is -a_g 1'M u'.
    input = ground_input_power(m.body, s == 0 ? Pivot::right : *d.phase.pivot(), a, q);
    viscous = viscous_power(m.body, q.u_dot);
    dydt[l.energy.start] = input;
    dydt[l.energy.start + 1] = viscous;
    dydt[l.energy.start + 2] = damper_power;
  }
}

std::vector<PhaseGuard> phase_guards(const ContactModel& m, Phase phase) {
  if (m.kind == ModelKind::fixed_base) return {};
  const std::optional<Pivot> p = phase.pivot();
  if (!p) return {{Guard::uplift_right, Crossing::rising, {}}, {Guard::uplift_left, Crossing::rising, {}}};
  std::vector<PhaseGuard> out{{Guard::impact, Crossing::falling, {}}, {Guard::overturn, Crossing::rising, {}}};
  const auto& acting = m.acting[index(*p)];
  for (int i : m.breakable[index(*p)])
    out.push_back({Guard::fracture, Crossing::rising, acting[static_cast<std::size_t>(i)].device});
  return out;
}

void guard_values(const ContactModel& m, const Discrete& d, GroundAcceleration a, const Eigen::Ref<const Eigen::VectorXd>& y,
                  Eigen::Ref<Eigen::VectorXd> g) {
  if (m.kind == ModelKind::fixed_base) return;
  const std::optional<Pivot> p = d.phase.pivot();
  if (!p) {
    const UpliftTerms t = uplift_terms(m, a, y);
    g[0] = uplift_guard(m, d, Pivot::right, t);
    g[1] = uplift_guard(m, d, Pivot::left, t);
  } else {
    const double st = sign(*p) * y[m.layout.theta.start];
    g[0] = st;
    g[1] = st - m.overturn_angle;
    const auto& breakable = m.breakable[index(*p)];
    if (breakable.empty()) return;
    const Tilt tilt(y[m.layout.theta.start]);
    Eigen::Index k = 2;
    for (int i : breakable) {
      const ContactModel::Acting& a = m.acting[index(*p)][static_cast<std::size_t>(i)];
      g[k++] = d.is_broken(a.device) ? -1.0
                                     : stretch(a.geometry, m.body.structure.half_width, *p, tilt).e - a.capacity;
    }
  }
}

void fracture(Discrete& d, int device) {
  d.broken |= 1u << device;
  d.held_fresh_ = false;
}

void Discrete::refresh_held(const ContactModel& m) const {
  for (std::size_t i : {0, 1}) {
    double held = 0;
    for (const ContactModel::Acting& a : m.acting[i])
      if (!is_broken(a.device)) held += law_force_at_rest(a.law, z(a.device)) * a.lever;
    held_[i] = held;
  }
  held_fresh_ = true;
}

void device_samples(const ContactModel& m, const Discrete& d, Eigen::Ref<const Eigen::VectorXd> y,
                    std::vector<DeviceSample>& out) {
  out.assign(m.devices.size(), DeviceSample{});
  if (d.broken != 0)
    for (std::size_t k = 0; k < out.size(); ++k)
      if (d.is_broken(static_cast<int>(k))) out[k] = {std::nan(""), std::nan(""), 0.0};
  const std::optional<Pivot> p = d.phase.pivot();
  if (!p) return;
  const int s = sign(*p);
  const Tilt tilt(y[m.layout.theta.start]);
  const double thd = y[m.layout.theta_dot.start];
  for (const ContactModel::Acting& a : m.acting[index(*p)]) {
    if (d.broken != 0 && d.is_broken(a.device)) continue;
    const DamperState n = a.state(a, d, m.body.structure.half_width, *p, tilt, thd, y.data());
    const double de_dtheta = stretch(a.geometry, m.body.structure.half_width, *p, tilt).de_dtheta;
    out[static_cast<std::size_t>(a.device)] = {n.elongation, n.force, s * n.force * de_dtheta};
  }
}

GuardInputs guard_inputs(const ContactModel& m, Phase phase, bool vertical_shaking) {
  const bool uplift = !phase.is_rocking() && m.kind != ModelKind::fixed_base;
  return {.horizontal = uplift && m.kind == ModelKind::rigid_block, .vertical = uplift && vertical_shaking};
}

std::optional<Pivot> uplift_now(const ContactModel& m, const Discrete& d, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y) {
  if (m.kind == ModelKind::fixed_base) return std::nullopt;
  const UpliftTerms t = uplift_terms(m, a, y);
  for (Pivot p : pivots)
    if (uplift_guard(m, d, p, t) > 0) return p;
  return std::nullopt;
}

namespace {
// The states of the devices pivot p stretches, from the discrete state into
// their slots, or back.
void load_states(const ContactModel& m, const Discrete& d, Pivot p, Eigen::Ref<Eigen::VectorXd> y) {
  for (const ContactModel::Acting& a : m.acting[index(p)])
    if (a.slot) y[*a.slot] = d.z(a.device);
}
void save_states(const ContactModel& m, Discrete& d, Pivot p, Eigen::Ref<const Eigen::VectorXd> y) {
  for (const ContactModel::Acting& a : m.acting[index(p)])
    if (a.slot) d.set_z(a.device, y[*a.slot]);
}
}  // namespace

void begin_rocking(const ContactModel& m, Discrete& d, Pivot p, Eigen::Ref<Eigen::VectorXd> y) {
  d.phase = Phase::rocking(p);
  d.last_pivot = p;
  y[m.layout.theta.start] = 0.0;
  y[m.layout.theta_dot.start] = 0.0;
  load_states(m, d, p, y);
}

ImpactResult impact(const ContactModel& m, Discrete& d, Eigen::Ref<Eigen::VectorXd> y) {
  const Layout& l = m.layout;
  const Structure& st = m.body.structure;
  const Pivot p = *d.phase.pivot();
  const int s = sign(p);
  const double B = st.half_width, theta_dot = y[l.theta_dot.start];
  save_states(m, d, p, y);  // the stretched devices keep their z for their next cycle
  y[l.theta.start] = 0.0;
  // L_new = (J_p - 2 (1'M1 + m0) B^2 + u'Mu) th'- + H'M u' (momentum about the new pivot)
  const double uMu = mass_norm(m.body, u_of(m, y));
  const double l_new = (pivot_inertia(st) - 2.0 * total_mass(st) * B * B + uMu) * theta_dot +
                       moment_of_velocities(m, y);
  ImpactResult out;
  out.continues = -s * l_new >= 0 && std::abs(theta_dot) > m.contact.theta_dot_min;
  if (out.continues) {
    out.r = restitution(m, p, y, l_new, theta_dot);
    y[l.theta_dot.start] = out.r * theta_dot;
    d.phase = Phase::rocking(opposite(p));
    d.last_pivot = opposite(p);
    load_states(m, d, opposite(p), y);
  } else {
    if (l.u.present()) y.segment(l.u_dot.start, l.n) += heights_in_coordinates(m.body) * theta_dot;
    y[l.theta_dot.start] = 0.0;
    d.phase = Phase::full_contact();
  }
  return out;
}

double mechanical_energy(const ContactModel& m, Phase phase, Eigen::Ref<const Eigen::VectorXd> y) {
  // Full contact has no pivot; at theta = 0 the energy about either pivot is the same.
  const Pivot p = phase.is_rocking() ? *phase.pivot() : Pivot::right;
  const Coordinates q{u_of(m, y), u_dot_of(m, y), Tilt(theta_of(m, y)), theta_dot_of(m, y)};
  return mechanical_energy(m.body, p, q);
}

void view(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y, StateView& out) {
  out.u.resize(m.zero_motion.size());
  out.u_dot.resize(m.zero_motion.size());
  to_nodal(m.body, u_of(m, y), out.u);
  to_nodal(m.body, u_dot_of(m, y), out.u_dot);
  out.theta = theta_of(m, y);
  out.theta_dot = theta_dot_of(m, y);
}

}  // namespace rocking
