// rocking.contact: the phases of a rocking structure and the changes between
// them (MODEL.md 2 and 6; the paper's Eqs. 2-3 and 8-10), as pure functions of
// (model, discrete state, continuous state).
// A scene models one of: a rigid block (state theta, theta'), a fixed-base
// flexible structure (u, u'; linear, no events), or a flexible rocking
// structure (u, u', theta, theta'), plus the internal states z of the devices
// the current pivot stretches (rocking.devices, MODEL.md 11). The state holds
// only that; energy accumulators (ground input, viscous, work on the devices
// in all and on each) may follow for the bookkeeping of MODEL.md 7. Devices act on the rocking
// equation through their generalised force -s F de/d|th|, on the uplift
// guards through their force at rest times their lever arm, and keep their z
// in the discrete state while their pivot is not the current one. The paper's
// [damper] is a Bouc-Wen chord device at each edge (x = -B, stretched about
// pivot +1; x = +B, about -1). A device with a capacity e_u fractures when its
// elongation reaches it (a located event) and exerts nothing after.
// Phases (rocking.geometry's Phase): full contact, or rocking about a pivot,
// s = +1 (right, theta > 0) or -1 (left). Guards: uplift about s (both Eq. 2 as the smooth moment guard g_s and
// Eq. 3, L_s > 0: the guard is min(g_s, L_s), rising); impact (s theta falling
// through 0); overturning (s theta rising through the overturn angle).
// Resets: uplift (theta = theta' = 0, the stretched devices resume their z);
// impact, either continued rocking about -s (th'+ = r th'-, u'+ = u'-) when
// -s L_new >= 0 and |th'-| > theta_dot_min, or full contact
// (th'+ = 0, u'+ = u'- + H th'-). r: constant, Eq. 10, or Eq. 9 per impact.
module;
#include <rocking/eigen.hpp>
#include <array>
#include <optional>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>
export module rocking.contact;
export import rocking.dynamics;
export import rocking.devices;
export import rocking.chain;
export import rocking.columns;

