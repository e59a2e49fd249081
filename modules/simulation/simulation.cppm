// rocking.simulation: the driver that runs a scene under a ground motion
// (MODEL.md 6 and 7): it integrates the phase's equations with the chosen
// backend, stops at the guards of rocking.contact, applies their resets and
// restarts, and streams the response to observers. Full contact of a flexible
// structure under a record is linear with a piecewise-linear input and is
// stepped exactly instead (RunOptions::exact_full_contact).
// Outputs (MODEL.md 7), the quantities of rocking.quantities: delta_t (Eq. 11)
// and delta_e (Eq. 12) over H_N, theta, theta / alpha_cg and theta', the elongation
// and force of the paper's damper the pivot stretches (signed by the pivot:
// + when rocking about the right pivot; 0 once it has broken), and shear and
// moment of the elastic nodal forces K u at the base and at mid-height over
// V_ref, M_ref; the top node's absolute acceleration along the structure's
// width e1 = (cos th, -sin th), Newton's law at node N of MODEL.md 4's
// u-equation: m_N a_N = -(K u + C u')_N + m_N g sin th (in full contact the
// horizontal absolute acceleration a_g + u_N''); each device's by its name (a broken one's history is empty
// after its fracture).
// Peaks are taken on the dense output at the integrator's guard samples
// (for a flexible structure spaced an eighth of the shortest period of a mode
// that oscillates, Rayleigh damping ratio below 1:
// all of an exact step's, 2 to 4 of an rk45 step's; else 4 per step) and
// refined at local extrema by the parabola through three samples, so they do
// not depend on where the integrator happened to step. The energy balance
//   E(t) - E(0) = W_ground - W_viscous - W_damper - W_impacts
// is carried along (W_damper is the work done on the devices, stored plus
// dissipated; also per device), and its residual measures the run's accuracy.
// Each device's peak elongation and force are taken on the same samples (no
// refinement), and a device that reaches its capacity fractures at the
// located event, its time reported.
module;
#include <rocking/eigen.hpp>
#include <array>
#include <chrono>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>
export module rocking.simulation;
export import rocking.quantities;
export import rocking.contact;
export import rocking.sundials;
export import rocking.ground_motion;
export import :chain_stiff;

export namespace rocking {

// The response at one instant: every quantity of rocking.quantities. Forces
// are normalised (V_ref, M_ref); a quantity the model lacks (Presence) is 0.
// a_g, a_v, M_dev, x_g and the energy balance's terms (E, W_*) are filled for
// history rows only (the peaks do not need them).
struct Response {
  double t = 0;
  Phase phase;
  std::array<double, quantity_count> q{};
  double operator[](Quantity k) const { return q[index(k)]; }
  double& operator[](Quantity k) { return q[index(k)]; }
};
// What a model reports (which quantities mean something for it).
Presence presence(const ContactModel& m);

// A phase change of a run, located to the tolerance (MODEL.md 6): an uplift
// onto pivot s, an impact on the pivot s the structure rocked about, an
// overturning about s, a device's fracture (its index in the model).
enum class EventKind { uplift, impact, overturn, fracture };
std::string_view event_name(EventKind k);  // "uplift", "impact", "overturn", "fracture"
struct Event {
  EventKind kind = EventKind::uplift;
  double t = 0;
  Pivot pivot = Pivot::right;  // the pivot lifted onto, struck, overturned about or rocked about at a fracture
  std::optional<int> device;  // a fracture's device
  int joint = 0;  // where it happened: 0 the base, 1 .. J the joints above (MODEL.md 15)
};

// One joint's state at an instant (a structure with joints, MODEL.md 15):
// its phase, rocking angle and rate relative to the face below, and its
// reaction (rocking.chain's JointReaction: N compression > 0, V, M).
struct JointSample {
  Phase phase;
  double theta = 0, theta_dot = 0;
  double N = 0, V = 0, M = 0;
  double friction() const;  // |V| / N (infinity when N <= 0)
};

// Receives the response as it is computed (history files, plots, tests).
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void record(const Response& r) = 0;
  // The elastic displacements u and velocities u' (nodes 1..N; empty for a
  // rigid block) at the instant of the next record(), called just before it,
  // for observers that draw the structure or record its nodes and elements
  // (node_value, element_value). u' is filled only when wants_velocities().
  virtual void nodal(Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot) {
    (void)u;
    (void)u_dot;
  }
  virtual bool wants_velocities() const { return false; }
  // Each device's elongation and force (in the model's order) at the instant
  // of the next record(), called just before it when the model has devices.
  virtual void devices(const std::vector<DeviceSample>& samples) { (void)samples; }
  // Each phase change, as it happens (before the row recorded at it).
  virtual void event(const Event& e) { (void)e; }
  // A structure with joints: every joint's sample (joint 0, the base, first)
  // at the instant of the next record(), called just before it.
  virtual void joints(std::span<const JointSample> samples) { (void)samples; }
};

