module;
#include <rocking/eigen.hpp>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <new>
#include <numbers>
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

// The model in the elastic coordinates the run integrates in (RunOptions::
// coordinates) with this backend: a modal copy when the model is nodal and
// the run wants the modes; null when the model serves as it is.
std::unique_ptr<const ContactModel> recast(const ContactModel& m, ode::Backend backend, const RunOptions& o) {
  if (!m.layout.u.present() || m.body.coordinates == ElasticCoordinates::modal) return nullptr;
  const bool modal = backend == ode::Backend::rosw ||
                     o.coordinates.value_or(ElasticCoordinates::nodal) == ElasticCoordinates::modal;
  if (!modal) return nullptr;
  return std::make_unique<const ContactModel>(in_modal_coordinates(m));
}

class Driver {
 public:
  Driver(const ContactModel& given, const GroundMotion& ground, const RunOptions& o, Observer* observer)
      : backend_(choose_backend(given, ground, o.backend)), own_(recast(given, backend_, o)),
        m_(own_ ? *own_ : given), ground_(ground), vertical_(ground.vertical()), opt_(o), observer_(observer),
        scales_(output_scales(m_)),
        y_(Eigen::VectorXd::Zero(m_.layout.size)), dense_(m_.layout.size) {
    // The parameters bind to the std::function's own arguments: no Ref is copied per call.
    auto rhs = [this](double t, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& dydt) {
      phase_rhs(m_, d_, ground_at(t), y, dydt);
    };
    ode::Options tolerances = o.tolerances;
    tolerances.max_step = std::min(tolerances.max_step, ground.max_step());
    if (vertical_) tolerances.max_step = std::min(tolerances.max_step, vertical_->max_step());
    // The energy accumulators (the tail of the state) are integrals that
    // nothing depends on: they do not steer the steps, so that a run that
    // tracks the energy balance steps as one that does not, to the same peaks.
    if (m_.layout.energy.present()) tolerances.error_components = m_.layout.energy.start;
    // Guards and peaks sampled 8 times in the shortest period of a mode that
    // oscillates (the exact steps below do the same), not more densely when
    // steps are short.
    if (m_.layout.u.present()) tolerances.sample_spacing = shortest_period(m_) / 8;
    // rosw solves with the stiff elastic part of the current phase.
    ode::LinearSolve stiff;
    if (backend_ == ode::Backend::rosw && m_.layout.u.present()) {
      stiff_ = std::make_unique<StiffPart>(m_);
      stiff = [this](double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x) {
        stiff_->solve(d_.phase, g, b, x);
      };
    }
    integrator_ = ode::make_integrator(backend_, m_.layout.size, rhs, tolerances, std::move(stiff));
    t_end_ = o.duration > 0 ? o.duration : ground.duration();
    // An automatic choice of rosw integrates full contact too: its steps are
    // not bound by the highest modes, and it then costs less than the exact
    // steps, which sample every oscillating period (`rocking tradeoff --scenes`).
    const bool auto_rosw = o.backend == ode::Backend::automatic && backend_ == ode::Backend::rosw;
    if (o.exact_full_contact && !auto_rosw && m_.layout.u.present() && ground.piecewise_linear() &&
        (!vertical_ || vertical_->piecewise_linear()))
      exact_ = exact_full_contact(m_, m_.layout.size, m_.layout.u.start,
                                  m_.layout.energy.present() ? std::optional(m_.layout.energy.start) : std::nullopt,
                                  ground_, tolerances.max_steps);
    integrator_->set_breakpoints(record_samples(ground_));
    active_ = integrator_.get();
  }