export namespace rocking {

// How the rocking velocity after an impact follows from the one before
// (MODEL.md 6): a constant r, Eq. 10 from the geometry, or Eq. 9 per impact.
enum class RestitutionRule { constant, eq10, eq9 };

// How the structure meets the ground.
struct Contact {
  bool rocking = true;                       // false: fixed base
  RestitutionRule restitution_rule = RestitutionRule::eq10;
  double restitution = 0;                    // r when the rule is constant
  double theta_dot_min = 0.0015;             // Eq. 8 threshold [rad/s]
  double overturn_angle = 0;                 // |theta| that ends a run [rad]; 0: alpha_cg
};

enum class ModelKind { rigid_block, fixed_base, flexible };

// A part of the ODE state: `count` coordinates from `start`. A count of zero
// is a part the model lacks.
struct StateRange {
  Eigen::Index start = 0, count = 0;
  bool present() const { return count > 0; }
};

// Where each part of the ODE state sits. u and u_dot hold the elastic
// coordinates in the body's coordinates: the nodal displacements, or the
// fixed-base modes' amplitudes (rocking.dynamics); none for a rigid block.
// theta and theta_dot: one each, none on a fixed base.
struct Layout {
  Eigen::Index n = 0;  // elastic coordinates (N, or 0 for a rigid block)
  StateRange u, u_dot, theta, theta_dot;
  StateRange z;  // the states of the devices the current pivot stretches
  // [ground input, viscous, work on all devices, and when some pivot
  // stretches several devices the work on device 0, 1, ...] [J]
  StateRange energy;
  Eigen::Index size = 0;
};

struct Discrete;
struct ContactModel;

// A device's elongation [m] and force [N] (active_damper below).
struct DamperState {
  double elongation = 0, force = 0;
};

// A structure that rocks at more than one level (MODEL.md 15): the chain of
// segments rocking.chain integrates, with each joint's rules. A model that
// carries one is run by the chain's equations (rocking.simulation); the rest
// of ContactModel then describes the structure as one piece on its base (for
// its name, slenderness and devices).
struct JointedModel {
  Chain chain;
  std::vector<double> restitution;     // per joint: r, or < 0 for the momentum law (MODEL.md 15)
  std::vector<double> initial_theta;   // per joint [rad]: a release from a tilt
  std::vector<double> friction_limit;  // per joint: |V| / N beyond it ends the run (infinity: not checked)
  std::vector<double> overturn_angle;  // per joint [rad]: the slenderness of everything above it
  std::vector<std::string> tendons;    // the tendons' names (ChainData::tendons' order)
  // The model's devices [0, base_devices) stand across the base joint, as on
  // a one-joint structure (MODEL.md 11: chord or vertical, any law; their
  // acting lists and state slots are a rigid block's, from 2 after theta_0 and
  // theta_0'); then come the devices across the joints above (`upper`, in
  // that order), then the chain's tendons, in order.
  std::size_t base_devices = 0;
  // The devices across one joint j >= 1, as those across the base: section
  // 11's forms in joint j's frame (from the face of segment j-1 to the slab of
  // segment j), their elongation a function of theta_j alone. `block` holds
  // them as a rigid block on a base of half-width B_j holds them (its acting
  // lists, breakable lists and state slots from 2 after theta_j and theta_j',
  // numbered 0.. in `devices`' order); `devices` are their places in
  // ContactModel::devices.
  struct UpperDevices {
    int joint = 0;
    std::vector<std::size_t> devices;
    std::shared_ptr<const ContactModel> block;
  };
  std::vector<UpperDevices> upper;
  // The devices across some joint (base and upper): the tendons start here.
  std::size_t joint_devices() const {
    std::size_t n = base_devices;
    for (const UpperDevices& u : upper) n += u.devices.size();
    return n;
  }
  double theta_dot_min = 0.0015;       // Eq. 8's threshold, per joint [rad/s]
  // contact.rocking = false holds the base joint closed: chain.data.base_held.
  bool base_rocks() const { return !chain.data.base_held; }
};

// A structure standing on rocking columns (MODEL.md 16): the frame
// rocking.columns integrates, with the impact rule of [contact]. A model that
// carries one is run by the columns' equations (rocking.simulation); the rest
// of ContactModel then describes the structure on the cap beam as on a fixed
// base (a rigid one as a block: its outputs only).
struct ColumnsModel {
  Columns columns;
  // The devices between the ground and the cap beam (Kinematics::beam), one
  // each (not one per column): ContactModel::devices[device], anchored at
  // (ground_x, ground_y) and at (beam_x, 2h) at rest (beam_device_stretch),
  // with its state's slot after the column devices' (none: stateless) and
  // de/d|theta| at rest about each pivot (index(Pivot)), the lever of its
  // held moment F(e = 0) de/d|theta|.
  struct BeamDevice {
    int device = 0;
    std::optional<Eigen::Index> slot;
    double ground_x = 0, ground_y = 0, beam_x = 0;
    std::array<double, 2> lever{0.0, 0.0};
  };
  std::vector<BeamDevice> beam_devices;
  double restitution = -1;        // r, or < 0 for the momentum law (MODEL.md 15, 16's r for a rigid deck)
  double theta_dot_min = 0.0015;  // Eq. 8's threshold [rad/s]
  double overturn_angle = 0;      // the columns' alpha [rad]: past it gravity tips the frame over
  bool rocking = true;            // contact.rocking: false holds the columns down (no uplift)
};

struct ContactModel {
  ModelKind kind = ModelKind::flexible;
  RockingBody body;
  bool has_damper = false;      // the paper's [damper] pair is among the devices (Device::edge_damper)
  std::vector<Device> devices;
  struct Acting;
  // What an acting device adds to the rocking right-hand side: F de/d|th|
  // [N m] and F e' [W] (its z' written into dydt), and its elongation and
  // force (0 once broken) for the outputs; each a function specialised for
  // the device's law and kinematics, chosen when the model is built, so that
  // a right-hand side makes no dispatch on them.
  struct DeviceTerms {
    double moment = 0, power = 0;
  };
  using TermsFn = DeviceTerms (*)(const Acting& a, const Discrete& d, double half_width, Pivot p, const Tilt& tilt,
                                  double theta_dot, const double* y, double* dydt);
  using StateFn = DamperState (*)(const Acting& a, const Discrete& d, double half_width, Pivot p, const Tilt& tilt,
                                  double theta_dot, const double* y);
  struct Acting {
    int device = 0;
    std::optional<Eigen::Index> slot;  // of its state z; none: stateless
    double lever = 0;        // l = B - s x [m]
    DeviceGeometry geometry;
    DeviceLaw law;
    double capacity = 0;     // e_u [m]; 0: never breaks
    TermsFn terms = nullptr;
    StateFn state = nullptr;
  };
  // Per pivot (index(Pivot): [0] left, [1] right): the devices it stretches (lever arm
  // > 0), in the scene's order, each with what the right-hand side needs of
  // it in one place; and whether some state slot is left unused there.
  std::array<std::vector<Acting>, 2> acting;
  // Per pivot: which of its acting devices is the paper's damper, if one is.
  std::array<std::optional<std::size_t>, 2> damper;
  // Per pivot: which of its acting devices can break (each has a fracture guard).
  std::array<std::vector<int>, 2> breakable;
  std::array<bool, 2> idle_slots{false, false};
  Contact contact;
  // The model reports the ground's vertical acceleration a_v (its runs are
  // given a vertical motion, MODEL.md 14; rocking.run sets it).
  bool vertical_shaking = false;
  double r_eq10 = 0;
  double overturn_angle = 0;   // [rad]
  Layout layout;
  // N zeros: the elastic displacements and velocities of a rigid block, so
  // that the formulas it shares with a flexible structure (momenta, Eq. 9,
  // the impact reset's inertia, energies, views) read them as those of a
  // structure whose u stays 0, with no branch on the model.
  Eigen::VectorXd zero_motion;
  // Rows on the contiguous [u; u'] (2N) giving 1'M u and H'M u', with
  // body.moment_row the terms of both uplift guards, which are sampled
  // several times a step: [M1; 0], [0; MH].
  Eigen::VectorXd mass_row, momentum_row;
  // Set for a structure with joints above its base (or the momentum law at
  // its base): the run is the chain's.
  std::shared_ptr<const JointedModel> jointed;
  // Set for a structure on rocking columns: the run is the columns'.
  std::shared_ptr<const ColumnsModel> on_columns;
};
// The model of a structure meeting the ground by these rules, with these
// devices (ignored on a fixed base); energy accumulators when asked.
// InputError for an anchor off the base or too many devices with a state.
ContactModel make_contact_model(const Structure& structure, const Contact& contact, std::vector<Device> devices,
                                bool track_energy);
// The same model with the fixed-base modes as its elastic coordinates: every
// right-hand side, guard and stiff solve then costs O(N) (rocking.dynamics).
ContactModel in_modal_coordinates(ContactModel m);

// At most this many devices with an internal state (the discrete state is a
// fixed array, so that events allocate nothing).
inline constexpr int max_device_states = 16;

// The discrete state kept beside the ODE state. The devices' z and their
// fractures change only through set_z and fracture, so that the moment the
// devices hold at rest about each pivot (a sum over the devices, needed at
// every uplift-guard sample) is computed once per change of them.
struct Discrete {
  Phase phase;                     // full contact, or rocking about a pivot
  Pivot last_pivot = Pivot::right;  // the pivot of the last rocking phase
  std::uint32_t broken = 0;        // bit k: device k has fractured (exerts nothing for the rest of the run)
  bool is_broken(int device) const { return ((broken >> device) & 1u) != 0; }
  // z of each device (by device index) while not stretched.
  double z(int device) const { return z_[static_cast<std::size_t>(device)]; }
  void set_z(int device, double value) {
    z_[static_cast<std::size_t>(device)] = value;
    held_fresh_ = false;
  }