struct InitialState {
  double theta = 0, theta_dot = 0;  // a release from a tilt: rocking about sign(theta)
  Eigen::VectorXd u, u_dot;         // elastic displacements and velocities (empty: zero)
};

struct RunOptions {
  // automatic: rk45, unless its steps would be bound by the stability of the
  // structure's highest modes rather than by the motion (choose_backend).
  ode::Backend backend = ode::Backend::automatic;
  // The default tolerance is the knee of the measured work-precision curve
  // (README, `rocking tradeoff`): El Centro's peak drift to about 5e-6 for
  // 13 % more time than rtol 1e-3.
  ode::Options tolerances{.rtol = 1e-4, .atol = 1e-7};
  double duration = 0;           // simulated time [s]; 0: the motion's duration
  double output_interval = 0.01; // history rows every this many s (and at every event)
  // A history row at the run's end too, when the last is earlier: its
  // energy columns are then the summary's totals (the browser lab's bars).
  bool final_row = false;
  // Full contact is linear (Eq. 1) and a record is linear between samples, so
  // a flexible structure in full contact under a record is stepped exactly
  // (ode::make_exact_linear) and the backend integrates the rocking phases
  // only; the energy accumulators are integrated with those steps in closed
  // form. Not used under an analytic pulse, or when an automatic backend
  // chose rosw (choose_backend).
  bool exact_full_contact = true;
  long max_events = 100000;      // more phase changes than this: the run fails (chattering)
  // The elastic coordinates of the integrated state (rocking.dynamics): by
  // default the fixed-base modes under rosw (its O(N) linear solve needs
  // them) and the model's own (nodal) otherwise. Modal makes every
  // right-hand side O(N) for any backend; rosw always runs modal.
  std::optional<ElasticCoordinates> coordinates;
  // Polled between steps: true ends the run as failed ("stopped at t = ..."),
  // with everything reached so far kept (a Ctrl-C on a long run).
  std::function<bool()> stop;
  InitialState initial;
};

// InputError unless the tolerances are in (0, 1) and positive, the limits at
// least 1, the history interval positive and the duration 0 (the motion's)
// or in (0, 1e5] s. The message names the option as `prefix` + its name
// ("--rtol 2: must be in (0, 1)" for the command line's "--").
void check_run_options(const RunOptions& o, std::string_view prefix);

// Three outcomes end a run where the model's assumptions end; each is
// stated (RunResult::stated), never continued or guessed:
// - separated: a joint's normal force reached 0 (MODEL.md 15: the part above
//   would leave it), or a column top's (16: the beam would lift off);
// - sliding: a joint's friction demand |V|/N reached the limit its scene
//   states (15: sliding is not modelled);
// - undecided: an impact for which the momentum law (15) admits no outcome,
//   or more than one, or has more outcomes than it examines
//   (rocking.chain's max_impact_outcomes).
enum class Outcome { completed, overturned, failed, separated, sliding, undecided };
std::string_view outcome_name(Outcome o);
std::optional<Outcome> outcome_named(std::string_view name);  // outcome_name's inverse
// Whether a run that ended so has reached every limit a study sets: it
// overturned, a joint separated or slid (beyond them the model says nothing,
// so a study counts them with overturning as the state past every limit).
// An undecided run has no such answer: a study reports it as a row without
// a result, with its statement.
inline bool past_every_limit(Outcome o) {
  return o == Outcome::overturned || o == Outcome::separated || o == Outcome::sliding;
}
// Whether the model stated why it ended the run there (RunResult::stated).
inline bool is_stated(Outcome o) {
  return o == Outcome::separated || o == Outcome::sliding || o == Outcome::undecided;
}

struct Counts {
  long uplifts = 0, impacts = 0;
};

// What one device did in a run (MODEL.md 11).
struct DeviceResult {
  std::string name;
  std::string law;                 // its law's name ("elastic")
  double force_at_rest = 0;        // F(e = 0) [N]: a tendon's prestress
  double peak_elongation = 0;      // max e [m], up to its fracture
  double peak_force = 0;           // max |F| [N], up to its fracture
  double work = std::numeric_limits<double>::quiet_NaN();  // int F de: stored + dissipated [J] (energy tracked)
  double fracture_time = std::numeric_limits<double>::quiet_NaN();  // [s]; NaN: intact
};

