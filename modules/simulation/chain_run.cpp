// The run of a structure that rocks at more than one level (MODEL.md 15):
// the chain's equations (rocking.chain) integrated by the same backends
// (rocking.integrator, rocking.sundials) and reported through the same
// observers, events, peaks and energy balance as the one-joint structure's
// (simulation.cpp). The phase is one per joint. Guards, per joint j:
// - closed: uplift about s when the resultant reaches the corner and the
//   corner's relative acceleration points away from the face,
//   min(s M_j - N_j B_j, s theta_j''), rising (Eq. 2/3 for the base);
// - rocking about s: impact, s theta_j falling through 0; overturning, s
//   theta_j rising through the slenderness of everything above the joint;
// - any phase: tension, N_j falling through 0, the outcome `separated` (the
//   part above would leave the joint: the model's end, stated); with a stated
//   friction limit mu_j, mu_j N_j - |V_j| falling through 0, which ends the
//   run as failed. Neither is ever continued.
// Resets: uplift (theta_j = theta_j' = 0, already so); impact by the momentum
// law of MODEL.md 15 (chain_impact: impact-induced uplift of other joints is
// an event; an outcome that is not unique, or none, ends the run, stated) or
// a given r (theta_j'+ = r theta_j'-, the rest continuous); an impact slower
// than contact.theta_dot_min closes the joint by the momentum law into full
// contact (Eq. 8's threshold, which acts only when the motion dies out).
// Devices: the chain's tendons (rocking.chain: forces in its equations and
// reactions) and the devices across one joint, the base or one above, as on
// a one-joint structure (MODEL.md 11 in that joint's frame, rocking.contact's
// acting devices of a rigid block on a base of the joint's half-width): while
// joint j rocks about s they exert the generalised force -s D on theta_j
// (D = sum F de/d|theta_j|; their elongation depends on theta_j alone), their
// states z integrated, their fractures located events; while it is closed
// they rest, keeping their states for the next uplift about the same side,
// and hold D_0(s) against uplift about s (the moment condition less D_0, the
// corner's acceleration less D_0 over the inertia about the corner).
// The state is [q, q', z of each joint's devices, W_ground, W_viscous,
// W_devices, the work on each device across a joint]: the works are
// integrals that do not steer the steps. The mechanical energy is kinetic +
// gravity + elastic; the tendons' stored energy and the joint devices' work
// are the work done on the devices.
// The devices' moment M_dev is not computed.
// contact.rocking = false holds the base joint closed (a fixed base): the
// joints above still rock.
// With every joint closed under a piecewise-linear record (no vertical
// shaking, no tendons), the chain is stepped as its linearisation about rest
// (rocking.chain's chain_at_rest: MODEL.md 3's form with the P-delta of the
// segments above a turning face), exactly from sample to sample as the
// one-joint structure's full contact is (RunOptions::exact_full_contact;
// --integrate-contact integrates the nonlinear equations instead). Its guards
// are the nonlinear reactions' wherever a term lies within its margin of its
// threshold, the first-order reactions' elsewhere (docs/chain.md).
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <map>
module rocking.simulation;
import :peaks;
import :record_steps;
import rocking.errors;

namespace rocking {

double JointSample::friction() const { return N > 0 ? std::abs(V) / N : std::numeric_limits<double>::infinity(); }

namespace {

enum class ChainGuard { uplift, impact, overturn, tension, friction, fracture };

struct ChainGuardDef {
  ChainGuard what = ChainGuard::uplift;
  int joint = 0;
  Pivot pivot = Pivot::right;
  int acting = 0;  // a fracture guard's device across the joint, by its place in the pivot's acting list
};

// The states z of a joint's devices: the slots after theta and theta' that
// the model's acting devices use (a rigid block's, rocking.scene).
Eigen::Index device_states(const ContactModel& m) {
  Eigen::Index end = 2;
  for (const auto& acting : m.acting)
    for (const ContactModel::Acting& a : acting)
      if (a.slot) end = std::max(end, *a.slot + 1);
  return end - 2;
}

class ChainDriver {
 public:
  ChainDriver(const ContactModel& m, const GroundMotion& ground, const RunOptions& o, Observer* observer)
      : m_(m), jm_(*m.jointed), c_(jm_.chain), ground_(ground), vertical_(ground.vertical()), opt_(o),
        observer_(observer), scales_(output_scales(m)), w_(make_workspace(c_)), n_(c_.size),
        phases_(static_cast<std::size_t>(c_.joints)), reactions_(static_cast<std::size_t>(c_.joints)),
        samples_(static_cast<std::size_t>(c_.joints)), nb_(jm_.joint_devices()), z_(2 * n_),
        work_(z_ + make_groups()), size_(work_ + 3 + static_cast<Eigen::Index>(nb_)),
        y_(Eigen::VectorXd::Zero(size_)), dense_(size_), qdd_(n_), elongation_(c_.data.tendons.size(), 0.0),
        device_samples_(m.devices.size()) {
    auto rhs = [this](double t, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& dydt) {
      derivatives(t, y, dydt);
    };
    // The one-joint structure's choice (choose_backend: rosw when the fixed-base
    // modes would hold rk45's steps far below the record's), and rosw solves
    // with the stiff elastic part of the current phases. Unlike a one-joint
    // structure's, an automatic rosw keeps the exact closed steps below.
    const ode::Backend backend = choose_backend(m, ground, o.backend);
    ode::LinearSolve stiff;
    if (backend == ode::Backend::rosw && n_ > c_.joints) {
      stiff_ = std::make_unique<ChainStiff>(c_);
      stiff = [this](double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x) {
        stiff_->solve(phases_, g, b, x);
      };
    }
    integrator_ = motion_integrator(backend, ground, size_, rhs, motion_tolerances(o, ground, work_), std::move(stiff));
    t_end_ = run_end(o, ground);
    // Every joint closed under a piecewise-linear record (no vertical
    // shaking, no tendons: their forces are not linear): the chain
    // linearised about rest, stepped exactly from sample to sample.
    if (o.exact_full_contact && n_ > c_.joints && c_.data.tendons.empty() && vertical_ == nullptr &&
        ground.piecewise_linear())
      exact_ = closed_steps(o);
    if (exact_) {
      linearise_reactions();
      set_margins();
    }
    active_ = integrator_.get();
    // The top node's local height on its segment: delta_t is its horizontal displacement over H_N.
    const ChainSegment& top = c_.data.segments.back();
    top_ = {.segment = c_.joints - 1, .x = 0.0, .z = top.heights[top.heights.size() - 1] - top.base_height,
            .node = top.rigid ? -1 : static_cast<int>(top.heights.size()) - 1};
  }