  RunResult run() {
    result_.integrator = integrator_->name();
    result_.exact_full_contact = exact_ != nullptr;
    result_.presence = presence(m_);
    result_.energy_tracked = m_.layout.energy.present();
    for (const Device& dev : m_.devices)
      result_.devices.push_back({.name = dev.name,
                                 .law = law_name(dev.law),
                                 .force_at_rest = law_force_at_rest(dev.law, 0.0),
                                 .work = result_.energy_tracked ? 0.0 : std::nan("")});
    initial_state();
    result_.energy.initial = mechanical();
    next_output_ = opt_.output_interval;
    outputs_ = 1;
    try {
      begin_contact_if_lifting(0.0);
      restart(0.0);
      if (tilted_beyond_overturning()) {  // released past the point of no return: no crossing to locate
        announce({EventKind::overturn, 0.0, *d_.phase.pivot(), std::nullopt});
        result_.outcome = Outcome::overturned;
      } else {
        loop();
      }
    } catch (const ode::IntegrationError& e) {
      result_.outcome = Outcome::failed;
      result_.failure = fmt::format("{} (phase {}){}", e.what(), phase_name(d_.phase), failure_cause(e));
    } catch (const RunError& e) {
      result_.outcome = Outcome::failed;
      result_.failure = fmt::format("{} (phase {})", e.what(), phase_name(d_.phase));
    }
    finish();
    return result_;
  }

 private:
  // What made a run's state non-finite or its step vanish, in terms of the
  // input: the part of the state (and its rate) that is not finite at the
  // failure names the values that drive it; a step that vanished on finite
  // values at the start is the scene's values, too fast for any step.
  std::string failure_cause(const ode::IntegrationError& e) const {
    using Kind = ode::IntegrationError::Kind;
    if (e.kind() != Kind::non_finite_state && e.kind() != Kind::step_size_underflow) return {};
    const Layout& l = m_.layout;
    Eigen::VectorXd y = active_ != nullptr ? Eigen::VectorXd(active_->state()) : y_;
    Eigen::VectorXd dydt = Eigen::VectorXd::Zero(y.size());
    if (y.allFinite()) phase_rhs(m_, d_, ground_at(e.time()), y, dydt);
    auto bad = [&](const StateRange& r) {
      return r.count > 0 && !(y.segment(r.start, r.count).allFinite() && dydt.segment(r.start, r.count).allFinite());
    };
    std::string names;
    for (const Device& dev : m_.devices) names += (names.empty() ? "" : ", ") + dev.name;
    if (bad(l.z))
      return fmt::format(": the devices' hysteresis ({}): their parameters (a yield elongation d_y or a sharpness n "
                         "against the stiffness k) drive it beyond what the run can follow", names);
    if (bad(l.u) || bad(l.u_dot))
      return ": the structure's elastic motion: check initial.u, initial.u_dot and the structure's stiffness and masses";
    if (bad(l.theta) || bad(l.theta_dot))
      return ": the rocking motion: check initial.theta, initial.theta_dot and the ground motion's scale";
    if (e.time() <= 1e-9 * std::max(1.0, t_end_))
      return fmt::format(": at the start of the run, the scene's values (the devices' parameters{}{}, the initial "
                         "velocities, the ground motion) ask for a motion faster than any step can follow",
                         names.empty() ? "" : ": ", names);
    if (e.kind() == Kind::step_size_underflow)
      return fmt::format(": the scene's values ask for a motion faster than any step can follow here (the devices' "
                         "parameters{}{}: a small yield elongation against a large stiffness; the structure's "
                         "stiffness and masses; the ground motion)", names.empty() ? "" : ": ", names);
    return {};
  }

  // The ground's acceleration at t: along the plane, and upward when shaken so.
  GroundAcceleration ground_at(double t) const {
    return vertical_ ? GroundAcceleration{ground_.acceleration(t), vertical_->acceleration(t)}
                     : GroundAcceleration{ground_.acceleration(t)};
  }