 private:
  friend void fracture(Discrete& d, int device);
  friend double held_moment(const ContactModel& m, const Discrete& d, Pivot p);
  void refresh_held(const ContactModel& m) const;
  std::array<double, max_device_states> z_{};
  mutable std::array<double, 2> held_{};  // per pivot (index(Pivot)), valid while held_fresh_
  mutable bool held_fresh_ = false;
};

// dy/dt in the current phase at ground acceleration a (a_g, a_v).
void phase_rhs(const ContactModel& m, const Discrete& d, GroundAcceleration a, const Eigen::Ref<const Eigen::VectorXd>& y,
               Eigen::Ref<Eigen::VectorXd> dydt);

// Full contact of a flexible structure (Eq. 1) as x' = A x + b a_g(t) on the
// block x = [u; u'] of the state, which starts at `first` (the rest is
// constant in full contact), for exact integration under a piecewise-linear
// record.
struct LinearPhase {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  Eigen::Index first = 0;
  // The energy accumulators' rates in full contact, on the same z: the
  // ground's power a_g ground' z and the viscous power z' viscous z (read off
  // ground_input_power and viscous_power, which phase_rhs integrates).
  Eigen::VectorXd ground;
  Eigen::MatrixXd viscous;
};
LinearPhase full_contact_matrices(const ContactModel& m);

// The stiff part of each phase's equations, for a linearly implicit
// integrator (ode::LinearSolve), on a model in modal coordinates: the elastic
// forces f = k q + c q' (per unit modal mass) with the inertia of the phase
// frozen at u = 0. In full contact q'' = -f; rocking about either pivot,
// q'' = -P f and th'' = a h'f with P = I + a h h', a = mu / D0,
// D0 = m0 B^2 + B^2 1'M1 (MODEL.md 4 at u = 0, the same for both pivots). T
// holds these rows and nothing else; solve() gives x = (I - g T)^-1 b on the
// whole state in O(N): the velocity block
//   (I + P D) x_v = b_v - g P (k b_u),  D = g c + g^2 k (diagonal),
// is a diagonal plus a rank-one term (Sherman-Morrison), x_u = b_u + g x_v
// and x_th' = b_th' + g a h'(k x_u + c x_v). A rigid block has no stiff part
// (x = b). InputError for a flexible model in nodal coordinates.
class StiffPart {
 public:
  explicit StiffPart(const ContactModel& m);
  void solve(Phase phase, double g, Eigen::Ref<const Eigen::VectorXd> b, Eigen::Ref<Eigen::VectorXd> x);