  RunResult run() {
    result_.integrator = integrator_->name();
    result_.exact_full_contact = exact_ != nullptr;
    result_.presence = presence(m_);
    result_.energy_tracked = true;
    result_.joints.resize(static_cast<std::size_t>(c_.joints));
    // The devices across each joint, then the chain's tendons, in the model's order.
    for (const Device& dev : m_.devices)
      result_.devices.push_back({.name = dev.name, .law = law_name(dev.law), .force_at_rest = law_force_at_rest(dev.law, 0.0),
                                 .work = 0.0});
    initial_state();
    tendons_initial_ = energy().tendons;
    // Each tendon's stored energy at the start: its work counts from there.
    for (std::size_t k = 0; k < c_.data.tendons.size(); ++k)
      tendon_start_.push_back(
          tendon_stored(k, tendon_elongation(c_, phases_, static_cast<int>(k), y_.head(n_), w_)));
    result_.energy.initial = mechanical();
    run_stated(
        result_,
        [this] {
          take_resting();
          for (int j = 0; j < c_.joints; ++j) lift_if_lifting(j, 0.0);
          restart(0.0);
          if (separated_at(0.0)) return;
          for (int j = 0; j < c_.joints; ++j)
            if (phases_[j].is_rocking() && sign(*phases_[j].pivot()) * y_[j] >= jm_.overturn_angle[j]) {
              announce({EventKind::overturn, 0.0, *phases_[j].pivot(), std::nullopt, j});
              result_.outcome = Outcome::overturned;
            }
          if (result_.outcome != Outcome::overturned) loop();
        },
        [this] { return fmt::format("phases {}", phases_text()); });
    finish();
    return result_;
  }

 private:
  GroundAcceleration ground_at(double t) const { return rocking::ground_at(ground_, vertical_, t); }

  // A closed joint's theta and theta' are 0: the exact steps' eigen form
  // leaves round-off (of 1e-16 of the elastic state) in the rates it carries.
  void closed_at_rest(Eigen::Ref<Eigen::VectorXd> y) const {
    for (int j = 0; j < c_.joints; ++j)
      if (!phases_[j].is_rocking()) y[j] = y[n_ + j] = 0.0;
  }

  // The phase with every joint closed as MODEL.md 3's linear system: the
  // chain linearised about rest (chain_at_rest: M x'' + C x' + K x = f a_g on
  // the elastic coordinates x, K with gravity's P-delta of the segments above
  // a turning face), stepped exactly under the record's piecewise-linear
  // acceleration (ode::make_exact_linear) on the block y[J, 2n) of the state:
  // x, the joints' rates theta' (0 while closed: rows -theta', which keep them
  // at 0) and x'. The ground's and the viscous work are its quadratures,
  // a_g f'x' and x'C x'. Guards and peaks are sampled 8 times in the shortest
  // period of its modes that oscillate; the guards are the nonlinear chain's
  // (chain_reactions) at the states the steps reach. Null when M is singular
  // (a face turning with no mass above it).
  std::unique_ptr<ode::Integrator> closed_steps(const RunOptions& o) {
    const ChainAtRest lin = chain_at_rest(c_);
    const int J = c_.joints, ne = n_ - J;
    const Eigen::LLT<Eigen::MatrixXd> llt(lin.M);
    if (llt.info() != Eigen::Success) return nullptr;
    const Eigen::Index m = 2 * n_ - J, v = ne + J;  // the block's size, and where x' starts in it
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, m);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
    A.block(0, v, ne, ne).setIdentity();
    A.block(v, 0, ne, ne) = -llt.solve(lin.K);
    A.block(v, v, ne, ne) = -llt.solve(lin.C);
    b.segment(v, ne) = llt.solve(lin.f);
    for (int j = 0; j < J; ++j) A(ne + j, ne + j) = -1.0;
    Eigen::MatrixXd elastic(2 * ne, 2 * ne);  // A on (x, x') alone
    elastic << A.block(0, 0, ne, ne), A.block(0, v, ne, ne), A.block(v, 0, ne, ne), A.block(v, v, ne, ne);
    const Eigen::VectorXcd modes = Eigen::EigenSolver<Eigen::MatrixXd>(elastic, false).eigenvalues();
    double fastest = 0, largest = 0;
    for (const std::complex<double>& l : modes) {
      fastest = std::max(fastest, std::abs(l.imag()));
      largest = std::max(largest, std::abs(l));
    }
    Eigen::VectorXd c = Eigen::VectorXd::Zero(m);
    c.segment(v, ne) = lin.f;
    Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(m, m);
    Q.block(v, v, ne, ne) = lin.C;
    ode::LinearSystem system{size_, J, std::move(A), std::move(b), [this](double t) { return ground_.acceleration(t); }, {}};
    system.quadratures.push_back({work_, Eigen::MatrixXd(), std::move(c)});
    system.quadratures.push_back({work_ + 1, std::move(Q), Eigen::VectorXd()});
    ode::Options exact;
    exact.sample_spacing = 2 * std::numbers::pi / (fastest > 0 ? fastest : largest) / 8;
    exact.max_steps = o.tolerances.max_steps;
    std::unique_ptr<ode::Integrator> steps = ode::make_exact_linear(std::move(system), exact);
    steps->set_breakpoints(record_samples(ground_));
    return steps;
  }

  void derivatives(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> dydt) {
    const GroundAcceleration a = ground_at(t);
    const auto q = y.head(n_), qd = y.segment(n_, n_);
    apply_devices(y, true);
    ChainPower p;
    chain_acceleration(c_, phases_, a, q, qd, dydt.segment(n_, n_), w_, &p);
    dydt.head(n_) = qd;
    for (int j = 0; j < c_.joints; ++j)
      if (!phases_[j].is_rocking()) dydt[j] = 0;  // a closed joint's theta stays 0
    // The devices' states rest unless the pivot's acting devices write theirs.
    dydt[work_] = p.ground;
    dydt[work_ + 1] = p.damping;
    double total = 0;
    for (const JointDevices& g : groups_) {
      dydt.segment(g.z, g.states) = g.rates.segment(2, g.states);
      for (std::size_t k = 0; k < g.devices.size(); ++k) {
        dydt[work_ + 3 + static_cast<Eigen::Index>(g.devices[k])] = g.power[k];
        total += g.power[k];
      }
    }
    dydt[work_ + 2] = total;
  }

  // The devices across one joint: held as a rigid block on a base of the
  // joint's half-width holds them (`model`: its acting and breakable lists,
  // its device numbers local), their states z in y from `z` (slot 2 there),
  // [theta_j, theta_j', z] their view of the state and its rates.
  struct JointDevices {
    int joint = 0;
    const ContactModel* model = nullptr;
    std::vector<std::size_t> devices;  // local number -> place in the model's devices (and the results')
    Eigen::Index z = 0, states = 0;
    Discrete discrete;  // the joint's phase for its devices, their states kept, their fractures
    Eigen::VectorXd block, rates;
    std::vector<double> power;  // on each device [W]
  };

