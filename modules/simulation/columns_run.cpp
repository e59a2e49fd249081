// The run of a structure on rocking columns (MODEL.md 16): the frame's
// equations (rocking.columns) integrated by the same backends
// (rocking.integrator, rocking.sundials) and reported through the same
// observers, events, peaks and energy balance as the other drivers
// (simulation.cpp, chain_run.cpp; what they share is drive.cpp's). The phase
// is the columns': full contact (the structure on the cap beam as on a fixed
// base, MODEL.md 3) or rocking about either side. Guards:
// - full contact: uplift about s when the frame's equations give s theta'' > 0
//   at theta = theta' = 0 (uplift_guard, MODEL.md 16's Eq. 2 for the frame),
//   rising; none when contact.rocking = false holds the columns down;
// - rocking about s: impact, s theta falling through 0; overturning, s theta
//   rising through the columns' slenderness alpha (where gravity's moment on
//   the frame changes sign) or contact.overturn_angle;
// - any phase: tension, the smallest column-top contact force falling
//   through 0: the beam would leave a column, which the model assumes it does
//   not; the run ends there as `separated`, stated (MODEL.md 16).
// Resets: uplift (theta = theta' = 0, already so); impact by MODEL.md 15's
// momentum law (16's r for a rigid deck; a flexible deck's nodes keep their
// horizontal momentum) or a given r, into full contact when the ratio is not
// positive or |theta'| is below contact.theta_dot_min (Eq. 8's threshold);
// after an impact into full contact the frame lifts at once if the uplift
// condition already holds. Devices (MODEL.md 11) stand at the base of every
// column alike, as the model's devices of one column (rocking.scene): each
// acts while the columns rock, with its lever arm about the column's pivot,
// and the n alike exert n times its moment D and power; their states z rest
// in full contact and resume on the next uplift about the same side, and a
// device reaching its capacity fractures (an event, in every column at once).
// A device between the ground and the cap beam (ColumnsModel::beam_devices)
// is one: it acts while the columns rock about either side, its stretch the
// distance between its anchors (beam_device_stretch) and its moment
// F de/d|theta|; it holds F(e = 0) de/d|theta| against uplift; its force
// loads the deck, in both phases, for the column-top forces.
// The state is [theta, theta', z (the devices' states, as a rigid block's
// slots), u, u', W_ground, W_viscous, W_devices, the work on each device] (u
// nodal, none for a rigid deck); the works do not steer the steps. Full
// contact of a flexible structure under a piecewise-linear record is stepped
// exactly (rocking.integrator's make_exact_linear), as a structure on its own
// base is in simulation.cpp. The structure's outputs are those of the
// structure on a fixed base
// (rocking.simulation's evaluate on the model's fixed-base description) with
// the total top drift measured from the ground, (beam dx + u_N) / H_N, H_N
// from the column tops; a_N is -(K u + C u')_N / m_N in both phases (node N's
// Newton law, the beam's acceleration included). The columns report
// columns.theta, columns.theta_over_alpha (over their alpha),
// columns.theta_dot, beam.x and columns.top_force_min; each device its
// elongation and force (one column's) and M_dev the n devices' moment.
module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>
#include <fmt/format.h>
module rocking.simulation;
import :peaks;
import :record_steps;
import rocking.errors;