 private:
  void prepare(double g);

  const ContactModel* m_;
  double a_ = 0;                // mu / D0
  double cached_g_ = -1;
  Eigen::VectorXd e_, z_, Dh_;  // at cached_g_: 1 / (1 + D), e_ h and D h, D = g c + g^2 k
  double hDz_ = 0;              // at cached_g_: (D h)' z_
};

// The elongation and force of the paper's damper the current pivot stretches
// (0 in full contact, without such a damper, or once it has broken).
DamperState active_damper(const ContactModel& m, const Discrete& d, const Tilt& tilt,
                          Eigen::Ref<const Eigen::VectorXd> y);

// The guards of a phase (see the top of this file), each with what its
// crossing means and the direction in which it counts: in full contact the
// uplifts about +1 and -1 (rising); rocking, the impact (falling), the
// overturning (rising) and, for each device with a capacity that the pivot
// stretches, its fracture e - e_u (rising; -1 once broken).
enum class Guard { uplift_right, uplift_left, impact, overturn, fracture };
enum class Crossing { rising, falling };
struct PhaseGuard {
  Guard what = Guard::impact;
  Crossing crossing = Crossing::rising;
  std::optional<int> device;  // the device a fracture guard watches
};
std::vector<PhaseGuard> phase_guards(const ContactModel& m, Phase phase);
// The guards' values in the order of phase_guards (g holds one per guard).
// The uplift guards restrain with gravity g + a_v (MODEL.md 14).
void guard_values(const ContactModel& m, const Discrete& d, GroundAcceleration a, const Eigen::Ref<const Eigen::VectorXd>& y,
                  Eigen::Ref<Eigen::VectorXd> g);
// Which of the ground's accelerations the guards of this phase read: a_g in
// the uplift guards of a rigid block (its inertia force is -a_g H'M1; a
// flexible structure's is K u + C u') and, under vertical shaking, a_v in
// every uplift guard; a caller may pass 0 for the others without looking them up.
struct GuardInputs {
  bool horizontal = false, vertical = false;
};
GuardInputs guard_inputs(const ContactModel& m, Phase phase, bool vertical_shaking);

// The pivot about which the structure in full contact lifts at this instant
// (both conditions of MODEL.md 6 hold), if any.
std::optional<Pivot> uplift_now(const ContactModel& m, const Discrete& d, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> y);

// A device reaching its capacity fractures: it exerts nothing from now on.
void fracture(Discrete& d, int device);

// sum F_rest l over the intact devices pivot p stretches: the moment they
// hold against uplift about p (a tendon's prestress, a damper's stored force) [N m].
// Inline: every uplift-guard sample reads it.
inline double held_moment(const ContactModel& m, const Discrete& d, Pivot p) {
  if (!d.held_fresh_) d.refresh_held(m);
  return d.held_[index(p)];
}

// Each device's elongation and force in this state (0 for the devices the
// current pivot does not stretch; NaN for the broken, which have no
// elongation of their own after fracture, and exert no moment). out: one per device.
struct DeviceSample {
  double e = 0, F = 0;  // [m], [N]
  double moment = 0;    // s F de/d|th|: the moment it exerts against the tilt, signed as theta [N m]
  double work = 0;    // int F de since the start [J] (the run's drivers set it; NaN: energy not tracked)
};
void device_samples(const ContactModel& m, const Discrete& d, Eigen::Ref<const Eigen::VectorXd> y,
                    std::vector<DeviceSample>& out);

// Uplift about pivot p: theta = theta' = 0, the devices p stretches resume their z.
void begin_rocking(const ContactModel& m, Discrete& d, Pivot p, Eigen::Ref<Eigen::VectorXd> y);

// Impact while rocking: the reset of MODEL.md 6. Returns the r applied (0 when
// full contact begins).
struct ImpactResult {
  bool continues = false;
  double r = 0;
};
ImpactResult impact(const ContactModel& m, Discrete& d, Eigen::Ref<Eigen::VectorXd> y);

// Kinetic + gravity + elastic energy of a state in this phase [J].
double mechanical_energy(const ContactModel& m, Phase phase, Eigen::Ref<const Eigen::VectorXd> y);

// Coordinates (u, u', theta, theta') of a state, nodal, zeros where the model has none.
struct StateView {
  Eigen::VectorXd u, u_dot;
  double theta = 0, theta_dot = 0;
};
void view(const ContactModel& m, Eigen::Ref<const Eigen::VectorXd> y, StateView& out);

}  // namespace rocking
