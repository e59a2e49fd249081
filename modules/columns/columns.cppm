// rocking.columns: a structure standing on rocking columns, the rocking frame
// (MODEL.md 16; the Lagrange assembly of 15 specialised to this mechanism).
// n identical uniform rigid columns (half-width b, height 2h, mass m_c; R =
// sqrt(b^2 + h^2), alpha = atan(b/h), inertia m_c R^2 / 3 about the centre)
// rock together by theta about their bottom corners on side s (MODEL.md 2's
// signs). The cap beam rests on the top corners diagonally opposite the pivots
// and translates without rotating by (dx, dy) of MODEL.md 16. It is the
// foundation beam (node 0, mass m0) of MODEL.md 1's structure, rigid or
// flexible (K, C condensed and assembled by rocking.beam), whose nodes sit at
// heights H above the column tops with horizontal elastic displacements u
// relative to the beam. With phi = alpha - s theta, m_d = m0 + 1'M1 (the deck)
// and the gravity g + a_v of MODEL.md 14, Lagrange gives (docs/columns.md)
//   M u'' + 2R cos(phi) M1 theta'' = -M1 (a_g + 2 s R sin(phi) theta'^2) - K u - C u'
//   2R cos(phi) 1'M u'' + J theta'' = -R (n m_c + 2 m_d) (s (g + a_v) sin(phi) + a_g cos(phi)) - s D
// with J = (4/3) n m_c R^2 + 4 R^2 m_d, and D = sum_k F_k de_k/d|theta| the
// devices' generalised moment (a device across a column's base: MODEL.md 11's
// kinematics with half-width b; one between the ground and the beam: the
// straight distance between its anchors, beam_device_stretch). Full contact
// (theta = 0) is MODEL.md 3 on a fixed base. Uplift about s when the rocking
// equations give s theta'' > 0 at theta = theta' = 0 (uplift_guard, MODEL.md
// 6's Eq. 2 for the frame). Impacts conserve the generalised momentum
// conjugate to the post-impact coordinates (MODEL.md 15), which gives 16's r
// for a rigid deck, or take a given r. The column-top contact forces follow
// from the deck's Newton-Euler equations (statically indeterminate for n > 2:
// the minimum-norm split, linear across the columns).
// Departures from MODEL.md 16, each derived in docs/columns.md: gamma includes
// the cap beam, m0 (16 writes m_b, the same mass); 16's r holds for a rigid
// deck only (a flexible deck keeps its nodes' horizontal momentum across the
// impact, which gives another ratio); the structure on the beam feels no
// tilt, hence no geometric stiffness while the columns rock. SI units.
module;
#include <rocking/eigen.hpp>

#include <span>
export module rocking.columns;
export import rocking.geometry;
export import rocking.beam;
export import rocking.dynamics;  // GroundAcceleration, Coordinates
export import rocking.devices;   // Stretch