namespace rocking {

namespace {

enum class ColumnsGuard { uplift, impact, overturn, tension, fracture };

struct ColumnsGuardDef {
  ColumnsGuard what = ColumnsGuard::uplift;
  Pivot pivot = Pivot::right;
  int acting = 0;  // a fracture guard's device, by its place in the pivot's acting list
  int beam = -1;   // or, >= 0, by its place in the beam devices
};

// The states z of the devices: the slots after theta and theta' that the
// model's acting devices use (rocking.scene counts them as a rigid block's),
// then the beam devices'.
Eigen::Index device_states(const ContactModel& m) {
  Eigen::Index end = 2;
  for (const auto& acting : m.acting)
    for (const ContactModel::Acting& a : acting)
      if (a.slot) end = std::max(end, *a.slot + 1);
  for (const ColumnsModel::BeamDevice& d : m.on_columns->beam_devices)
    if (d.slot) end = std::max(end, *d.slot + 1);
  return end - 2;
}

class ColumnsDriver {
 public:
  ColumnsDriver(const ContactModel& m, const GroundMotion& ground, const RunOptions& o, Observer* observer)
      : m_(m), cm_(*m.on_columns), c_(cm_.columns), ground_(ground), vertical_(ground.vertical()), opt_(o),
        observer_(observer), scales_(output_scales(m)), n_(elastic_size(c_)), u_(2 + device_states(m)),
        work_(u_ + 2 * n_), size_(work_ + 3 + static_cast<Eigen::Index>(m.devices.size())),
        y_(Eigen::VectorXd::Zero(size_)), dense_(size_),
        fixed_(Eigen::VectorXd::Zero(m.layout.size)), normal_(static_cast<std::size_t>(c_.group.count)),
        history_(o.output_interval) {
    auto rhs = [this](double t, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& dydt) {
      derivatives(t, y, dydt);
    };
    integrator_ = motion_integrator(o.backend == ode::Backend::automatic ? ode::Backend::rk45 : o.backend, ground, size_,
                                    rhs, motion_tolerances(o, ground, work_));
    t_end_ = run_end(o, ground);
    // Full contact of a flexible structure under a piecewise-linear record:
    // the structure on the still beam is MODEL.md 3's linear system, stepped
    // exactly from sample to sample (as a structure on its own base is),
    // with the ground's and the viscous work as its quadratures.
    if (o.exact_full_contact && n_ > 0 && m.body.coordinates == ElasticCoordinates::nodal && ground.piecewise_linear() &&
        (!vertical_ || vertical_->piecewise_linear())) {
      exact_ = exact_full_contact(m, size_, u_, work_, ground_, o.tolerances.max_steps);
    }
    active_ = integrator_.get();
  }

  RunResult run() {
    result_.integrator = integrator_->name();
    result_.exact_full_contact = exact_ != nullptr;
    result_.presence = presence(m_);
    result_.energy_tracked = true;
    result_.columns.emplace();
    for (const Device& dev : m_.devices)
      result_.devices.push_back({.name = dev.name, .law = law_name(dev.law), .force_at_rest = law_force_at_rest(dev.law, 0.0),
                                 .work = 0.0});
    initial_state();
    result_.energy.initial = mechanical();
    run_stated(
        result_,
        [this] {
          try {
            lift_if_lifting(0.0);
            restart(0.0);
            if (phase_.is_rocking() && sign(*phase_.pivot()) * y_[0] >= cm_.overturn_angle) {
              announce({EventKind::overturn, 0.0, *phase_.pivot(), std::nullopt});
              result_.outcome = Outcome::overturned;
            } else {
              loop();
            }
          } catch (const Separation& s) {
            result_.outcome = Outcome::separated;
            result_.stated = s.what;
          }
        },
        [this] { return fmt::format("phase {}", phase_name(phase_)); });
    finish();
    return result_;
  }

 private:
  Pivot pivot() const { return *phase_.pivot(); }  // while rocking
  // The ground's accelerations at t, the last instant's remembered: a step's
  // last two stages and its end's guards share theirs.
  GroundAcceleration ground_at(double t) const {
    if (t != ground_t_) {
      ground_a_ = rocking::ground_at(ground_, vertical_, t);
      ground_t_ = t;
    }
    return ground_a_;
  }
  // The state's coordinates; in full contact theta = 0 (upright_, no trig call).
  Coordinates coordinates(Eigen::Ref<const Eigen::VectorXd> y) const {
    return {y.segment(u_, n_), y.segment(u_ + n_, n_), phase_.is_rocking() ? Tilt(y[0]) : upright_, y[1]};
  }
  double count() const { return c_.group.count; }
  double base_half_width() const { return c_.group.half_width; }
  const std::vector<ContactModel::Acting>& acting() const { return m_.acting[index(*phase_.pivot())]; }