  void initial_state() {
    const InitialState& init = opt_.initial;
    const Layout& l = m_.layout;
    for (const auto& [v, at, what] : {std::tuple{&init.u, l.u.start, "u"}, std::tuple{&init.u_dot, l.u_dot.start, "u_dot"}}) {
      if (v->size() == 0) continue;
      if (at < 0 || v->size() != l.n)
        throw InputError(fmt::format("initial {}: {} entries for a model with {} elastic coordinates", what, v->size(), l.n));
      from_nodal(m_.body, *v, y_.segment(at, l.n));
    }
    if (init.theta == 0 && init.theta_dot == 0) return;
    if (m_.kind == ModelKind::fixed_base)
      throw InputError("an initial tilt needs a rocking scene (contact.rocking = true)");
    const bool right = init.theta > 0 || (init.theta == 0 && init.theta_dot > 0);
    begin_rocking(m_, d_, right ? Pivot::right : Pivot::left, y_);
    y_[l.theta.start] = init.theta;
    y_[l.theta_dot.start] = init.theta_dot;
  }

  bool tilted_beyond_overturning() const {
    return d_.phase.is_rocking() && std::abs(y_[m_.layout.theta.start]) >= m_.overturn_angle;
  }

  double mechanical() { return mechanical_energy(m_, d_.phase, y_); }

  // Full contact has begun at time t (start, or an impact): lift now if both
  // uplift conditions already hold (MODEL.md 6).
  void begin_contact_if_lifting(double t) {
    if (d_.phase.is_rocking()) return;
    if (const std::optional<Pivot> p = uplift_now(m_, d_, ground_at(t), y_)) lift(*p, t);
  }

  void lift(Pivot p, double t) {
    begin_rocking(m_, d_, p, y_);
    if (result_.counts.uplifts++ == 0) result_.first_uplift = t;
    announce({EventKind::uplift, t, p, std::nullopt});
  }

  void announce(const Event& e) {
    if (observer_ != nullptr) observer_->event(e);
  }

  void restart(double t) {
    ode::Guards guards;
    guards_ = phase_guards(m_, d_.phase);
    for (const PhaseGuard& g : guards_)
      guards.directions.push_back(g.crossing == Crossing::rising ? ode::Direction::rising : ode::Direction::falling);
    if (!guards.directions.empty())
      guards.fn = [this, reads = guard_inputs(m_, d_.phase, vertical_ != nullptr)](
                      double tg, const Eigen::Ref<const Eigen::VectorXd>& y, Eigen::Ref<Eigen::VectorXd>&& g) {
        guard_values(m_, d_,
                     {reads.horizontal ? ground_.acceleration(tg) : 0.0, reads.vertical ? vertical_->acceleration(tg) : 0.0},
                     y, g);
      };
    active_ = !d_.phase.is_rocking() && exact_ ? exact_.get() : integrator_.get();
    active_->reset(t, y_, std::move(guards));
    emit(t, y_, true);
  }

  void loop() {
    while (active_->time() < t_end_) {
      if (opt_.stop && opt_.stop())
        throw RunError(fmt::format("stopped at t = {:.6g} s on request", active_->time()));
      const ode::StepReport rep = active_->step(t_end_);
      sample_step();
      if (rep.reason == ode::Stop::event) {
        if (!handle_event(guards_[static_cast<std::size_t>(rep.guard)], rep.t)) return;
      } else if (d_.phase.sign() * active_->state()[m_.layout.theta.start] < 0) {
        // Only round-off right after an uplift can put theta on the wrong side
        // without a crossing: treat it as the impact it is.
        if (!handle_event({Guard::impact, Crossing::falling, {}}, active_->time())) return;
      }
    }
  }

  // Returns false when the run ends (overturning).
  bool handle_event(PhaseGuard meaning, double t) {
    const Guard what = meaning.what;
    y_ = active_->state();
    attribute_work();
    if (++events_ > opt_.max_events)
      throw RunError(fmt::format("phase change number {} at t = {:.9g} s exceeds the limit (chattering? raise "
                                 "contact.theta_dot_min or the event limit)", events_, t));
    switch (what) {
      case Guard::uplift_right:
      case Guard::uplift_left:
        lift(what == Guard::uplift_right ? Pivot::right : Pivot::left, t);
        break;
      case Guard::impact: {
        announce({EventKind::impact, t, *d_.phase.pivot(), std::nullopt});
        const double before = mechanical();
        impact(m_, d_, y_);
        result_.energy.impacts += before - mechanical();
        if (result_.counts.impacts++ == 0) result_.first_impact = t;
        begin_contact_if_lifting(t);
        break;
      }
      case Guard::overturn:
        announce({EventKind::overturn, t, *d_.phase.pivot(), std::nullopt});
        result_.outcome = Outcome::overturned;
        return false;
      case Guard::fracture: {
        const int device = meaning.device.value();  // a fracture guard always names its device
        announce({EventKind::fracture, t, *d_.phase.pivot(), device});
        fracture(d_, device);
        result_.devices[static_cast<std::size_t>(device)].fracture_time = t;
        break;
      }
    }
    peaks_.break_continuity();
    restart(t);
    return true;
  }