export namespace rocking {

// The columns as given, all alike.
struct ColumnGroup {
  int count = 2;            // n >= 1
  double half_width = 0;    // b [m]
  double half_height = 0;   // h [m]: a column is 2h tall
  double mass = 0;          // m_c, one column [kg]
  double spacing = 0;       // distance between the outer columns' axes [m] (>= 2b; 0 for one column)
};

// Built once (make_columns); constant afterwards. The structure's own
// half_width is not used: its base is the beam, which does not rock on it.
// A structure with no nodes is a bare deck of mass base_mass (0: the
// columns alone, gamma = 0).
struct Columns {
  ColumnGroup group;
  Structure structure;
  StructuralMatrices matrices;    // empty when rigid or bare
  double g = gravity;
  // Derived: R [m], alpha [rad] with its sine and cosine; n m_c, m_s = 1'M1,
  // m_d = m0 + m_s [kg]; J = (4/3) n m_c R^2 + 4 R^2 m_d [kg m^2]; the
  // gravity lever R (n m_c + 2 m_d) [kg m]; H'M1 [kg m]; 1/m per node; 1'K
  // and 1'C (the base shear 1'(K u + C u') as two dot products) and H'K, H'C
  // (its moment about the beam); each column's axis along the beam [m].
  double R = 0, alpha = 0, sin_alpha = 0, cos_alpha = 1;
  double columns_mass = 0, structure_mass = 0, deck_mass = 0, inertia = 0, lever = 0, height_mass = 0;
  Eigen::VectorXd inverse_masses, shear_K, shear_C, moment_K, moment_C, axes;
  bool flexible = false;          // elastic coordinates u (one per node)
};
// Throws std::invalid_argument naming the first field that breaks an
// invariant (count >= 1, sizes > 0, spacing >= 2b for n >= 2; the structure as
// rocking.geometry checks it).
Columns make_columns(const ColumnGroup& group, const Structure& structure, double g = gravity);

// Elastic coordinates (0 when rigid or bare).
Eigen::Index elastic_size(const Columns& c);

// MODEL.md 16's closed forms for a rigid deck: gamma = m_d / (n m_c), the
// frame's frequency parameter p^2 (1 + 2 gamma) / (1 + 3 gamma) with p^2 =
// 3 g / (4 R) [1/s^2], and r = (1 - 1.5 sin^2 alpha + 3 gamma cos 2 alpha) / (1 + 3 gamma).
double frame_gamma(const Columns& c);
double frame_p2(const Columns& c);
double frame_restitution(const Columns& c);

// The beam's translation (MODEL.md 16) while rocking about pivot p, with its
// derivative in theta and its second derivative [m].
struct BeamMotion {
  double dx = 0, dy = 0;      // translation
  double jx = 0, jy = 0;      // d(dx, dy)/dtheta
  double kx = 0, ky = 0;      // d2(dx, dy)/dtheta2
};
BeamMotion beam_motion(const Columns& c, Pivot p, const Tilt& tilt);

// A device between a ground point and a point of the beam (both given at
// rest in the ground's frame: x from the centre line, y up from the columns'
// bottoms) with free length L (<= 0: the rest distance): its elongation and
// de/d|theta| = s de/dtheta while rocking about p (s = sign(p)).
Stretch beam_device_stretch(const Columns& c, double ground_x, double ground_y, double beam_x, double beam_y,
                            double free_length, Pivot p, const Tilt& tilt);

// A load on the deck from outside it, applied at its underside: the force
// [N] and its moment about the underside's centre O [N m], counterclockwise.
struct DeckLoad {
  double fx = 0, fy = 0, moment = 0;
};
// The load on the deck of such a device pulling with `force` (tension > 0,
// toward the ground anchor) in the phase: rocking about its pivot, or full
// contact (the beam at rest). beam_y is measured from the columns' bottoms:
// 2h on the underside.
DeckLoad beam_device_load(const Columns& c, double ground_x, double ground_y, double beam_x, double beam_y, Phase phase,
                          const Tilt& tilt, double force);

// (u', u'') under full contact into rates (2N entries): MODEL.md 3, the beam fixed.
void full_contact_acceleration(const Columns& c, double a_g, Eigen::Ref<const Eigen::VectorXd> u,
                               Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> rates);

// (u', u'') into rates (2N entries; none when rigid) and theta'' as the
// result, while rocking about pivot p (s = sign(p)) with device moment D [N m].
// These, the guard, the impact, the energy and powers and the top forces
// allocate nothing.
double rocking_acceleration(const Columns& c, Pivot p, GroundAcceleration a, double device_moment, const Coordinates& q,
                            Eigen::Ref<Eigen::VectorXd> rates);

// In full contact: s theta'' that rocking about p (s = sign(p)) would start with now, times
// the effective inertia (J - 4 h^2 m_s for a flexible deck, J for a rigid one)
// [N m] (> 0: the frame lifts), the devices holding `held_moment`
// (sum_k F_k(e = 0) de_k/d|theta|, a tendon's prestress times its lever).
// For a rigid deck under a_g alone it is zero at |a_g| = (g + a_v) b / h.
double uplift_guard(const Columns& c, Pivot p, GroundAcceleration a, double held_moment,
                    Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot);

// Impact at theta = 0 while rocking about p (s = sign(p)). restitution < 0: the
// momentum law (MODEL.md 15): rocking about opposite(p) if that gives theta'+ of the sign -s and
// |theta'-| > min_rate, else full contact (u'+ = u'- + 2h theta'-). A given r:
// theta'+ = r theta'-, u' continuous, full contact when r <= 0 or |theta'-| <= min_rate.
// u_dot is updated in place.
struct ColumnsImpact {
  Phase after;
  double theta_dot = 0;  // after [rad/s]
  double ratio = 0;      // theta'+ / theta'- of the rocking outcome (even if it was not taken)
};
ColumnsImpact impact(const Columns& c, Pivot p, double theta_dot, Eigen::Ref<Eigen::VectorXd> u_dot,
                     double restitution = -1, double min_rate = 0);

// Energy (MODEL.md 7 and 14): kinetic, gravity m g y from rest (columns'
// centres, beam and nodes), elastic 1/2 u'K u [J], in the phase (rocking
// about its pivot, s = sign(p), or full contact: theta = 0, the beam at rest).
// Power of the ground, -sum m (a_g x' + a_v y') [W], so that
// dE/dt = ground - u'C u' - s D theta'.
struct ColumnsEnergy {
  double kinetic = 0, gravity = 0, elastic = 0;
  double total() const { return kinetic + gravity + elastic; }
};
ColumnsEnergy mechanical_energy(const Columns& c, Phase phase, const Coordinates& q);
double ground_input_power(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q);
double viscous_power(const Columns& c, Eigen::Ref<const Eigen::VectorXd> u_dot);

// The column-top contact forces on the deck (beam and structure, one free body
// whose underside centre is O): the normal force of each column (compression
// > 0) into `normal` (count entries) and the totals, in the phase (rocking
// about its pivot, or full contact: the contacts at the columns' axes);
// theta_ddot and u_ddot are the accelerations the equations give now, `load`
// what else acts on the deck (the devices between the ground and the beam). With
// n = 2 the split is determined; with n > 2 it is the minimum-norm one (linear
// across the contact points); with one column the single contact carries the
// total.
struct TopContact {
  double normal = 0;    // sum N [N]
  double shear = 0;     // sum of the columns' horizontal forces on the deck [N]
  double moment = 0;    // about O, counterclockwise, that the contacts carry [N m]
  double smallest = 0;  // min N [N]: < 0 is tension the model cannot carry
};
TopContact top_contact_forces(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q, double theta_ddot,
                              Eigen::Ref<const Eigen::VectorXd> u_ddot, std::span<double> normal,
                              const DeckLoad& load = {});
// The same forces at the accelerations the equations give in this state
// (rocking about the phase's pivot with the devices' moment D, or in full contact),
// from the sums over the nodes they need (1'M u'', H'M u'', 1'M u: dot
// products with 1'K, 1'C, H'K, H'C), without the nodes' accelerations: what
// a guard sampled several times a step costs.
TopContact top_contact_forces_now(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q,
                                  double device_moment, std::span<double> normal, const DeckLoad& load = {});

}  // namespace rocking