  // While rocking: the n alike devices' moment n sum F de/d|theta| with the
  // beam devices' sum F de/d|theta|, D [N m], with their states' rates into
  // dydt (when given) and the power on each device (a column device's n
  // copies) into power_ (the acting ones; the others 0).
  double device_terms(Eigen::Ref<const Eigen::VectorXd> y, const Tilt& tilt, double* dydt) {
    if (m_.devices.empty() || !phase_.is_rocking()) return 0.0;
    std::fill(power_.begin(), power_.end(), 0.0);
    double* rates = dydt != nullptr ? dydt : scratch_.data();
    double moment = 0;
    for (const ContactModel::Acting& a : acting()) {
      const ContactModel::DeviceTerms t = a.terms(a, devices_, base_half_width(), pivot(), tilt, y[1], y.data(), rates);
      moment += t.moment;
      power_[static_cast<std::size_t>(a.device)] = count() * t.power;
    }
    moment *= count();
    for (const ColumnsModel::BeamDevice& d : cm_.beam_devices) {
      if (devices_.is_broken(d.device)) {
        if (d.slot) rates[*d.slot] = 0.0;
        continue;
      }
      const Stretch st = beam_stretch(d, tilt);
      const double e_dot = st.de_dtheta * sign(pivot()) * y[1];
      const LawResponse f = law_force_and_rate(law(d), st.e, e_dot, d.slot ? y[*d.slot] : 0.0);
      if (d.slot) rates[*d.slot] = f.rate;
      moment += f.F * st.de_dtheta;
      power_[static_cast<std::size_t>(d.device)] = f.F * e_dot;
    }
    return moment;
  }

  // A beam device's law, and its stretch while rocking about pivot().
  const DeviceLaw& law(const ColumnsModel::BeamDevice& d) const { return m_.devices[static_cast<std::size_t>(d.device)].law; }
  Stretch beam_stretch(const ColumnsModel::BeamDevice& d, const Tilt& tilt) const {
    return beam_device_stretch(c_, d.ground_x, d.ground_y, d.beam_x, 2.0 * c_.group.half_height, 0.0, pivot(), tilt);
  }

  // The beam devices' force on the deck (at rest in full contact): each
  // intact one's law at its stretch, rate and state.
  DeckLoad beam_load(Eigen::Ref<const Eigen::VectorXd> y) const {
    DeckLoad total;
    const Tilt tilt(y[0]);
    for (const ColumnsModel::BeamDevice& d : cm_.beam_devices) {
      if (devices_.is_broken(d.device)) continue;
      const double z = d.slot ? (phase_.is_rocking() ? y[*d.slot] : devices_.z(d.device)) : 0.0;
      double F = law_force(law(d), 0.0, 0.0, z);
      if (phase_.is_rocking()) {
        const Stretch st = beam_stretch(d, tilt);
        F = law_force(law(d), st.e, st.de_dtheta * sign(pivot()) * y[1], z);
      }
      const DeckLoad l =
          beam_device_load(c_, d.ground_x, d.ground_y, d.beam_x, 2.0 * c_.group.half_height, phase_, tilt, F);
      total.fx += l.fx;
      total.fy += l.fy;
      total.moment += l.moment;
    }
    return total;
  }

  void derivatives(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> dydt) {
    const GroundAcceleration a = ground_at(t);
    // The devices' states rest unless the pivot's acting devices write theirs.
    dydt.segment(2, u_ - 2).setZero();
    dydt.tail(size_ - work_ - 2).setZero();
    const Coordinates q = coordinates(y);  // one tilt for the whole right-hand side
    if (!phase_.is_rocking()) {
      full_contact_acceleration(c_, a.h, q.u, q.u_dot, dydt.segment(u_, 2 * n_));
      dydt[0] = 0.0;  // a closed frame's theta stays 0
      dydt[1] = 0.0;
    } else {
      const double moment = device_terms(y, q.tilt, dydt.data());
      dydt[0] = y[1];
      dydt[1] = rocking_acceleration(c_, pivot(), a, moment, q, dydt.segment(u_, 2 * n_));
      if (!m_.devices.empty()) {
        double total = 0;
        for (std::size_t k = 0; k < power_.size(); ++k) {
          dydt[work_ + 3 + static_cast<Eigen::Index>(k)] = power_[k];
          total += power_[k];
        }
        dydt[work_ + 2] = total;
      }
    }
    dydt[work_] = ground_input_power(c_, phase_, a, q);
    dydt[work_ + 1] = viscous_power(c_, q.u_dot);
  }