  // Peaks on samples of the last step's dense output; history rows on the grid.
  void sample_step() {
    const int count = active_->sample_count();  // the integrator's guard samples
    const double t0 = active_->previous_time(), t1 = active_->time();
    // The peak tracker reads each response as whole vectors, which cannot be
    // forwarded from the scalar stores that wrote it: responses are written
    // in place, a batch at a time, and tracked once those stores have completed.
    for (int first = 1; first <= count; first += static_cast<int>(batch_.size())) {
      const int last = std::min(count, first + static_cast<int>(batch_.size()) - 1);
      for (int k = first; k <= last; ++k) {
        const Eigen::VectorXd& y = active_->sample(k, count);  // the integrator's buffer, not a copy
        Response* r = ::new (&batch_[static_cast<std::size_t>(k - first)])
            Response(evaluate(m_, scales_, d_, ode::Integrator::sample_time(t0, t1, k, count), y));
        device_peaks(y, *r);
      }
      for (int k = first; k <= last; ++k) {
        const Response& r = batch_[static_cast<std::size_t>(k - first)];
        peaks_.add(r.t, r.q);
      }
    }
    if (observer_ == nullptr || !(opt_.output_interval > 0)) return;
    while (next_output_ <= active_->time()) {
      active_->dense(next_output_, dense_);
      observer_->record(history_row(next_output_, dense_));
      next_output_ = opt_.output_interval * static_cast<double>(++outputs_);
    }
  }

  // Peak elongation and force of the devices the current pivot stretches. When
  // the paper's damper is the only one, it is the response's (d, F_hd), already
  // evaluated.
  void device_peaks(Eigen::Ref<const Eigen::VectorXd> y, const Response& r) {
    if (!d_.phase.is_rocking() || m_.devices.empty()) return;
    const auto& acting = m_.acting[index(*d_.phase.pivot())];
    if (acting.size() == 1 && m_.devices[static_cast<std::size_t>(acting.front().device)].edge_damper) {
      const int k = acting.front().device;
      if (d_.is_broken(k)) return;
      DeviceResult& out = result_.devices[static_cast<std::size_t>(k)];
      out.peak_elongation = std::max(out.peak_elongation, std::abs(r[Quantity::damper_d]));
      out.peak_force = std::max(out.peak_force, std::abs(r[Quantity::damper_F]));
      return;
    }
    device_samples(m_, d_, y, samples_);
    for (std::size_t k = 0; k < samples_.size(); ++k) {
      if (d_.is_broken(static_cast<int>(k))) continue;  // its peaks are those it had when it broke
      DeviceResult& r = result_.devices[k];
      r.peak_elongation = std::max(r.peak_elongation, samples_[k].e);
      r.peak_force = std::max(r.peak_force, std::abs(samples_[k].F));
    }
  }