  // The joints' device groups (the base's from the model itself, those above
  // from JointedModel::upper), their states laid out from z_; returns the
  // number of states.
  Eigen::Index make_groups() {
    group_of_.assign(static_cast<std::size_t>(c_.joints), -1);
    Eigen::Index next = z_;
    const auto add = [&](int joint, const ContactModel& model, std::vector<std::size_t> devices) {
      JointDevices g;
      g.joint = joint;
      g.model = &model;
      g.devices = std::move(devices);
      g.z = next;
      g.states = device_states(model);
      next += g.states;
      g.block = Eigen::VectorXd::Zero(2 + g.states);
      g.rates = Eigen::VectorXd::Zero(2 + g.states);
      g.power.assign(g.devices.size(), 0.0);
      group_of_[static_cast<std::size_t>(joint)] = static_cast<int>(groups_.size());
      for (std::size_t k = 0; k < g.devices.size(); ++k) where_.push_back({groups_.size(), k});
      groups_.push_back(std::move(g));
    };
    if (jm_.base_devices > 0) {
      std::vector<std::size_t> base(jm_.base_devices);
      for (std::size_t k = 0; k < base.size(); ++k) base[k] = k;
      add(0, m_, std::move(base));
    }
    for (const JointedModel::UpperDevices& u : jm_.upper) add(u.joint, *u.block, u.devices);
    return next - z_;
  }
  const JointDevices* group_at(int j) const {
    const int g = group_of_[static_cast<std::size_t>(j)];
    return g < 0 ? nullptr : &groups_[static_cast<std::size_t>(g)];
  }
  JointDevices* group_at(int j) {
    const int g = group_of_[static_cast<std::size_t>(j)];
    return g < 0 ? nullptr : &groups_[static_cast<std::size_t>(g)];
  }
  // Whether device k (a place in the model's devices, across a joint) has broken.
  bool broken(std::size_t k) const {
    const auto [g, local] = where_[k];
    return groups_[g].discrete.is_broken(static_cast<int>(local));
  }
  // [theta_j, theta_j', z] of group g from the state y.
  void load_block(JointDevices& g, Eigen::Ref<const Eigen::VectorXd> y) const {
    g.block[0] = y[g.joint];
    g.block[1] = y[n_ + g.joint];
    g.block.tail(g.states) = y.segment(g.z, g.states);
  }
  const std::vector<ContactModel::Acting>& acting(const JointDevices& g) const {
    return g.model->acting[index(*phases_[g.joint].pivot())];
  }

  // Each joint's devices' generalised force on its theta into the workspace
  // (-s D while the joint rocks about s, else 0), from the state y; with
  // `rates`, their states' rates into the group's rates and each one's power.
  void apply_devices(Eigen::Ref<const Eigen::VectorXd> y, bool rates) {
    for (JointDevices& g : groups_) {
      const int j = g.joint;
      w_.applied[j] = 0.0;
      if (rates) {
        g.rates.setZero();
        std::fill(g.power.begin(), g.power.end(), 0.0);
      }
      if (!phases_[j].is_rocking()) continue;
      load_block(g, y);
      const Pivot p = *phases_[j].pivot();
      const int s = sign(p);
      const Tilt tilt(y[j]);
      double moment = 0;
      for (const ContactModel::Acting& a : acting(g)) {
        const ContactModel::DeviceTerms dt =
            a.terms(a, g.discrete, half_width(j), p, tilt, y[n_ + j], g.block.data(), g.rates.data());
        moment += dt.moment;
        if (rates) g.power[static_cast<std::size_t>(a.device)] = dt.power;
      }
      w_.applied[j] = -s * moment;
    }
  }

  double half_width(int j) const { return c_.data.segments[static_cast<std::size_t>(j)].half_width; }
  // The moment the intact devices across joint j hold against uplift about p at rest.
  double held(int j, Pivot p) const { return resting_[static_cast<std::size_t>(j)].held[index(p)]; }

  // What the intact devices across each joint do while it is closed, from
  // the states they keep: the moment they hold against uplift about each
  // pivot (held_moment) and the pull their forces at rest add to its N.
  // Both change only at events (a kept state, a break), so they are taken
  // there (restart, and before the uplift checks at the start and after an
  // impact) and read by every guard evaluation.
  struct Resting {
    std::array<double, 2> held{};  // left, right (rocking.geometry's index)
    double pull = 0;
  };
  void take_resting() {
    for (int j = 0; j < c_.joints; ++j) {
      Resting& r = resting_[static_cast<std::size_t>(j)];
      r = {};
      const JointDevices* g = group_at(j);
      if (g == nullptr) continue;
      for (Pivot p : pivots) r.held[index(p)] = held_moment(*g->model, g->discrete, p);
      for (std::size_t k = 0; k < g->devices.size(); ++k)
        if (!g->discrete.is_broken(static_cast<int>(k)))
          r.pull += law_force_at_rest(g->model->devices[k].law, g->discrete.z(static_cast<int>(k)));
    }
  }

  // Joint j's contact reaction: the multipliers' N and V, with the pull of
  // the devices across it, which the chain applies on theta_j alone (the
  // moment condition holds it as D_0): the contact carries it as well. A
  // device from the face below at (x, 0) to the anchor above pulls along its
  // chord, at |theta_j| / 2 from the face's normal toward the pivot's side
  // (MODEL.md 11), or along that normal (kinematics vertical); at rest each
  // intact device pulls down with its force at rest. (Across the joints
  // below, the pair of forces is internal to the part above: no change.)
  JointReaction contact_reaction(int j, Eigen::Ref<const Eigen::VectorXd> y) {
    JointReaction r = reactions_[j];
    const JointDevices* g = group_at(j);
    if (g == nullptr) return r;
    if (!phases_[j].is_rocking()) {
      r.N += resting_[static_cast<std::size_t>(j)].pull;
      return r;
    }
    sample_devices(y);
    const double half = 0.5 * std::abs(y[j]), s = phases_[j].sign();
    for (const ContactModel::Acting& a : acting(*g)) {
      if (g->discrete.is_broken(a.device)) continue;
      const double F = device_samples_[g->devices[static_cast<std::size_t>(a.device)]].F;
      const bool chord = a.geometry.kinematics == Kinematics::chord;
      r.N += chord ? F * std::cos(half) : F;
      r.V += chord ? s * F * std::sin(half) : 0.0;
    }
    return r;
  }

  // A joint's devices follow its phase: the acting devices of a new rocking
  // phase resume the states they kept (keep_device_states).
  void phase_set(int j) {
    JointDevices* g = group_at(j);
    if (g == nullptr) return;
    g->discrete.phase = phases_[j];
    if (!phases_[j].is_rocking()) return;
    for (const ContactModel::Acting& a : acting(*g))
      if (a.slot) y_[g->z + *a.slot - 2] = g->discrete.z(a.device);
  }
  void phases_set() {
    for (int j = 0; j < c_.joints; ++j) phase_set(j);
  }
  void keep_device_states() {
    for (JointDevices& g : groups_) {
      if (!phases_[g.joint].is_rocking()) continue;
      for (const ContactModel::Acting& a : acting(g))
        if (a.slot) g.discrete.set_z(a.device, y_[g.z + *a.slot - 2]);
    }
  }

  std::string phases_text() const {
    std::string out;
    for (int j = 0; j < c_.joints; ++j) out += fmt::format("{}{}", j == 0 ? "" : ", ", phase_name(phases_[j]));
    return out;
  }

  void initial_state() {
    const InitialState& init = opt_.initial;
    if (init.u.size() > 0 || init.u_dot.size() > 0)
      throw InputError("initial u, u_dot: a structure with joints starts with its elastic displacements at zero");
    for (int j = 0; j < c_.joints; ++j) {
      const double theta = j == 0 ? init.theta : jm_.initial_theta[j];
      const double rate = j == 0 ? init.theta_dot : 0.0;
      if (theta == 0 && rate == 0) continue;
      phases_[j] = Phase::rocking(theta > 0 || (theta == 0 && rate > 0) ? Pivot::right : Pivot::left);
      y_[j] = theta;
      y_[n_ + j] = rate;
    }
    phases_set();
  }

  ChainEnergy energy() { return chain_energy(c_, phases_, y_.head(n_), y_.segment(n_, n_), w_); }
  double mechanical() {
    const ChainEnergy e = energy();
    return e.kinetic + e.gravity + e.elastic;
  }