  // The moment the intact devices hold against uplift about p at rest: n sum
  // F(e = 0) l, and F(e = 0) de/d|theta| of each beam device.
  double held(Pivot p) const {
    if (m_.devices.empty()) return 0.0;
    double moment = count() * held_moment(m_, devices_, p);
    for (const ColumnsModel::BeamDevice& d : cm_.beam_devices)
      if (!devices_.is_broken(d.device)) moment += law_force_at_rest(law(d), devices_.z(d.device)) * d.lever[index(p)];
    return moment;
  }

  // The column-top contact forces now (normal_ filled).
  // (At the accelerations the phase's equations give now, with the devices'
  // moment while rocking.)
  TopContact top_forces(GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y) {
    return top_forces(a, y, coordinates(y));
  }
  TopContact top_forces(GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y, const Coordinates& q) {
    const double moment = phase_.is_rocking() ? device_terms(y, q.tilt, nullptr) : 0.0;
    return top_contact_forces_now(c_, phase_, a, q, moment, normal_, cm_.beam_devices.empty() ? DeckLoad{} : beam_load(y));
  }

  // The deck at an instant: the smallest column-top force and the beam's
  // translation dx, remembered at the guards' samples: the step's samples
  // for the outputs are the same times and states (the integrator's
  // buffers), which need not be worked out twice.
  struct Deck {
    double smallest = 0, dx = 0;
  };
  struct Remembered {
    double t = 0;
    Eigen::VectorXd y;
    Deck deck;
  };
  Deck deck_now(GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y) {
    const Coordinates q = coordinates(y);
    return {top_forces(a, y, q).smallest, phase_.is_rocking() ? beam_motion(c_, pivot(), q.tilt).dx : 0.0};
  }
  double remembered_top_force(double t, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y) {
    Remembered& r = remembered_[next_remembered_];
    next_remembered_ = (next_remembered_ + 1) % remembered_.size();
    r.t = t;
    r.y = y;
    r.deck = deck_now(a, y);
    held_remembered_ = std::min(held_remembered_ + 1, remembered_.size());
    return r.deck.smallest;
  }
  // (The latest first: a step's samples follow its guards' last samples.)
  Deck deck_at(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    const std::size_t size = remembered_.size();
    for (std::size_t k = 1; k <= held_remembered_; ++k) {
      const Remembered& r = remembered_[(next_remembered_ + size - k) % size];
      if (r.t == t && std::memcmp(r.y.data(), y.data(), sizeof(double) * static_cast<std::size_t>(size_)) == 0)
        return r.deck;
    }
    return deck_now(ground_at(t), y);
  }

  void initial_state() {
    const InitialState& init = opt_.initial;
    for (const auto& [v, at, what] : {std::tuple{&init.u, u_, "u"}, std::tuple{&init.u_dot, u_ + n_, "u_dot"}}) {
      if (v->size() == 0) continue;
      if (v->size() != n_)
        throw InputError(fmt::format("initial {}: {} entries for a structure with {} elastic coordinates on the columns",
                                     what, v->size(), n_));
      y_.segment(at, n_) = *v;
    }
    if (init.theta == 0 && init.theta_dot == 0) return;
    set_phase(Phase::rocking(init.theta > 0 || (init.theta == 0 && init.theta_dot > 0) ? Pivot::right : Pivot::left));
    y_[0] = init.theta;
    y_[1] = init.theta_dot;
  }

  double mechanical() { return mechanical_energy(c_, phase_, coordinates(y_)).total(); }

  // In full contact (at the start or after an impact): lift now if the uplift
  // condition already holds about one side.
  void lift_if_lifting(double t) {
    if (phase_.is_rocking() || !cm_.rocking) return;
    const GroundAcceleration a = ground_at(t);
    for (Pivot p : pivots)
      if (uplift_guard(c_, p, a, held(p), y_.segment(u_, n_), y_.segment(u_ + n_, n_)) > 0) {
        lift(p, t);
        return;
      }
  }