  // A history row: the response with the ground's acceleration and
  // displacement, the devices' moment and the energy balance's terms so far
  // (the accumulators of the state, the impacts' losses up to now), the
  // devices' samples and the nodal displacements handed over first.
  Response history_row(double t, Eigen::Ref<const Eigen::VectorXd> y) {
    last_row_ = t;
    Response r = evaluate(m_, scales_, d_, t, y);
    r[Quantity::a_g] = ground_.acceleration(t);
    r[Quantity::a_v] = vertical_ ? vertical_->acceleration(t) : 0.0;
    r[Quantity::x_g] = travel_.at(t).d;
    if (m_.layout.energy.present()) {
      const Eigen::Index e = m_.layout.energy.start;
      r[Quantity::energy] = mechanical_energy(m_, d_.phase, y);
      r[Quantity::work_ground] = y[e];
      r[Quantity::work_viscous] = y[e + 1];
      r[Quantity::work_devices] = y[e + 2];
      r[Quantity::work_impacts] = result_.energy.impacts;
    }
    pass_nodal(y);
    if (!m_.devices.empty()) {
      device_samples(m_, d_, y, samples_);
      device_works(y);
      double moment = 0;
      for (const DeviceSample& s : samples_) moment += s.moment;
      r[Quantity::device_moment] = moment;
      observer_->devices(samples_);
    }
    return r;
  }

  // The work done on each device up to the state y (into samples_): its own
  // accumulator when some pivot stretches several; else what attribute_work
  // gave it up to the last event, and to the device the pivot stretches now
  // the total's growth since. NaN when the energy is not tracked.
  void device_works(Eigen::Ref<const Eigen::VectorXd> y) {
    const Layout& l = m_.layout;
    for (std::size_t k = 0; k < samples_.size(); ++k)
      samples_[k].work = !l.energy.present() ? std::nan("")
                         : l.energy.count > 3 ? y[l.energy.start + 3 + static_cast<Eigen::Index>(k)]
                                              : result_.devices[k].work;
    if (!l.energy.present() || l.energy.count > 3) return;
    if (const std::optional<Pivot> p = d_.phase.pivot())
      for (const ContactModel::Acting& a : m_.acting[index(*p)])
        samples_[static_cast<std::size_t>(a.device)].work += y[l.energy.start + 2] - work_at_event_;
  }

  void emit(double t, Eigen::Ref<const Eigen::VectorXd> y, bool also_history) {
    const Response r = evaluate(m_, scales_, d_, t, y);
    peaks_.add(r.t, r.q);
    device_peaks(y, r);
    if (also_history && observer_ != nullptr) {
      observer_->record(history_row(t, y));
    }
  }

  void pass_nodal(Eigen::Ref<const Eigen::VectorXd> y) {
    const Layout& l = m_.layout;
    if (!l.u.present()) {
      observer_->nodal(y.head(0), y.head(0));
      return;
    }
    nodal_.resize(l.n);
    to_nodal(m_.body, y.segment(l.u.start, l.n), nodal_);
    nodal_dot_.resize(observer_->wants_velocities() ? l.n : 0);
    if (nodal_dot_.size() > 0) to_nodal(m_.body, y.segment(l.u_dot.start, l.n), nodal_dot_);
    observer_->nodal(nodal_, nodal_dot_);
  }

  // Without an accumulator per device (no pivot stretches two), the work on
  // the devices done since the last event is the one acting device's.
  void attribute_work() {
    const Layout& l = m_.layout;
    if (!l.energy.present() || l.energy.count > 3) return;
    const double total = y_[l.energy.start + 2];
    if (const std::optional<Pivot> p = d_.phase.pivot())
      for (const ContactModel::Acting& a : m_.acting[index(*p)])
        result_.devices[static_cast<std::size_t>(a.device)].work += total - work_at_event_;
    work_at_event_ = total;
  }