  // Closed joint j lifts now (at the start or after an impact) when both
  // uplift conditions already hold about one of its corners.
  void lift_if_lifting(int j, double t) {
    if (phases_[j].is_rocking() || (j == 0 && !jm_.base_rocks())) return;
    const GroundAcceleration a = ground_at(t);
    const auto q = y_.head(n_), qd = y_.segment(n_, n_);
    apply_devices(y_, false);
    chain_reactions(c_, phases_, a, q, qd, reactions_, qdd_, w_, corners_);
    for (Pivot s : pivots)
      if (lift_moment(j, s) > 0 && lift_acceleration(j, s) > 0) {
        lift(j, s, t);
        return;
      }
  }

  // Closed joint j's uplift conditions about s from the last reactions: the
  // resultant past the corner, and the corner's relative acceleration away
  // from the face, each less the held moment of the devices across it.
  double lift_moment(int j, Pivot s) const { return uplift_guard(c_, j, s, reactions_[j]) - held(j, s); }
  double lift_acceleration(int j, Pivot s) const { return corners_[j][s] + held(j, s) * corners_[j].gain(s); }

  // The uplift guard: both conditions in one value, their min. In the exact
  // closed phase the moment's is taken over the inertia about the corner
  // (-1 / gain, > 0), so that both are angular accelerations: a positive
  // scale keeps its sign, so the event is the same, and in the same units
  // the two terms nearly coincide where they cross (for a rigid block they
  // are the same moment about the corner), so that the min has no kink there
  // by a factor of that inertia, across which the event search's secant
  // steps creep, each step a solve of the nonlinear reactions. The phases
  // the backend integrates take the moment as it is, their event times
  // unchanged to the bit (docs/chain.md).
  double uplift_value(std::size_t k) const {
    const Lift& l = lifts_[k];
    return std::min(active_ == exact_.get() ? l.scale * l.moment : l.moment, l.acceleration);
  }

  // The terms the guards compare, from the reactions now in reactions_ and
  // corners_ at state y, once for each evaluation: each joint's contact
  // reaction (contacts_) and each uplift guard's two conditions (lifts_).
  struct Lift {
    double moment = 0, acceleration = 0, scale = 0;  // scale: -gain, 1 / the inertia about the corner
  };
  void guard_terms(Eigen::Ref<const Eigen::VectorXd> y) {
    for (int j = 0; j < c_.joints; ++j) contacts_[j] = contact_reaction(j, y);
    for (std::size_t k = 0; k < guards_.size(); ++k) {
      const ChainGuardDef& d = guards_[k];
      if (d.what == ChainGuard::uplift)
        lifts_[k] = {lift_moment(d.joint, d.pivot), lift_acceleration(d.joint, d.pivot), -corners_[d.joint].gain(d.pivot)};
    }
  }

  void lift(int j, Pivot s, double t) {
    phases_[j] = Phase::rocking(s);
    y_[j] = 0;
    y_[n_ + j] = 0;
    phase_set(j);
    JointResult& r = result_.joints[j];
    if (r.uplifts++ == 0) r.first_uplift = t;
    if (result_.counts.uplifts++ == 0) result_.first_uplift = t;
    announce({EventKind::uplift, t, s, std::nullopt, j});
  }

  void announce(const Event& e) {
    if (observer_ != nullptr) observer_->event(e);
  }

  // The reactions of the guards' last few states (the steps' guard samples
  // are the states sample_step then tracks), keyed by t and the whole state,
  // and forgotten when the phases change (restart).
  struct Remembered {
    double t = 0;
    Eigen::VectorXd y;
    std::vector<JointReaction> reactions, contacts;
  };
  void remember(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    Remembered& r = remembered_[next_remembered_];
    next_remembered_ = (next_remembered_ + 1) % remembered_.size();
    r.t = t;
    r.y = y;
    r.reactions.assign(reactions_.begin(), reactions_.end());
    r.contacts.assign(contacts_.begin(), contacts_.end());
    held_ = std::min(held_ + 1, remembered_.size());
  }
  bool recall(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    for (std::size_t k = 0; k < held_; ++k) {
      const Remembered& r = remembered_[k];
      if (r.t == t && r.y == y) {
        std::copy(r.reactions.begin(), r.reactions.end(), reactions_.begin());
        std::copy(r.contacts.begin(), r.contacts.end(), contacts_.begin());
        return true;
      }
    }
    return false;
  }

  void restart(double t) {
    take_resting();
    held_ = next_remembered_ = 0;
    guards_.clear();
    std::vector<ode::Direction> directions;
    for (int j = 0; j < c_.joints; ++j) {
      if (phases_[j].is_rocking()) {
        guards_.push_back({ChainGuard::impact, j, *phases_[j].pivot()});
        directions.push_back(ode::Direction::falling);
        guards_.push_back({ChainGuard::overturn, j, *phases_[j].pivot()});
        directions.push_back(ode::Direction::rising);
      } else if (j > 0 || jm_.base_rocks()) {
        for (Pivot s : pivots) {
          guards_.push_back({ChainGuard::uplift, j, s});
          directions.push_back(ode::Direction::rising);
        }
      }
      if (j == 0 && !jm_.base_rocks()) continue;  // a fixed base holds the structure down: no tension, no sliding
      guards_.push_back({ChainGuard::tension, j});
      directions.push_back(ode::Direction::falling);
      if (std::isfinite(jm_.friction_limit[j])) {
        guards_.push_back({ChainGuard::friction, j});
        directions.push_back(ode::Direction::falling);
      }
    }
    for (const JointDevices& g : groups_)  // the devices across a rocking joint that can break: at their capacity
      if (phases_[g.joint].is_rocking())
        for (int k : g.model->breakable[index(*phases_[g.joint].pivot())]) {
          guards_.push_back({ChainGuard::fracture, g.joint, *phases_[g.joint].pivot(), k});
          directions.push_back(ode::Direction::rising);
        }
    lifts_.assign(guards_.size(), {});
    ode::Guards guards{[this](double tg, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& g) {
                         guard_values(tg, y, g);
                       },
                       std::move(directions)};
    active_ = exact_ && std::none_of(phases_.begin(), phases_.end(), [](const Phase& p) { return p.is_rocking(); })
                  ? exact_.get()
                  : integrator_.get();
    active_->reset(t, y_, std::move(guards));
    emit(t, y_, true);
  }