// What one joint did in a run of a structure with joints (MODEL.md 15).
struct JointResult {
  double first_uplift = std::numeric_limits<double>::quiet_NaN();  // [s]
  double first_impact = std::numeric_limits<double>::quiet_NaN();  // [s]
  long uplifts = 0, impacts = 0;
  double peak_theta = 0;     // max |theta| [rad]
  double peak_friction = 0;  // max |V| / N while closed or rocking [-]
  double peak_theta_over_alpha = 0;  // max |theta| over alpha_j, the slenderness of everything above the joint [-]
};

// What the columns did in a run of a structure on rocking columns (MODEL.md
// 16; their uplifts and impacts are the run's counts, their peaks the
// columns.* quantities'): the smallest column-top contact force over the
// run and when, sampled as the peaks are.
struct ColumnsResult {
  double smallest_top_force = std::numeric_limits<double>::infinity();  // [N]; compression > 0
  double smallest_top_force_time = std::numeric_limits<double>::quiet_NaN();  // [s]
};

struct EnergyBalance {
  double initial = 0, final = 0;                 // mechanical: kinetic + gravity + elastic [J]
  double ground = 0, viscous = 0, damper = 0, impacts = 0;  // [J]
  double residual() const { return (final - initial) - (ground - viscous - damper - impacts); }
};

struct RunResult {
  Outcome outcome = Outcome::completed;
  std::string failure;             // what stopped a failed run, with time and phase
  std::string stated;              // a separated, sliding or undecided run: which joint, when, why
  std::optional<int> separated_joint;  // a separated chain: the joint in tension (0 the base); none on columns
  double t_end = 0;                // where the run ended [s]
  Phase final_phase;               // at t_end
  double final_theta = 0;          // theta at t_end [rad]: the residual tilt when the motion has died out
  std::array<double, quantity_count> peaks{};  // absolute peaks of the peak quantities (others 0)
  double top_total_mm = 0;         // peak |delta_t| H_N [mm]
  Presence presence;               // which quantities the model reports
  Counts counts;
  std::vector<DeviceResult> devices;  // one per device of the model, in its order
  std::vector<JointResult> joints;    // a structure with joints: one per joint, the base first; else empty
  std::optional<ColumnsResult> columns;  // a structure on rocking columns; else none
  double first_uplift = std::numeric_limits<double>::quiet_NaN();
  double first_impact = std::numeric_limits<double>::quiet_NaN();
  EnergyBalance energy;
  bool energy_tracked = false;
  ode::Stats stats;
  std::string integrator;
  bool exact_full_contact = false;  // full contact was stepped exactly (stats add both)
  double wall_s = 0;
  Eigen::VectorXd final_state;     // the state at t_end, elastic coordinates nodal
  double peak(Quantity k) const { return peaks[index(k)]; }
  bool reports(Quantity k) const { return presence.has(info(k).needs); }
};

// The normalisation and geometry the outputs need, built once per model.
struct OutputScales {
  double H_N = 0, alpha_cg = 0, V_ref = 0, M_ref = 0;
  double inverse_H_N = 0, inverse_alpha_cg = 0;  // multiplied, not divided, at every sample
  bool has_forces = true;
  // Rows giving (base shear / V_ref, base moment / M_ref, mid shear / V_ref,
  // mid moment / M_ref) from the elastic coordinates: sums of the elastic
  // nodal forces K u.
  Eigen::Matrix<double, 4, Eigen::Dynamic> force_rows;
  Eigen::RowVectorXd top_row;  // u_N from modal coordinates; empty when nodal (u_N is the last)
  // -(K u)_N / m_N and -(C u')_N / m_N as rows on the elastic coordinates and their rates.
  Eigen::RowVectorXd top_stiffness_row, top_damping_row;
};
OutputScales output_scales(const ContactModel& m);
Response evaluate(const ContactModel& m, const OutputScales& sc, const Discrete& d, double t,
                  Eigen::Ref<const Eigen::VectorXd> y);

// A node's (1..N) or an element's (1..N) quantity of rocking.quantities at
// the instant of the response `r` (its theta and x_g), from the nodal elastic
// displacements and velocities (empty for a rigid block; u' is read by a_abs
// only). The index is in range and the model reports the quantity (the
// callers check both).
double node_value(const ContactModel& m, NodeQuantity q, int node, const Response& r,
                  Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot);
double element_value(const ContactModel& m, ElementQuantity q, int element, Eigen::Ref<const Eigen::VectorXd> u);

