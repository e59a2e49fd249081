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
// reactions) and the devices across the base joint, as on a one-joint
// structure (MODEL.md 11, rocking.contact's acting devices of a rigid block
// on the same base): while the base rocks about s they exert the generalised
// force -s D on theta_0 (D = sum F de/d|theta_0|), their states z integrated,
// their fractures located events; in full contact they rest, keeping their
// states for the next uplift about the same side, and hold D_0(s) against
// uplift about s (the moment condition less D_0, the corner's acceleration
// less D_0 over the inertia about the corner).
// The state is [q, q', z, W_ground, W_viscous, W_devices, the work on each
// base device]: the works are integrals that do not steer the steps. The
// mechanical energy is kinetic + gravity + elastic; the tendons' stored
// energy and the base devices' work are the work done on the devices.
// The devices' moment M_dev is not computed.
// contact.rocking = false holds the base joint closed (a fixed base): the
// joints above still rock.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.simulation;
import :peaks;
import rocking.errors;

namespace rocking {

double JointSample::friction() const { return N > 0 ? std::abs(V) / N : std::numeric_limits<double>::infinity(); }

namespace {

enum class ChainGuard { uplift, impact, overturn, tension, friction, fracture };

struct ChainGuardDef {
  ChainGuard what = ChainGuard::uplift;
  int joint = 0;
  Pivot pivot = Pivot::right;
  int acting = 0;  // a fracture guard's base device, by its place in the pivot's acting list
};

// The states z of the base devices: the slots after theta and theta' that
// the model's acting devices use (a rigid block's, rocking.scene).
Eigen::Index base_device_states(const ContactModel& m) {
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
        samples_(static_cast<std::size_t>(c_.joints)), nb_(jm_.base_devices), z_(2 * n_),
        work_(z_ + base_device_states(m)), size_(work_ + 3 + static_cast<Eigen::Index>(nb_)),
        y_(Eigen::VectorXd::Zero(size_)), dense_(size_), qdd_(n_), elongation_(c_.data.tendons.size(), 0.0),
        device_samples_(m.devices.size()), block_(Eigen::VectorXd::Zero(2 + work_ - z_)),
        block_rates_(Eigen::VectorXd::Zero(block_.size())), power_(nb_, 0.0) {
    auto rhs = [this](double t, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& dydt) {
      derivatives(t, y, dydt);
    };
    integrator_ = motion_integrator(o, ground, size_, rhs, motion_tolerances(o, ground, work_));
    t_end_ = run_end(o, ground);
    // The top node's local height on its segment: delta_t is its horizontal displacement over H_N.
    const ChainSegment& top = c_.data.segments.back();
    top_ = {.segment = c_.joints - 1, .x = 0.0, .z = top.heights[top.heights.size() - 1] - top.base_height,
            .node = top.rigid ? -1 : static_cast<int>(top.heights.size()) - 1};
  }

  RunResult run() {
    result_.integrator = integrator_->name();
    result_.presence = presence(m_);
    result_.energy_tracked = true;
    result_.joints.resize(static_cast<std::size_t>(c_.joints));
    // The base devices, then the chain's tendons, in the model's order.
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

  void derivatives(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> dydt) {
    const GroundAcceleration a = ground_at(t);
    const auto q = y.head(n_), qd = y.segment(n_, n_);
    apply_base_devices(y, true);
    ChainPower p;
    chain_acceleration(c_, phases_, a, q, qd, dydt.segment(n_, n_), w_, &p);
    dydt.head(n_) = qd;
    for (int j = 0; j < c_.joints; ++j)
      if (!phases_[j].is_rocking()) dydt[j] = 0;  // a closed joint's theta stays 0
    // The base devices' states rest unless the pivot's acting devices write theirs.
    dydt.segment(z_, work_ - z_) = block_rates_.segment(2, work_ - z_);
    dydt[work_] = p.ground;
    dydt[work_ + 1] = p.damping;
    double total = 0;
    for (std::size_t k = 0; k < nb_; ++k) {
      dydt[work_ + 3 + static_cast<Eigen::Index>(k)] = power_[k];
      total += power_[k];
    }
    dydt[work_ + 2] = total;
  }

  // The base devices' generalised force on theta_0 into the workspace (-s D
  // while the base rocks about s, else 0), from the state y; with `rates`,
  // their states' rates into block_rates_ and each one's power into power_.
  void apply_base_devices(Eigen::Ref<const Eigen::VectorXd> y, bool rates) {
    w_.applied[0] = 0.0;
    if (rates) {
      block_rates_.setZero();
      std::fill(power_.begin(), power_.end(), 0.0);
    }
    if (nb_ == 0 || !phases_[0].is_rocking()) return;
    block_[0] = y[0];
    block_[1] = y[n_];
    block_.tail(work_ - z_) = y.segment(z_, work_ - z_);
    const int s = phases_[0].sign();
    const Tilt tilt(y[0]);
    double moment = 0;
    for (const ContactModel::Acting& a : acting()) {
      const ContactModel::DeviceTerms dt =
          a.terms(a, devices_, base_half_width(), s, tilt, y[n_], block_.data(), block_rates_.data());
      moment += dt.moment;
      if (rates) power_[static_cast<std::size_t>(a.device)] = dt.power;
    }
    w_.applied[0] = -s * moment;
  }

  double base_half_width() const { return c_.data.segments[0].half_width; }
  const std::vector<ContactModel::Acting>& acting() const { return m_.acting[index(*phases_[0].pivot())]; }
  // The moment the intact base devices hold against uplift about p at rest.
  double held(Pivot p) const { return nb_ == 0 ? 0.0 : held_moment(m_, devices_, p); }

  // Joint j's contact reaction: the multipliers' N and V, with, at the base,
  // the pull of the base devices, which the chain applies on theta_0 alone
  // (the moment condition holds it as D_0): the contact carries it as well.
  // A device from the ground at (x, 0) to the base's anchor pulls along its
  // chord, at |theta_0| / 2 from the vertical toward the pivot's side
  // (MODEL.md 11), or vertically (kinematics vertical); at rest each intact
  // device pulls down with its force at rest.
  JointReaction contact_reaction(int j, Eigen::Ref<const Eigen::VectorXd> y) {
    JointReaction r = reactions_[j];
    if (j != 0 || nb_ == 0) return r;
    if (!phases_[0].is_rocking()) {
      for (std::size_t k = 0; k < nb_; ++k)
        if (!devices_.is_broken(static_cast<int>(k)))
          r.N += law_force_at_rest(m_.devices[k].law, devices_.z(static_cast<int>(k)));
      return r;
    }
    sample_devices(y);
    const double half = 0.5 * std::abs(y[0]), s = phases_[0].sign();
    for (const ContactModel::Acting& a : acting()) {
      if (devices_.is_broken(a.device)) continue;
      const double F = device_samples_[static_cast<std::size_t>(a.device)].F;
      const bool chord = a.geometry.kinematics == Kinematics::chord;
      r.N += chord ? F * std::cos(half) : F;
      r.V += chord ? s * F * std::sin(half) : 0.0;
    }
    return r;
  }

  // The base joint's devices follow its phase: the acting devices of a new
  // rocking phase resume the states they kept (keep_device_states).
  void base_phase_set() {
    devices_.phase = phases_[0];
    if (nb_ == 0 || !phases_[0].is_rocking()) return;
    for (const ContactModel::Acting& a : acting())
      if (a.slot) y_[z_ + *a.slot - 2] = devices_.z(a.device);
  }
  void keep_device_states() {
    if (nb_ == 0 || !phases_[0].is_rocking()) return;
    for (const ContactModel::Acting& a : acting())
      if (a.slot) devices_.set_z(a.device, y_[z_ + *a.slot - 2]);
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
    base_phase_set();
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
    apply_base_devices(y_, false);
    chain_reactions(c_, phases_, a, q, qd, reactions_, qdd_, w_, corners_);
    for (Pivot s : pivots)
      if (lift_moment(j, s) > 0 && lift_acceleration(j, s) > 0) {
        lift(j, s, t);
        return;
      }
  }

  // Closed joint j's uplift conditions about s from the last reactions: the
  // resultant past the corner, and the corner's relative acceleration away
  // from the face, each less the base devices' held moment at the base.
  double lift_moment(int j, Pivot s) const {
    return uplift_guard(c_, j, s, reactions_[j]) - (j == 0 ? held(s) : 0.0);
  }
  double lift_acceleration(int j, Pivot s) const {
    return corners_[j][s] + (j == 0 ? held(s) * corners_[j].gain(s) : 0.0);
  }

  void lift(int j, Pivot s, double t) {
    phases_[j] = Phase::rocking(s);
    y_[j] = 0;
    y_[n_ + j] = 0;
    if (j == 0) base_phase_set();
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
    std::vector<JointReaction> reactions;
  };
  void remember(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    Remembered& r = remembered_[next_remembered_];
    next_remembered_ = (next_remembered_ + 1) % remembered_.size();
    r.t = t;
    r.y = y;
    r.reactions.assign(reactions_.begin(), reactions_.end());
    held_ = std::min(held_ + 1, remembered_.size());
  }
  bool recall(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    for (std::size_t k = 0; k < held_; ++k) {
      const Remembered& r = remembered_[k];
      if (r.t == t && r.y == y) {
        std::copy(r.reactions.begin(), r.reactions.end(), reactions_.begin());
        return true;
      }
    }
    return false;
  }

  void restart(double t) {
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
    if (phases_[0].is_rocking())  // the base devices that can break: at their capacity
      for (std::size_t k = 0; k < m_.breakable[index(*phases_[0].pivot())].size(); ++k) {
        guards_.push_back({ChainGuard::fracture, 0, *phases_[0].pivot(),
                           m_.breakable[index(*phases_[0].pivot())][k]});
        directions.push_back(ode::Direction::rising);
      }
    ode::Guards guards{[this](double tg, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& g) {
                         guard_values(tg, y, g);
                       },
                       std::move(directions)};
    integrator_->reset(t, y_, std::move(guards));
    emit(t, y_, true);
  }

  void guard_values(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> g) {
    const GroundAcceleration a = ground_at(t);
    const auto q = y.head(n_), qd = y.segment(n_, n_);
    apply_base_devices(y, false);
    chain_reactions(c_, phases_, a, q, qd, reactions_, qdd_, w_, corners_);
    remember(t, y);
    for (std::size_t k = 0; k < guards_.size(); ++k) {
      const ChainGuardDef& d = guards_[k];
      const int j = d.joint;
      const double s = sign(d.pivot);
      switch (d.what) {
        case ChainGuard::uplift: g[k] = std::min(lift_moment(j, d.pivot), lift_acceleration(j, d.pivot)); break;
        case ChainGuard::impact: g[k] = s * q[j]; break;
        case ChainGuard::overturn: g[k] = s * q[j] - jm_.overturn_angle[j]; break;
        case ChainGuard::tension: g[k] = contact_reaction(j, y).N; break;
        case ChainGuard::friction: {
          const JointReaction c = contact_reaction(j, y);
          g[k] = jm_.friction_limit[j] * c.N - std::abs(c.V);
          break;
        }
        case ChainGuard::fracture: {
          const ContactModel::Acting& dev = acting()[static_cast<std::size_t>(d.acting)];
          g[k] = devices_.is_broken(dev.device)
                     ? -1.0
                     : stretch(dev.geometry, base_half_width(), phases_[0].sign(), Tilt(q[0])).e - dev.capacity;
          break;
        }
      }
    }
  }

  void loop() {
    while (integrator_->time() < t_end_) {
      check_stop(opt_, integrator_->time());
      const ode::StepReport rep = integrator_->step(t_end_);
      sample_step();
      if (rep.reason == ode::Stop::event) {
        if (!handle_event(guards_[static_cast<std::size_t>(rep.guard)], rep.t)) return;
        continue;
      }
      // Round-off right after an uplift can put a theta on the wrong side
      // without a crossing: treat it as the impact it is.
      for (int j = 0; j < c_.joints; ++j)
        if (phases_[j].is_rocking() && sign(*phases_[j].pivot()) * integrator_->state()[j] < 0) {
          if (!handle_event({ChainGuard::impact, j, *phases_[j].pivot()}, integrator_->time())) return;
          break;
        }
    }
  }

  // Returns false when the run ends (overturning, separation).
  bool handle_event(const ChainGuardDef& d, double t) {
    y_ = integrator_->state();
    const int j = d.joint;
    count_phase_change(events_, opt_, t);
    switch (d.what) {
      case ChainGuard::uplift: lift(j, d.pivot, t); break;
      case ChainGuard::impact: impact(j, t); break;
      case ChainGuard::overturn:
        announce({EventKind::overturn, t, d.pivot, std::nullopt, j});
        result_.outcome = Outcome::overturned;
        return false;
      case ChainGuard::tension: separate(j, t); return false;
      case ChainGuard::friction:
        throw RunError(fmt::format("joint {} would slide at t = {:.9g} s: its friction demand |V|/N reached the stated "
                                   "limit {:g} (sliding is not modelled)", j, t, jm_.friction_limit[j]));
      case ChainGuard::fracture: {
        const int device = acting()[static_cast<std::size_t>(d.acting)].device;
        announce({EventKind::fracture, t, d.pivot, device, 0});
        fracture(devices_, device);
        result_.devices[static_cast<std::size_t>(device)].fracture_time = t;
        break;
      }
    }
    peaks_.break_continuity();
    restart(t);
    return !separated_at(t);
  }

  // Joint j's normal force reached 0: the part above would leave it (MODEL.md 15).
  void separate(int j, double t) {
    result_.outcome = Outcome::separated;
    result_.separated_joint = j;
    result_.separation = fmt::format("joint {} at t = {:.9g} s: its normal force N reached 0, so the part above "
                                     "would leave it, which the model does not follow (phases {})",
                                     j, t, phases_text());
  }

  // A joint already in tension as a phase begins (after an impact, or at the
  // start) ends the run as one whose N falls through 0 does.
  bool separated_at(double t) {
    apply_base_devices(y_, false);
    chain_reactions(c_, phases_, ground_at(t), y_.head(n_), y_.segment(n_, n_), reactions_, qdd_, w_);
    for (int j = 0; j < c_.joints; ++j)
      if ((j > 0 || jm_.base_rocks()) && contact_reaction(j, y_).N < 0) {
        separate(j, t);
        return true;
      }
    return false;
  }

  // Impact at joint j (theta_j back to 0): the momentum law or a given r.
  void impact(int j, double t) {
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
      if (out.status != ImpactStatus::unique)
        throw RunError(fmt::format("impact at joint {} at t = {:.9g} s: the momentum law gives {} ({} candidates "
                                   "examined): the outcome is not decided",
                                   j, t, out.status == ImpactStatus::none ? "no admissible outcome" : "more than one admissible outcome",
                                   out.candidates.size()));
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
    base_phase_set();
    result_.energy.impacts += before - mechanical();
    JointResult& rj = result_.joints[j];
    if (rj.impacts++ == 0) rj.first_impact = t;
    if (result_.counts.impacts++ == 0) result_.first_impact = t;
    for (int k = 0; k < c_.joints; ++k) lift_if_lifting(k, t);
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
    r[Quantity::theta] = q[0];
    r[Quantity::theta_over_alpha] = q[0] * scales_.inverse_alpha_cg;
    r[Quantity::theta_dot] = qd[0];
    const Eigen::Vector2d top = anchor_position(c_, phases_, top_, q, w_);
    r[Quantity::delta_t] = top.x() * scales_.inverse_H_N;
    for (std::size_t k = 0; k < elongation_.size(); ++k)
      elongation_[k] = tendon_elongation(c_, phases_, static_cast<int>(k), q, w_);
    if (reactions && !recall(t, y)) {
      apply_base_devices(y, false);
      chain_reactions(c_, phases_, ground_at(t), q, qd, reactions_, qdd_, w_);
    }
    for (int j = 0; j < c_.joints; ++j) {
      JointSample& s = samples_[j];
      s.phase = phases_[j];
      s.theta = q[j];
      s.theta_dot = qd[j];
      if (reactions) {
        const JointReaction c = contact_reaction(j, y);
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
      if (devices_.is_broken(static_cast<int>(k))) continue;  // its peaks are those it had when it broke
      DeviceResult& out = result_.devices[k];
      out.peak_elongation = std::max(out.peak_elongation, device_samples_[k].e);
      out.peak_force = std::max(out.peak_force, std::abs(device_samples_[k].F));
    }
  }

  // Every device's elongation, force and work so far into device_samples_
  // (after response(), which measured the tendons): the base devices' while
  // the base rocks (0 in full contact, NaN once broken), then the tendons'.
  void sample_devices(Eigen::Ref<const Eigen::VectorXd> y) {
    for (std::size_t k = 0; k < nb_; ++k)
      device_samples_[k] = devices_.is_broken(static_cast<int>(k))
                               ? DeviceSample{std::nan(""), std::nan(""), 0.0}
                               : DeviceSample{};
    for (std::size_t k = 0; k < nb_; ++k) device_samples_[k].work = y[work_ + 3 + static_cast<Eigen::Index>(k)];
    if (nb_ > 0 && phases_[0].is_rocking()) {
      block_[0] = y[0];
      block_[1] = y[n_];
      block_.tail(work_ - z_) = y.segment(z_, work_ - z_);
      const Tilt tilt(y[0]);
      for (const ContactModel::Acting& a : acting()) {
        if (devices_.is_broken(a.device)) continue;
        const DamperState st = a.state(a, devices_, base_half_width(), phases_[0].sign(), tilt, y[n_], block_.data());
        DeviceSample& out = device_samples_[static_cast<std::size_t>(a.device)];
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

  void sample_step() {
    const int count = integrator_->sample_count();
    const double t0 = integrator_->previous_time(), t1 = integrator_->time();
    for (int k = 1; k <= count; ++k) {
      const Eigen::VectorXd& y = integrator_->sample(k, count);
      track(response(ode::Integrator::sample_time(t0, t1, k, count), y, true), y);
    }
    if (observer_ == nullptr) return;
    history_.rows(*integrator_, dense_, [this](double t, const Eigen::VectorXd& y) { history_row(t, y); });
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
    y_ = integrator_->state();
    result_.t_end = integrator_->time();
    result_.final_phase = phases_[0];
    result_.final_theta = y_[0];
    result_.final_state = y_;
    result_.peaks = peaks_.peaks();
    result_.top_total_mm = result_.peak(Quantity::delta_t) * scales_.H_N * 1000.0;
    result_.stats = integrator_->stats();
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
  std::vector<CornerAcceleration> corners_ = std::vector<CornerAcceleration>(static_cast<std::size_t>(c_.joints));
  std::vector<Remembered> remembered_ = std::vector<Remembered>(16);
  std::size_t next_remembered_ = 0, held_ = 0;
  std::vector<JointSample> samples_;
  std::size_t nb_;                 // base devices (the model's first)
  Eigen::Index z_, work_, size_;   // the state's z block, its works, its size
  Eigen::VectorXd y_, dense_, qdd_;
  std::vector<double> elongation_;  // per tendon, at the last response
  std::vector<DeviceSample> device_samples_;  // per device, for the history's device columns
  Eigen::VectorXd block_, block_rates_;  // [theta_0, theta_0', z]: the base devices' view of the state, and its rates
  std::vector<double> power_;            // on each base device [W]
  Discrete devices_;                     // the base devices': the base's phase, the states kept, the fractures
  ChainAnchor top_;
  std::vector<ChainGuardDef> guards_;
  GroundTravel travel_{ground_};
  std::unique_ptr<ode::Integrator> integrator_;
  double t_end_ = 0, tendons_initial_ = 0;
  std::vector<double> tendon_start_;  // each tendon's stored energy at the start [J]
  double last_row_ = -std::numeric_limits<double>::infinity();  // the last history row's time
  long events_ = 0;
  HistoryGrid history_{opt_.output_interval};
  PeakTracker peaks_;
  RunResult result_;
};

}  // namespace

RunResult simulate_chain(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                         Observer* observer) {
  return timed_run<ChainDriver>(m, ground, options, observer);
}

}  // namespace rocking