  // The closed phase's reactions and corner accelerations to first order in
  // the state and a_g (N, V, M, the corners' accelerations and gains of each
  // joint: 7 rows per joint), from the nonlinear ones by central differences
  // about rest (exact for the linear part up to round-off: the even terms cancel).
  void linearise_reactions() {
    const int J = c_.joints, rows = 7 * J;
    const std::vector<Phase> closed(static_cast<std::size_t>(J));
    Eigen::VectorXd y = Eigen::VectorXd::Zero(2 * n_), plus(rows), minus(rows);
    auto eval = [&](double ag, Eigen::VectorXd& out) {
      chain_reactions(c_, closed, GroundAcceleration{ag}, y.head(n_), y.tail(n_), reactions_, qdd_, w_, corners_);
      for (int j = 0; j < J; ++j)
        out.segment(7 * j, 7) << reactions_[j].N, reactions_[j].V, reactions_[j].M, corners_[j].left, corners_[j].right,
            corners_[j].left_gain, corners_[j].right_gain;
    };
    linear_.r0.resize(rows);
    eval(0.0, linear_.r0);
    linear_.columns.clear();
    for (int k = 0; k < 2 * n_; ++k)
      if (k % n_ >= J) linear_.columns.push_back(k);  // not the joints' theta and theta', 0 while closed
    Eigen::MatrixXd R(rows, static_cast<Eigen::Index>(linear_.columns.size()));  // on the state's entries `columns`
    for (std::size_t i = 0; i < linear_.columns.size(); ++i) {
      const int k = linear_.columns[i];
      constexpr double h = 1e-6;  // [m, rad, m/s, rad/s]
      y[k] = h;
      eval(0.0, plus);
      y[k] = -h;
      eval(0.0, minus);
      y[k] = 0.0;
      R.col(static_cast<Eigen::Index>(i)) = (plus - minus) / (2 * h);
    }
    constexpr double h = 1e-3;  // [m/s^2]
    eval(h, plus);
    eval(-h, minus);
    const Eigen::VectorXd ra = (plus - minus) / (2 * h);
    linear_.values.resize(rows);
    const std::size_t nc = linear_.columns.size();
    linear_.packed.assign(static_cast<std::size_t>(J) * 8 * (2 + nc), 0.0);
    double* p = linear_.packed.data();
    for (int j = 0; j < J; ++j, p += 8 * (2 + nc))
      for (int r = 0; r < 7; ++r) {
        p[r] = linear_.r0[7 * j + r];
        p[8 + r] = ra[7 * j + r];
        for (std::size_t k = 0; k < nc; ++k) p[8 * (2 + k) + r] = R(7 * j + r, static_cast<Eigen::Index>(k));
      }
  }

  // The closed phase's reactions to first order into reactions_ and corners_:
  // r0 + ra a_g + R y over the elastic coordinates and rates (`columns`: the
  // joints' are 0 while closed). A joint's 7 rows go as one vector of 8
  // lanes, a column at a time (`packed`: per joint, r0, ra, then each
  // column's rows, each padded to 8), so that its sums run side by side.
  void linear_reactions(double ag, Eigen::Ref<const Eigen::VectorXd> y) {
    const std::size_t nc = linear_.columns.size();
    double* v = linear_.values.data();
    const double* p = linear_.packed.data();
    for (int j = 0; j < c_.joints; ++j, v += 7) {
      double acc[8];
      for (int r = 0; r < 8; ++r) acc[r] = p[r] + p[8 + r] * ag;
      p += 16;
      for (std::size_t k = 0; k < nc; ++k, p += 8) {
        const double x = y[linear_.columns[k]];
        for (int r = 0; r < 8; ++r) acc[r] += p[r] * x;
      }
      for (int r = 0; r < 7; ++r) v[r] = acc[r];
    }
    v = linear_.values.data();
    for (int j = 0; j < c_.joints; ++j) {
      const double* r = v + 7 * j;
      reactions_[j] = {r[0], r[1], r[2]};
      corners_[j] = {r[3], r[4], r[5], r[6]};
    }
  }

  // Whether guard k's sign could differ between the first-order reactions
  // (their terms in contacts_ and lifts_) and the nonlinear ones: one of the
  // terms it compares with 0 lies within its margin of 0.
  bool near_threshold(std::size_t k) const {
    const ChainGuardDef& d = guards_[k];
    const int j = d.joint;
    const Margins& m = linear_.margins[static_cast<std::size_t>(j)];
    switch (d.what) {
      case ChainGuard::uplift: {
        const double a = lifts_[k].moment, b = lifts_[k].acceleration;
        const double ma = m.moment, mb = m.corner[index(d.pivot)];
        return a > -ma && b > -mb && (a < ma || b < mb);
      }
      case ChainGuard::tension: return std::abs(contacts_[j].N) < m.normal;
      case ChainGuard::friction: {
        const JointReaction& c = contacts_[j];
        return std::abs(jm_.friction_limit[j] * c.N - std::abs(c.V)) < jm_.friction_limit[j] * m.normal;
      }
      default: return true;
    }
  }

  void guard_values(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> g) {
    const GroundAcceleration a = ground_at(t);
    const auto q = y.head(n_), qd = y.segment(n_, n_);
    bool near = true;
    if (active_ == exact_.get() && linear_.trusted) {
      // Every joint closed, stepped as the linearisation: the guards from the
      // first-order reactions while each is far from its threshold, else
      // (and then for all) from the nonlinear chain's.
      linear_reactions(a.h, y);
      guard_terms(y);
      near = false;
      for (std::size_t k = 0; k < guards_.size() && !near; ++k) near = near_threshold(k);
      if (near) linear_.held = linear_.values;
    }
    if (near) {
      apply_devices(y, false);
      chain_reactions(c_, phases_, a, q, qd, reactions_, qdd_, w_, corners_);
      if (active_ == exact_.get() && linear_.trusted) check_linear();
      guard_terms(y);
    }
    remember(t, y);
    for (std::size_t k = 0; k < guards_.size(); ++k) {
      const ChainGuardDef& d = guards_[k];
      const int j = d.joint;
      const double s = sign(d.pivot);
      switch (d.what) {
        case ChainGuard::uplift: g[k] = uplift_value(k); break;
        case ChainGuard::impact: g[k] = s * q[j]; break;
        case ChainGuard::overturn: g[k] = s * q[j] - jm_.overturn_angle[j]; break;
        case ChainGuard::tension: g[k] = contacts_[j].N; break;
        case ChainGuard::friction: {
          const JointReaction& c = contacts_[j];
          g[k] = jm_.friction_limit[j] * c.N - std::abs(c.V);
          break;
        }
        case ChainGuard::fracture: {
          const JointDevices& at = *group_at(j);
          const ContactModel::Acting& dev = acting(at)[static_cast<std::size_t>(d.acting)];
          g[k] = at.discrete.is_broken(dev.device)
                     ? -1.0
                     : stretch(dev.geometry, half_width(j), *phases_[j].pivot(), Tilt(q[j])).e - dev.capacity;
          break;
        }
      }
    }
  }

  // The margins of the closed phase's guards: 5 % of each term's value at
  // rest (N, N B, the corners' accelerations). The first-order reactions'
  // error is of second order, a fraction of the order of the rotations of
  // those values (docs/chain.md), so that beyond its margin a term's sign is
  // the nonlinear one's; check_linear holds that error below half the margin
  // wherever the nonlinear reactions are evaluated.
  void set_margins() {
    constexpr double share = 0.05;
    linear_.margins.assign(static_cast<std::size_t>(c_.joints), {});
    for (int j = 0; j < c_.joints; ++j) {
      const double* r = linear_.r0.data() + 7 * j;
      Margins& m = linear_.margins[static_cast<std::size_t>(j)];
      m.normal = share * std::abs(r[0]);
      m.moment = share * std::abs(r[0]) * c_.data.segments[j].half_width;
      m.corner = {share * std::abs(r[3]), share * std::abs(r[4])};  // left, right (rocking.geometry's index)
    }
  }

  // After a nonlinear evaluation near a threshold: the first-order reactions
  // (linear_.held) must be within half their margins of the nonlinear ones,
  // else the closed phase's guards are the nonlinear ones for the rest of the run.
  void check_linear() {
    for (int j = 0; j < c_.joints && linear_.trusted; ++j) {
      const double* r = linear_.held.data() + 7 * j;
      const Margins& m = linear_.margins[static_cast<std::size_t>(j)];
      const double B = c_.data.segments[j].half_width;
      const bool close = std::abs(reactions_[j].N - r[0]) < 0.5 * m.normal &&
                         std::abs(reactions_[j].V - r[1]) < 0.5 * m.normal &&
                         std::abs(reactions_[j].M - r[2]) < 0.5 * m.normal * B &&
                         std::abs(corners_[j].left - r[3]) < 0.5 * m.corner[0] &&
                         std::abs(corners_[j].right - r[4]) < 0.5 * m.corner[1];
      linear_.trusted = close;
    }
  }