// The integrator an automatic run uses: rosw (Rosenbrock-W, linearly implicit
// in the elastic forces) for a flexible structure whose fastest mode would
// hold rk45's steps below a quarter of the motion's own time step (a
// record's mean sample interval, a pulse's period / 40): Dormand-Prince is
// stable up to about h = 3.3 / |lambda|, with lambda the fastest eigenvalue
// of the fixed-base modes under Rayleigh damping (an overdamped mode's fast
// root a0 + a1 omega^2 and above). Else rk45. A given backend is kept. On a
// one-joint structure an automatic rosw integrates full contact as well
// (exact_full_contact applies to an automatic rk45 and to a backend given by
// name); a chain (chain_run.cpp) keeps its exact closed steps under either.
ode::Backend choose_backend(const ContactModel& m, const GroundMotion& ground, ode::Backend requested);

// Runs the model under the ground motion: along the model's plane and, when
// it comes with one (GroundMotion::vertical), upward (MODEL.md 14). A model
// with joints (ContactModel::jointed) is run by the chain's equations
// (MODEL.md 15), one on rocking columns (ContactModel::on_columns) by the
// columns' (MODEL.md 16), with the same backends, events, observers and
// energy balance.
// Never throws for a run that cannot finish: the result says failed, with
// the reason, and holds what was reached.
RunResult simulate(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                   Observer* observer = nullptr);

}  // namespace rocking

namespace rocking {
// The run of a model with joints (ContactModel::jointed, MODEL.md 15), which
// simulate() hands over to: chain_run.cpp.
RunResult simulate_chain(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                         Observer* observer);
// The run of a structure on rocking columns (ContactModel::on_columns,
// MODEL.md 16): columns_run.cpp.
RunResult simulate_columns(const ContactModel& m, const GroundMotion& ground, const RunOptions& options,
                           Observer* observer);

// What the drivers of chain_run.cpp and columns_run.cpp share (drive.cpp;
// MODEL.md 6 and 14).
// The ground's acceleration at t: along the plane, and upward when shaken so.
GroundAcceleration ground_at(const GroundMotion& ground, const GroundMotion* vertical, double t);
// The run's tolerances with steps no longer than the motion's (and its
// vertical motion's), the error measured on the first `steering` components
// only (the energy accumulators after them are integrals nothing depends on).
ode::Options motion_tolerances(const RunOptions& o, const GroundMotion& ground, Eigen::Index steering);
// The backend `backend` (rosw solves with `stiff`, without one it is its
// explicit order-3 method), stopping at every sample of the records.
std::unique_ptr<ode::Integrator> motion_integrator(ode::Backend backend, const GroundMotion& ground, Eigen::Index size,
                                                   ode::Rhs rhs, const ode::Options& tolerances,
                                                   ode::LinearSolve stiff = {});
// Where the run ends: the duration asked for, else the motion's.
double run_end(const RunOptions& o, const GroundMotion& ground);
// One more phase change at t: RunError beyond the run's limit (chattering).
void count_phase_change(long& events, const RunOptions& o, double t);
// RunError ("stopped at t = ...") when the caller asks the run to stop.
void check_stop(const RunOptions& o, double t);
// Runs body; a failure it throws (the integrator's, or a stated outcome's
// RunError) ends the run as failed, with the phase as `phase` tells it.
void run_stated(RunResult& result, const std::function<void()>& body, const std::function<std::string()>& phase);

// A driver's run, timed from its set-up (the wall time counts it).
template <class Driver>
RunResult timed_run(const ContactModel& m, const GroundMotion& ground, const RunOptions& options, Observer* observer) {
  const auto start = std::chrono::steady_clock::now();
  Driver driver(m, ground, options, observer);
  RunResult result = driver.run();
  result.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

// The history's rows every output_interval after t = 0 (the start's row is
// the caller's): row(t, y) at each one the integrator has passed, up to
// `until` when the last step ends earlier than the integrator's (an event
// found after it).
class HistoryGrid {
 public:
  explicit HistoryGrid(double interval) : interval_(interval), next_(interval) {}
  template <class Row>
  void rows(ode::Integrator& integrator, Eigen::VectorXd& dense, Row&& row,
            double until = std::numeric_limits<double>::infinity()) {
    if (!(interval_ > 0)) return;
    while (next_ <= std::min(integrator.time(), until)) {
      integrator.dense(next_, dense);
      row(next_, dense);
      next_ = interval_ * static_cast<double>(++count_);
    }
  }

 private:
  double interval_, next_;
  long count_ = 1;
};
}  // namespace rocking