  void finish() {
    y_ = active_->state();
    attribute_work();
    result_.t_end = active_->time();
    result_.final_phase = d_.phase;
    result_.final_theta = m_.layout.theta.present() ? y_[m_.layout.theta.start] : 0.0;
    result_.final_state = y_;
    const Layout& l = m_.layout;
    if (l.u.present()) {
      to_nodal(m_.body, y_.segment(l.u.start, l.n), result_.final_state.segment(l.u.start, l.n));
      to_nodal(m_.body, y_.segment(l.u_dot.start, l.n), result_.final_state.segment(l.u_dot.start, l.n));
    }
    result_.peaks = peaks_.peaks();
    result_.top_total_mm = result_.peak(Quantity::delta_t) * scales_.H_N * 1000.0;
    result_.stats = run_stats(*integrator_, exact_.get());
    result_.energy.final = mechanical();
    if (m_.layout.energy.present()) {
      result_.energy.ground = y_[m_.layout.energy.start];
      result_.energy.viscous = y_[m_.layout.energy.start + 1];
      result_.energy.damper = y_[m_.layout.energy.start + 2];
      for (std::size_t k = 0; k < result_.devices.size() && m_.layout.energy.count > 3; ++k)
        result_.devices[k].work = y_[m_.layout.energy.start + 3 + static_cast<Eigen::Index>(k)];
    }
    if (opt_.final_row && observer_ != nullptr && opt_.output_interval > 0 && last_row_ < result_.t_end)
      observer_->record(history_row(result_.t_end, y_));
  }

  ode::Backend backend_;                     // choose_backend's
  std::unique_ptr<const ContactModel> own_;  // the model in other coordinates (recast)
  const ContactModel& m_;
  const GroundMotion& ground_;
  const GroundMotion* vertical_;  // null: no vertical shaking
  const RunOptions& opt_;
  Observer* observer_;
  OutputScales scales_;
  Discrete d_;
  Eigen::VectorXd y_, dense_, nodal_, nodal_dot_;
  std::vector<DeviceSample> samples_;
  std::vector<PhaseGuard> guards_;                       // the current phase's, in the integrator's order
  GroundTravel travel_{ground_};                         // x_g at the history's rows
  std::unique_ptr<StiffPart> stiff_;                     // rosw's linear solves
  std::unique_ptr<ode::Integrator> integrator_, exact_;  // the backend; full contact under a record
  ode::Integrator* active_ = nullptr;                    // the one stepping the current phase
  double t_end_ = 0, next_output_ = 0, work_at_event_ = 0;
  double last_row_ = -std::numeric_limits<double>::infinity();  // the last history row's time
  long outputs_ = 0, events_ = 0;
  PeakTracker<peak_quantities_without<Needs::columns>()> peaks_;
  std::array<Response, 4> batch_;  // samples awaiting the peak tracker
  RunResult result_;
};

}  // namespace

ode::Backend choose_backend(const ContactModel& m, const GroundMotion& ground, ode::Backend requested) {
  if (requested != ode::Backend::automatic) return requested;
  if (!m.layout.u.present()) return ode::Backend::rk45;
  const Rayleigh& ray = m.body.matrices.rayleigh;
  double fastest = 0;
  for (double w : m.body.matrices.fixed_base.omega) {
    const double c = ray.a0 + ray.a1 * w * w;  // lambda^2 + c lambda + w^2 = 0
    fastest = std::max(fastest, c > 2 * w ? 0.5 * (c + std::sqrt(c * c - 4 * w * w)) : w);
  }
  const std::size_t samples = ground.sample_count();
  const double pace = ground.piecewise_linear() && samples > 1
                          ? ground.duration() / static_cast<double>(samples - 1)
                          : ground.max_step();
  // rk45 with exact full contact stays the cheaper while its stability
  // limit is above 1/32 of the pace: on the 8-node tower under El Centro
  // (limit pace / 9) it takes 0.4 of rosw's steps and about half its time,
  // on the 16-node one (limit pace / 180) ten times rosw's (tower_bench).
  return std::isfinite(pace) && 3.3 / fastest < pace / 32 ? ode::Backend::rosw : ode::Backend::rk45;
}

RunResult simulate(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                   Observer* observer) {
  // The run's wall time counts its set-up: the integrators, the exact steps'
  // eigen forms, the output scales.
  if (m.jointed) return simulate_chain(m, ground, options, observer);  // MODEL.md 15: chain_run.cpp
  if (m.on_columns) return simulate_columns(m, ground, options, observer);  // MODEL.md 16: columns_run.cpp
  const auto start = std::chrono::steady_clock::now();
  Driver driver(m, ground, options, observer);
  RunResult result = driver.run();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rocking