  void loop() {
    while (active_->time() < t_end_) {
      check_stop(opt_, active_->time());
      const ode::StepReport rep = active_->step(t_end_);
      if (rep.reason != ode::Stop::event) {
        // A rocking joint can end a step on the wrong side without a located
        // crossing: a return inside one step that the guards' samples did not
        // see (a joint an impact or uplift left open with s theta_j' ~ 0 and
        // its acceleration pointing back), or round-off right after an
        // uplift. Its impact is where s theta_j falls through 0 on the step's
        // dense output; the step ends there, so that no state past it (the
        // joint through its face, with less potential energy than any
        // motion gives) enters the outputs or the energy.
        double at = std::numeric_limits<double>::infinity();
        int which = -1;
        for (int j = 0; j < c_.joints; ++j)
          if (phases_[j].is_rocking() && sign(*phases_[j].pivot()) * active_->state()[j] < 0) {
            const double tj = wrong_side_crossing(j);
            if (tj < at) {
              at = tj;
              which = j;
            }
          }
        if (which >= 0) {
          sample_step(at);
          Eigen::VectorXd y(size_);
          active_->dense(at, y);
          if (!handle_event({ChainGuard::impact, which, *phases_[which].pivot()}, at, &y)) return;
          continue;
        }
      }
      sample_step();
      if (rep.reason == ode::Stop::event) {
        if (!handle_event(guards_[static_cast<std::size_t>(rep.guard)], rep.t)) return;
        continue;
      }
    }
  }

  // The last time in the last step at which rocking joint j is still on its
  // side, s theta_j >= 0, before it falls through 0 (it ends the step below
  // 0): the first of 16 even samples below 0, then bisection to round-off
  // from the sample before it (the step's start, where s theta_j >= 0, when
  // that is the first).
  double wrong_side_crossing(int j) {
    const double t0 = active_->previous_time(), t1 = active_->time();
    const double s = sign(*phases_[j].pivot());
    const auto side = [&](double t) {
      active_->dense(t, scratch_);
      return s * scratch_[j];
    };
    double lo = t0, hi = t1;
    constexpr int samples = 16;
    for (int k = 1; k < samples; ++k) {
      const double tk = t0 + (t1 - t0) * k / samples;
      if (side(tk) < 0) {
        hi = tk;
        break;
      }
      lo = tk;
    }
    for (int i = 0; i < 200 && hi - lo > 4 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(hi)); ++i) {
      const double mid = 0.5 * (lo + hi);
      (side(mid) < 0 ? hi : lo) = mid;
    }
    return lo;
  }

  // Returns false when the run ends (overturning, separation).
  // With `y`, the state at t (an event found after the step, not at its end).
  bool handle_event(const ChainGuardDef& d, double t, const Eigen::VectorXd* y = nullptr) {
    y_ = y != nullptr ? *y : active_->state();
    closed_at_rest(y_);
    const int j = d.joint;
    count_phase_change(events_, opt_, t);
    switch (d.what) {
      case ChainGuard::uplift: lift(j, d.pivot, t); break;
      case ChainGuard::impact:
        if (!impact(j, t)) return false;
        break;
      case ChainGuard::overturn:
        announce({EventKind::overturn, t, d.pivot, std::nullopt, j});
        result_.outcome = Outcome::overturned;
        return false;
      case ChainGuard::tension: separate(j, t); return false;
      case ChainGuard::friction:
        result_.outcome = Outcome::sliding;
        result_.stated = fmt::format("joint {} at t = {:.9g} s: its friction demand |V|/N reached the scene's limit "
                                     "{:g}, so it would slide, which the model does not follow (phases {})",
                                     j, t, jm_.friction_limit[j], phases_text());
        return false;
      case ChainGuard::fracture: {
        JointDevices& at = *group_at(j);
        const int local = acting(at)[static_cast<std::size_t>(d.acting)].device;
        const std::size_t device = at.devices[static_cast<std::size_t>(local)];
        announce({EventKind::fracture, t, d.pivot, static_cast<int>(device), j});
        fracture(at.discrete, local);
        result_.devices[device].fracture_time = t;
        break;
      }
    }
    peaks_.break_continuity();
    restart(t);
    return !separated_at(t);
  }

  // Joint j's normal force reached 0 (or, with `impulse`, an impact's
  // impulse there would be tensile): the part above would leave it (MODEL.md 15).
  void separate(int j, double t, std::string_view impulse = {}) {
    result_.outcome = Outcome::separated;
    result_.separated_joint = j;
    result_.stated = fmt::format("joint {} at t = {:.9g} s: {}, so the part above would leave it, which the model "
                                 "does not follow (phases {})",
                                 j, t, impulse.empty() ? "its normal force N reached 0" : impulse, phases_text());
  }

  // A joint already in tension as a phase begins (after an impact, or at the
  // start) ends the run as one whose N falls through 0 does.
  bool separated_at(double t) {
    apply_devices(y_, false);
    chain_reactions(c_, phases_, ground_at(t), y_.head(n_), y_.segment(n_, n_), reactions_, qdd_, w_);
    for (int j = 0; j < c_.joints; ++j)
      if ((j > 0 || jm_.base_rocks()) && contact_reaction(j, y_).N < 0) {
        separate(j, t);
        return true;
      }
    return false;
  }

  // Why the momentum law leaves an impact's outcome open, in words: how many
  // outcomes it admits, and when none, what refused them ("the momentum law
  // admits none of the 2 outcomes examined (2 with a tensile impulse at
  // joint 1; 1 with joint 0 opened but moving shut)"), or that it has too
  // many to examine.
  static std::string undecided_impact(const ImpactOutcome& out) {
    if (out.status == ImpactStatus::beyond_search)
      return fmt::format("{} closed joints may open, giving 2 x 3^{} outcomes to examine, beyond the {} the "
                         "momentum law examines at one impact",
                         out.may_open, out.may_open, max_impact_outcomes);
    const auto admitted = std::ranges::count_if(out.candidates, [](const ImpactCandidate& c) { return c.consistent(); });
    if (admitted > 0)
      return fmt::format("the momentum law admits {} of the {} outcomes examined", admitted, out.candidates.size());
    std::map<std::pair<ImpactCandidate::Refusal, std::size_t>, int> why;
    for (const ImpactCandidate& c : out.candidates)
      for (std::size_t k = 0; k < c.refused.size(); ++k)
        if (c.refused[k] != ImpactCandidate::Refusal::none) ++why[{c.refused[k], k}];
    std::vector<std::string> parts;
    for (const auto& [key, count] : why)
      parts.push_back(fmt::format("{} with {}", count, refusal_words(key.first, static_cast<int>(key.second))));
    return fmt::format("the momentum law admits none of the {} outcomes examined ({})", out.candidates.size(),
                       fmt::join(parts, "; "));
  }