  // The phase, with the devices': the acting devices of a new rocking phase
  // resume the states they kept.
  void set_phase(Phase phase) {
    phase_ = phase;
    devices_.phase = phase;
    if (phase.is_rocking()) {
      for (const ContactModel::Acting& a : acting())
        if (a.slot) y_[*a.slot] = devices_.z(a.device);
      for (const ColumnsModel::BeamDevice& d : cm_.beam_devices)
        if (d.slot) y_[*d.slot] = devices_.z(d.device);
    }
  }

  // The acting devices keep their states for their next rocking phase.
  void keep_device_states() {
    for (const ContactModel::Acting& a : acting())
      if (a.slot) devices_.set_z(a.device, y_[*a.slot]);
    for (const ColumnsModel::BeamDevice& d : cm_.beam_devices)
      if (d.slot) devices_.set_z(d.device, y_[*d.slot]);
  }

  void lift(Pivot p, double t) {
    y_[0] = 0;
    y_[1] = 0;
    set_phase(Phase::rocking(p));
    if (result_.counts.uplifts++ == 0) result_.first_uplift = t;
    announce({EventKind::uplift, t, p, std::nullopt});
  }

  void announce(const Event& e) {
    if (observer_ != nullptr) observer_->event(e);
  }

  void restart(double t) {
    held_remembered_ = next_remembered_ = 0;
    guards_.clear();
    std::vector<ode::Direction> directions;
    if (phase_.is_rocking()) {
      guards_.push_back({ColumnsGuard::impact, *phase_.pivot()});
      directions.push_back(ode::Direction::falling);
      guards_.push_back({ColumnsGuard::overturn, *phase_.pivot()});
      directions.push_back(ode::Direction::rising);
      for (int i : m_.breakable[index(*phase_.pivot())]) {
        guards_.push_back({ColumnsGuard::fracture, *phase_.pivot(), i});
        directions.push_back(ode::Direction::rising);
      }
      for (std::size_t i = 0; i < cm_.beam_devices.size(); ++i)
        if (m_.devices[static_cast<std::size_t>(cm_.beam_devices[i].device)].capacity > 0) {
          guards_.push_back({ColumnsGuard::fracture, *phase_.pivot(), 0, static_cast<int>(i)});
          directions.push_back(ode::Direction::rising);
        }
    } else if (cm_.rocking) {
      for (Pivot p : pivots) {
        guards_.push_back({ColumnsGuard::uplift, p});
        directions.push_back(ode::Direction::rising);
      }
    }
    guards_.push_back({ColumnsGuard::tension});
    directions.push_back(ode::Direction::falling);
    ode::Guards guards{[this](double tg, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& g) {
                         guard_values(tg, y, g);
                       },
                       std::move(directions)};
    active_ = !phase_.is_rocking() && exact_ ? exact_.get() : integrator_.get();
    active_->reset(t, y_, std::move(guards));
    const TopContact top = top_forces(ground_at(t), y_);
    if (top.smallest < 0) tension(t);
    emit(t, y_);
  }

  void guard_values(double t, Eigen::Ref<const Eigen::VectorXd> y, Eigen::Ref<Eigen::VectorXd> g) {
    const GroundAcceleration a = ground_at(t);
    for (std::size_t k = 0; k < guards_.size(); ++k) {
      const ColumnsGuardDef& d = guards_[k];
      const double sd = sign(d.pivot);
      switch (d.what) {
        case ColumnsGuard::uplift:
          g[k] = uplift_guard(c_, d.pivot, a, held(d.pivot), y.segment(u_, n_), y.segment(u_ + n_, n_));
          break;
        case ColumnsGuard::impact: g[k] = sd * y[0]; break;
        case ColumnsGuard::overturn: g[k] = sd * y[0] - cm_.overturn_angle; break;
        case ColumnsGuard::tension: g[k] = remembered_top_force(t, a, y); break;
        case ColumnsGuard::fracture: {
          if (d.beam >= 0) {
            const ColumnsModel::BeamDevice& dev = cm_.beam_devices[static_cast<std::size_t>(d.beam)];
            g[k] = devices_.is_broken(dev.device)
                       ? -1.0
                       : beam_stretch(dev, Tilt(y[0])).e - m_.devices[static_cast<std::size_t>(dev.device)].capacity;
            break;
          }
          const ContactModel::Acting& dev = acting()[static_cast<std::size_t>(d.acting)];
          g[k] = devices_.is_broken(dev.device)
                     ? -1.0
                     : stretch(dev.geometry, base_half_width(), pivot(), Tilt(y[0])).e - dev.capacity;
          break;
        }
      }
    }
  }