  // The joint at which every outcome of an impact needs a tensile impulse:
  // the impact would throw the part above it off, which ends the run as a
  // tensile N between impacts does (separated).
  static std::optional<int> thrown_off(const ImpactOutcome& out) {
    if (out.status != ImpactStatus::none || out.candidates.empty()) return std::nullopt;
    for (std::size_t k = 0; k < out.candidates.front().refused.size(); ++k)
      if (std::ranges::all_of(out.candidates,
                              [&](const ImpactCandidate& c) { return c.refused[k] == ImpactCandidate::Refusal::tensile; }))
        return static_cast<int>(k);
    return std::nullopt;
  }

  // Impact at joint j (theta_j back to 0): the momentum law or a given r.
  // Returns false when the law does not decide the outcome (the run ends
  // `undecided`, in the state just before the impact).
  bool impact(int j, double t) {
    const Pivot s = *phases_[j].pivot();
    announce({EventKind::impact, t, s, std::nullopt, j});
    y_[j] = 0;
    const double before = mechanical();
    keep_device_states();
    const auto q = y_.head(n_);
    const Eigen::VectorXd qd = y_.segment(n_, n_);
    const double r = jm_.restitution[j];
    if (std::abs(qd[j]) <= jm_.theta_dot_min || r == 0) {
      // Too slow to rock on (Eq. 8), or r = 0: the joint closes, the rest by the momentum law.
      std::vector<Phase> after = phases_;
      after[j] = Phase::full_contact();
      const ImpactCandidate cand = impact_into(c_, phases_, j, after, q, qd);
      phases_ = cand.phases;
      y_.segment(n_, n_) = cand.q_dot;
    } else {
      const ImpactOutcome out = chain_impact(c_, phases_, j, q, qd, r);
      if (const std::optional<int> k = thrown_off(out)) {
        separate(*k, t,
                 fmt::format("the impact at joint {} needs a tensile impulse there in each of the {} outcomes the "
                             "momentum law examines",
                             j, out.candidates.size()));
        return false;
      }
      if (out.status != ImpactStatus::unique) {
        result_.outcome = Outcome::undecided;
        result_.stated = fmt::format("impact at joint {} at t = {:.9g} s: {}, so the outcome is not decided (phases {})",
                                     j, t, undecided_impact(out), phases_text());
        return false;
      }
      for (int k : out.uplifted) {  // impact-induced uplift
        JointResult& rk = result_.joints[k];
        if (rk.uplifts++ == 0) rk.first_uplift = t;
        if (result_.counts.uplifts++ == 0) result_.first_uplift = t;
        announce({EventKind::uplift, t, *out.phases[k].pivot(), std::nullopt, k});
      }
      phases_ = out.phases;
      y_.segment(n_, n_) = out.q_dot;
    }
    for (int k = 0; k < c_.joints; ++k)
      if (!phases_[k].is_rocking()) {
        y_[k] = 0;
        y_[n_ + k] = 0;
      }
    phases_set();
    result_.energy.impacts += before - mechanical();
    JointResult& rj = result_.joints[j];
    if (rj.impacts++ == 0) rj.first_impact = t;
    if (result_.counts.impacts++ == 0) result_.first_impact = t;
    take_resting();
    for (int k = 0; k < c_.joints; ++k) lift_if_lifting(k, t);
    return true;
  }

  // The response of joint 0 and the whole structure in today's quantities,
  // and every joint's sample (with its reaction when `reactions`).
  Response response(double t, Eigen::Ref<const Eigen::VectorXd> y, bool reactions) {
    const auto q = y.head(n_), qd = y.segment(n_, n_);
    Response r;
    r.t = t;
    r.phase = phases_[0];
    r[Quantity::t] = t;
    r[Quantity::phase] = phases_[0].sign();
    const bool base = phases_[0].is_rocking();  // a closed joint's theta and theta' are 0
    r[Quantity::theta] = base ? q[0] : 0.0;
    r[Quantity::theta_over_alpha] = r[Quantity::theta] * scales_.inverse_alpha_cg;
    r[Quantity::theta_dot] = base ? qd[0] : 0.0;
    const Eigen::Vector2d top = anchor_position(c_, phases_, top_, q, w_);
    r[Quantity::delta_t] = top.x() * scales_.inverse_H_N;
    for (std::size_t k = 0; k < elongation_.size(); ++k)
      elongation_[k] = tendon_elongation(c_, phases_, static_cast<int>(k), q, w_);
    if (reactions && !recall(t, y)) {
      apply_devices(y, false);
      chain_reactions(c_, phases_, ground_at(t), q, qd, reactions_, qdd_, w_);
      for (int j = 0; j < c_.joints; ++j) contacts_[j] = contact_reaction(j, y);
    }
    for (int j = 0; j < c_.joints; ++j) {
      JointSample& s = samples_[j];
      s.phase = phases_[j];
      s.theta = phases_[j].is_rocking() ? q[j] : 0.0;
      s.theta_dot = phases_[j].is_rocking() ? qd[j] : 0.0;
      if (reactions) {
        const JointReaction& c = contacts_[j];
        s.N = c.N;
        s.V = c.V;
        s.M = reactions_[j].M;
      }
    }
    return r;
  }

  void track(const Response& r, Eigen::Ref<const Eigen::VectorXd> y) {
    peaks_.add(r.t, r.q);
    for (int j = 0; j < c_.joints; ++j) {
      JointResult& out = result_.joints[j];
      out.peak_theta = std::max(out.peak_theta, std::abs(samples_[j].theta));
      out.peak_theta_over_alpha = out.peak_theta / jm_.overturn_angle[j];
      if (samples_[j].N > 0) out.peak_friction = std::max(out.peak_friction, samples_[j].friction());
    }
    sample_devices(y);
    for (std::size_t k = 0; k < result_.devices.size(); ++k) {
      if (k < nb_ && broken(k)) continue;  // its peaks are those it had when it broke
      DeviceResult& out = result_.devices[k];
      out.peak_elongation = std::max(out.peak_elongation, device_samples_[k].e);
      out.peak_force = std::max(out.peak_force, std::abs(device_samples_[k].F));
    }
  }

  // Every device's elongation, force and work so far into device_samples_
  // (after response(), which measured the tendons): those across each joint
  // while it rocks (0 while it is closed, NaN once broken), then the tendons'.
  void sample_devices(Eigen::Ref<const Eigen::VectorXd> y) {
    for (std::size_t k = 0; k < nb_; ++k)
      device_samples_[k] = broken(k) ? DeviceSample{std::nan(""), std::nan(""), 0.0} : DeviceSample{};
    for (std::size_t k = 0; k < nb_; ++k) device_samples_[k].work = y[work_ + 3 + static_cast<Eigen::Index>(k)];
    for (JointDevices& g : groups_) {
      const int j = g.joint;
      if (!phases_[j].is_rocking()) continue;
      load_block(g, y);
      const Tilt tilt(y[j]);
      for (const ContactModel::Acting& a : acting(g)) {
        if (g.discrete.is_broken(a.device)) continue;
        const DamperState st = a.state(a, g.discrete, half_width(j), *phases_[j].pivot(), tilt, y[n_ + j], g.block.data());
        DeviceSample& out = device_samples_[g.devices[static_cast<std::size_t>(a.device)]];
        out.e = st.elongation;
        out.F = st.force;
      }
    }
    for (std::size_t k = 0; k < elongation_.size(); ++k)
      device_samples_[nb_ + k] = {.e = elongation_[k], .F = tendon_force(k, elongation_[k]),
                                  .work = tendon_stored(k, elongation_[k]) - tendon_start_[k]};
  }