  // A column-top contact force turned tensile: the cap beam would lift off a
  // column, which the model assumes it does not (MODEL.md 16). The run ends
  // there, `separated`, as a joint in tension ends a chain's.
  struct Separation {
    std::string what;
  };
  [[noreturn]] void tension(double t) {
    throw Separation{fmt::format("the cap beam at t = {:.9g} s: a column-top contact force turned tensile, so the "
                                 "beam would lift off a column, which the model assumes it does not (MODEL.md 16)",
                                 t)};
  }

  void loop() {
    while (active_->time() < t_end_) {
      check_stop(opt_, active_->time());
      const ode::StepReport rep = active_->step(t_end_);
      sample_step();
      if (rep.reason == ode::Stop::event) {
        if (!handle_event(guards_[static_cast<std::size_t>(rep.guard)], rep.t)) return;
      } else if (phase_.sign() * active_->state()[0] < 0) {
        // Round-off right after an uplift can put theta on the wrong side
        // without a crossing: treat it as the impact it is.
        if (!handle_event({ColumnsGuard::impact, *phase_.pivot()}, active_->time())) return;
      }
    }
  }

  // Returns false when the run ends (overturning).
  bool handle_event(const ColumnsGuardDef& d, double t) {
    y_ = active_->state();
    count_phase_change(events_, opt_, t);
    switch (d.what) {
      case ColumnsGuard::uplift: lift(d.pivot, t); break;
      case ColumnsGuard::impact: impact(t); break;
      case ColumnsGuard::overturn:
        announce({EventKind::overturn, t, d.pivot, std::nullopt});
        result_.outcome = Outcome::overturned;
        return false;
      case ColumnsGuard::tension: tension(t);
      case ColumnsGuard::fracture: {
        const int device = d.beam >= 0 ? cm_.beam_devices[static_cast<std::size_t>(d.beam)].device
                                       : acting()[static_cast<std::size_t>(d.acting)].device;
        announce({EventKind::fracture, t, d.pivot, device});
        fracture(devices_, device);
        result_.devices[static_cast<std::size_t>(device)].fracture_time = t;
        break;
      }
    }
    peaks_.break_continuity();
    restart(t);
    return true;
  }

  // Impact at theta = 0: the momentum law or a given r (rocking.columns' impact).
  void impact(double t) {
    const Pivot p = *phase_.pivot();
    announce({EventKind::impact, t, p, std::nullopt});
    y_[0] = 0;
    const double before = mechanical();
    keep_device_states();
    Eigen::VectorXd u_dot = y_.segment(u_ + n_, n_);
    const ColumnsImpact out = rocking::impact(c_, p, y_[1], u_dot, cm_.restitution, cm_.theta_dot_min);
    y_.segment(u_ + n_, n_) = u_dot;
    set_phase(out.after);
    y_[1] = out.theta_dot;
    result_.energy.impacts += before - mechanical();
    if (result_.counts.impacts++ == 0) result_.first_impact = t;
    lift_if_lifting(t);
  }

  // The structure's response on the cap beam (its fixed-base outputs) with the
  // drift from the ground and the columns' quantities, the top forces among them.
  Response response(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    const Layout& l = m_.layout;
    if (l.u.present()) {
      from_nodal(m_.body, y.segment(u_, n_), fixed_.segment(l.u.start, l.n));
      from_nodal(m_.body, y.segment(u_ + n_, n_), fixed_.segment(l.u_dot.start, l.n));
    }
    Response r = evaluate(m_, scales_, contact_, t, fixed_);
    r.phase = phase_;
    r[Quantity::phase] = phase_.sign();
    const Deck deck = deck_at(t, y);
    const double dx = deck.dx;
    const double u_top = n_ > 0 ? y[u_ + n_ - 1] : 0.0;
    r[Quantity::delta_t] = (dx + u_top) * scales_.inverse_H_N;
    r[Quantity::columns_theta] = y[0];
    r[Quantity::columns_theta_over_alpha] = y[0] / c_.alpha;
    r[Quantity::columns_theta_dot] = y[1];
    r[Quantity::beam_x] = dx;
    r[Quantity::columns_top_force] = deck.smallest;
    ColumnsResult& cr = *result_.columns;
    if (deck.smallest < cr.smallest_top_force) {
      cr.smallest_top_force = deck.smallest;
      cr.smallest_top_force_time = t;
    }
    return r;
  }

  void sample_step() {
    const int count = active_->sample_count();
    const double t0 = active_->previous_time(), t1 = active_->time();
    for (int k = 1; k <= count; ++k) {
      const Eigen::VectorXd& y = active_->sample(k, count);
      const Response r = response(ode::Integrator::sample_time(t0, t1, k, count), y);
      peaks_.add(r.t, r.q);
      device_peaks(y);
    }
    if (observer_ == nullptr) return;
    history_.rows(*active_, dense_, [this](double t, const Eigen::VectorXd& y) { history_row(t, y); });
  }

  // Each device's elongation and force (a column device's in one column; NaN once broken) into
  // samples_, with the moment its n copies exert against the tilt; returns
  // the sum of those moments, M_dev [N m].
  double sample_devices(Eigen::Ref<const Eigen::VectorXd> y) {
    samples_.assign(m_.devices.size(), DeviceSample{});
    for (std::size_t k = 0; k < samples_.size(); ++k) {
      if (devices_.is_broken(static_cast<int>(k))) samples_[k] = {std::nan(""), std::nan(""), 0.0};
      samples_[k].work = y[work_ + 3 + static_cast<Eigen::Index>(k)];
    }
    if (!phase_.is_rocking()) return 0.0;
    const Tilt tilt(y[0]);
    double moment = 0;
    for (const ContactModel::Acting& a : acting()) {
      if (devices_.is_broken(a.device)) continue;
      const DamperState st = a.state(a, devices_, base_half_width(), pivot(), tilt, y[1], y.data());
      const double de_dtheta = stretch(a.geometry, base_half_width(), pivot(), tilt).de_dtheta;
      DeviceSample& out = samples_[static_cast<std::size_t>(a.device)];
      out.e = st.elongation;
      out.F = st.force;
      out.moment = count() * sign(pivot()) * st.force * de_dtheta;
      moment += out.moment;
    }
    for (const ColumnsModel::BeamDevice& d : cm_.beam_devices) {
      if (devices_.is_broken(d.device)) continue;
      const Stretch st = beam_stretch(d, tilt);
      const double F = law_force(law(d), st.e, st.de_dtheta * sign(pivot()) * y[1], d.slot ? y[*d.slot] : 0.0);
      DeviceSample& out = samples_[static_cast<std::size_t>(d.device)];
      out.e = st.e;
      out.F = F;
      out.moment = sign(pivot()) * F * st.de_dtheta;
      moment += out.moment;
    }
    return moment;
  }

  // Peak elongation and force of the intact devices.
  void device_peaks(Eigen::Ref<const Eigen::VectorXd> y) {
    if (m_.devices.empty() || !phase_.is_rocking()) return;
    sample_devices(y);
    for (std::size_t k = 0; k < samples_.size(); ++k) {
      if (devices_.is_broken(static_cast<int>(k))) continue;  // its peaks are those it had when it broke
      DeviceResult& out = result_.devices[k];
      out.peak_elongation = std::max(out.peak_elongation, samples_[k].e);
      out.peak_force = std::max(out.peak_force, std::abs(samples_[k].F));
    }
  }