  // F = max(0, P0 + k e) (MODEL.md 11's elastic law) and the energy it stores from rest.
  double tendon_force(std::size_t k, double e) const {
    const ChainTendon& t = c_.data.tendons[k];
    return std::max(0.0, t.prestress + t.stiffness * e);
  }
  double tendon_stored(std::size_t k, double e) const {
    const ChainTendon& t = c_.data.tendons[k];
    const double slack = -t.prestress / t.stiffness;  // below it the tendon is slack
    const double x = std::max(e, slack);
    return t.prestress * x + 0.5 * t.stiffness * x * x;
  }

  // The peaks and history rows of the last step, or of its part up to `until`
  // (an event found after the step, which ends it there).
  void sample_step(double until = std::numeric_limits<double>::infinity()) {
    const int count = active_->sample_count();
    const double t0 = active_->previous_time();
    if (until < active_->time()) {
      for (int k = 1; k <= count; ++k) {
        const double t = ode::Integrator::sample_time(t0, until, k, count);
        active_->dense(t, scratch_);
        track(response(t, scratch_, true), scratch_);
      }
    } else {
      const double t1 = active_->time();
      for (int k = 1; k <= count; ++k) {
        const Eigen::VectorXd& y = active_->sample(k, count);
        track(response(ode::Integrator::sample_time(t0, t1, k, count), y, true), y);
      }
    }
    if (observer_ == nullptr) return;
    history_.rows(*active_, dense_, [this](double t, const Eigen::VectorXd& y) { history_row(t, y); }, until);
  }

  // A history row, with the energy balance's terms so far: the mechanical
  // energy and the tendons' stored energy of the state, its ground and
  // viscous accumulators, the impacts' losses up to now.
  void history_row(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    last_row_ = t;
    Response r = response(t, y, true);
    r[Quantity::a_g] = ground_.acceleration(t);
    r[Quantity::a_v] = vertical_ ? vertical_->acceleration(t) : 0.0;
    r[Quantity::x_g] = travel_.at(t).d;
    const ChainEnergy e = chain_energy(c_, phases_, y.head(n_), y.segment(n_, n_), w_);
    r[Quantity::energy] = e.kinetic + e.gravity + e.elastic;
    r[Quantity::work_ground] = y[work_];
    r[Quantity::work_viscous] = y[work_ + 1];
    r[Quantity::work_devices] = e.tendons - tendons_initial_ + y[work_ + 2];
    r[Quantity::work_impacts] = result_.energy.impacts;
    observer_->nodal(y.head(0), y.head(0));
    if (!device_samples_.empty()) {
      sample_devices(y);
      observer_->devices(device_samples_);
    }
    observer_->joints(samples_);
    observer_->record(r);
  }

  void emit(double t, Eigen::Ref<const Eigen::VectorXd> y, bool also_history) {
    track(response(t, y, true), y);
    if (also_history && observer_ != nullptr) history_row(t, y);
  }

  void finish() {
    y_ = active_->state();
    closed_at_rest(y_);
    result_.t_end = active_->time();
    result_.final_phase = phases_[0];
    result_.final_theta = y_[0];
    result_.final_state = y_;
    result_.peaks = peaks_.peaks();
    result_.top_total_mm = result_.peak(Quantity::delta_t) * scales_.H_N * 1000.0;
    result_.stats = run_stats(*integrator_, exact_.get());
    result_.energy.final = mechanical();
    result_.energy.ground = y_[work_];
    result_.energy.viscous = y_[work_ + 1];
    result_.energy.damper = energy().tendons - tendons_initial_ + y_[work_ + 2];
    for (std::size_t k = 0; k < nb_; ++k) result_.devices[k].work = y_[work_ + 3 + static_cast<Eigen::Index>(k)];
    for (std::size_t k = 0; k < c_.data.tendons.size(); ++k)
      result_.devices[nb_ + k].work =
          tendon_stored(k, tendon_elongation(c_, phases_, static_cast<int>(k), y_.head(n_), w_)) - tendon_start_[k];
    if (opt_.final_row && observer_ != nullptr && opt_.output_interval > 0 && last_row_ < result_.t_end)
      history_row(result_.t_end, y_);
  }

  const ContactModel& m_;
  const JointedModel& jm_;
  const Chain& c_;
  const GroundMotion& ground_;
  const GroundMotion* vertical_;
  const RunOptions& opt_;
  Observer* observer_;
  OutputScales scales_;
  ChainWorkspace w_;
  int n_;
  std::vector<Phase> phases_;
  std::vector<JointReaction> reactions_;
  std::vector<JointReaction> contacts_ = std::vector<JointReaction>(static_cast<std::size_t>(c_.joints));  // contact_reaction's, per joint
  std::vector<Lift> lifts_;  // per guard (uplift guards only)
  std::vector<Resting> resting_ = std::vector<Resting>(static_cast<std::size_t>(c_.joints));  // per joint
  std::vector<CornerAcceleration> corners_ = std::vector<CornerAcceleration>(static_cast<std::size_t>(c_.joints));
  std::vector<Remembered> remembered_ = std::vector<Remembered>(16);
  std::size_t next_remembered_ = 0, held_ = 0;
  std::vector<JointSample> samples_;
  std::size_t nb_;                 // devices across a joint (the model's first)
  std::vector<JointDevices> groups_;                       // per joint with devices, from the ground up
  std::vector<int> group_of_;                              // per joint: its group, or -1
  std::vector<std::pair<std::size_t, std::size_t>> where_;  // per device across a joint: its group, its local number
  Eigen::Index z_, work_, size_;   // the state's z block, its works, its size
  Eigen::VectorXd y_, dense_, qdd_;
  Eigen::VectorXd scratch_ = Eigen::VectorXd::Zero(size_);  // a state on the last step's dense output
  std::vector<double> elongation_;  // per tendon, at the last response
  std::vector<DeviceSample> device_samples_;  // per device, for the history's device columns
  ChainAnchor top_;
  std::vector<ChainGuardDef> guards_;
  GroundTravel travel_{ground_};
  // The closed phase's first-order reactions (linearise_reactions) and the
  // margins of its guards (set_margins).
  struct Margins {
    double normal = 0, moment = 0;
    std::array<double, 2> corner{};
  };
  struct LinearReactions {
    std::vector<int> columns;  // the state's entries the reactions depend on
    std::vector<double> packed;  // r0, ra and R as linear_reactions reads them
    Eigen::VectorXd r0, values, held;
    std::vector<Margins> margins;
    bool trusted = true;
  } linear_;
  std::unique_ptr<ChainStiff> stiff_;                    // rosw's linear solves
  std::unique_ptr<ode::Integrator> integrator_, exact_;  // the backend; every joint closed under a record
  ode::Integrator* active_ = nullptr;                    // the one stepping the current phases
  double t_end_ = 0, tendons_initial_ = 0;
  std::vector<double> tendon_start_;  // each tendon's stored energy at the start [J]
  double last_row_ = -std::numeric_limits<double>::infinity();  // the last history row's time
  long events_ = 0;
  HistoryGrid history_{opt_.output_interval};
  PeakTracker<> peaks_;
  RunResult result_;
};

}  // namespace

RunResult simulate_chain(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                         Observer* observer) {
  return timed_run<ChainDriver>(m, ground, options, observer);
}

}  // namespace rocking