  // A history row, with the energy balance's terms so far (MODEL.md 7): the
  // state's mechanical energy, the ground's, the damping's and the devices'
  // accumulators, the impacts' losses up to now.
  void history_row(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    last_row_ = t;
    Response r = response(t, y);
    r[Quantity::a_g] = ground_.acceleration(t);
    r[Quantity::a_v] = vertical_ ? vertical_->acceleration(t) : 0.0;
    r[Quantity::x_g] = travel_.at(t).d;
    r[Quantity::energy] = mechanical_energy(c_, phase_, coordinates(y)).total();
    r[Quantity::work_ground] = y[work_];
    r[Quantity::work_viscous] = y[work_ + 1];
    r[Quantity::work_devices] = y[work_ + 2];
    r[Quantity::work_impacts] = result_.energy.impacts;
    if (!m_.devices.empty()) {
      r[Quantity::device_moment] = sample_devices(y);
      observer_->devices(samples_);
    }
    observer_->nodal(y.segment(u_, n_), y.segment(u_ + n_, n_));
    observer_->record(r);
  }

  void emit(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    const Response r = response(t, y);
    peaks_.add(r.t, r.q);
    device_peaks(y);
    if (observer_ != nullptr) history_row(t, y);
  }

  void finish() {
    y_ = active_->state();
    result_.t_end = active_->time();
    result_.final_phase = phase_;
    result_.final_theta = y_[0];
    result_.final_state = y_;
    result_.peaks = peaks_.peaks();
    result_.top_total_mm = result_.peak(Quantity::delta_t) * scales_.H_N * 1000.0;
    result_.stats = run_stats(*integrator_, exact_.get());
    result_.energy.final = mechanical();
    result_.energy.ground = y_[work_];
    result_.energy.viscous = y_[work_ + 1];
    result_.energy.damper = y_[work_ + 2];
    for (std::size_t k = 0; k < result_.devices.size(); ++k)
      result_.devices[k].work = y_[work_ + 3 + static_cast<Eigen::Index>(k)];
    if (opt_.final_row && observer_ != nullptr && opt_.output_interval > 0 && last_row_ < result_.t_end)
      history_row(result_.t_end, y_);
  }

  const ContactModel& m_;
  const ColumnsModel& cm_;
  const Columns& c_;
  const GroundMotion& ground_;
  const GroundMotion* vertical_;
  const RunOptions& opt_;
  Observer* observer_;
  OutputScales scales_;
  // Elastic coordinates; where u and the works start in the state; its size.
  Eigen::Index n_, u_, work_, size_;
  mutable double ground_t_ = std::numeric_limits<double>::quiet_NaN();
  mutable GroundAcceleration ground_a_;
  Phase phase_;
  const Tilt upright_{0.0};
  Discrete contact_;  // the structure's own phase on the beam: full contact
  Discrete devices_;  // the devices': the columns' phase, the states kept, the fractures
  std::vector<double> power_ = std::vector<double>(m_.devices.size(), 0.0);  // on each device's n copies [W]
  Eigen::VectorXd scratch_ = Eigen::VectorXd::Zero(size_);  // the state rates device_terms writes when not asked
  std::vector<DeviceSample> samples_;
  Eigen::VectorXd y_, dense_, fixed_;
  double last_row_ = -std::numeric_limits<double>::infinity();  // the last history row's time
  std::vector<double> normal_;
  std::vector<ColumnsGuardDef> guards_;
  GroundTravel travel_{ground_};
  std::unique_ptr<ode::Integrator> integrator_, exact_;  // the backend; full contact under a record
  ode::Integrator* active_ = nullptr;                    // the one stepping the current phase
  double t_end_ = 0;
  long events_ = 0;
  HistoryGrid history_;
  PeakTracker<> peaks_;
  RunResult result_;
  // As many as a step has guard samples (the exact stepping's most).
  std::vector<Remembered> remembered_ = std::vector<Remembered>(16, Remembered{0.0, y_, {}});
  std::size_t next_remembered_ = 0, held_remembered_ = 0;
};

}  // namespace

RunResult simulate_columns(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                           Observer* observer) {
  return timed_run<ColumnsDriver>(m, ground, options, observer);
}

}  // namespace rocking
