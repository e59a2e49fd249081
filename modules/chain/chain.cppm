// rocking.chain: a structure that rocks at more than one level, a chain of
// segments j = 0..J from the ground up (MODEL.md 15). Segment j is MODEL.md 1's
// structure in its own frame: a rigid slab (height h_j, mass m0_j on the centre
// line) standing on joint j (half-width B_j; joint 0 is the ground), its lumped
// nodes above, rigid or joined by Euler-Bernoulli elements (rocking.beam's
// element stiffness) clamped to the slab. A flexible segment with a joint above
// keeps its top node's rotation phi as a coordinate (the face the next segment
// stands on turns with it); every other rotation is condensed out.
// Coordinates (one fixed layout for every phase): theta_0..theta_J (segment j's
// rotation about a corner of its joint, relative to the face below, MODEL.md
// 2's sign; held at 0 while the joint is closed), then per flexible segment its
// nodal displacements u in its slab frame and, below a joint, phi.
// Each mass point's position is an explicit planar chain of rotations about the
// active corners and translations; J_i = dp_i/dq analytically; Lagrange gives
//   M = sum m_i J_i'J_i,  Q = -sum m_i J_i'(J_i' q' + (a_g, g + a_v)) - K x - C x' - sum_k F_k de_k/dq
// (ground acceleration as the frame's, MODEL.md 14; C = a0 M + a1 K per
// segment; each segment's points summed once into its frame's lumped mass and
// moments, with a flexible segment's sums over its nodes' u, docs/chain.md). Closed joints' reactions N, V, M are the Lagrange multipliers of
// their constraints (relative translation and rotation of the slab on the face);
// uplift about s when s M_j >= N_j B_j (devices spanning the joint are forces in
// the multipliers, so their restraint is inside N_j and M_j). Impacts conserve
// the generalised momentum conjugate to the post-impact coordinates; the
// outcome is searched over the phases the other joints may take and reported
// unique, non-unique or none, or left unexamined beyond max_impact_outcomes
// (more than ten other closed joints free to open): never guessed.
// docs/chain.md has the derivation.
// SI units.
module;
#include <rocking/eigen.hpp>

#include <cstddef>
#include <span>
#include <string>
#include <vector>
export module rocking.chain;
export import rocking.geometry;
export import rocking.beam;
export import rocking.dynamics;  // GroundAcceleration

export namespace rocking {

// One segment as given: its nodes' absolute heights (increasing, above the
// slab); the last node is the face of the next joint when a segment stands on it.
struct ChainSegment {
  double base_height = 0;  // h_j [m] (0 for segment 0)
  double half_width = 0;   // B_j of the joint it stands on [m]
  double base_mass = 0;    // m0_j, the slab [kg] (> 0 or nodes with mass)
  Eigen::VectorXd heights; // absolute node heights [m]
  Eigen::VectorXd masses;  // lumped node masses [kg]
  Eigen::VectorXd EI;      // element e: node e-1 (0: the slab) to node e [N m^2]; unused if rigid
  bool rigid = true;
};

// A point fixed to a segment's slab frame at (x, z) (z above the slab), or,
// with node >= 0, one that moves with that node's displacement u. segment -1
// is the ground.
struct ChainAnchor {
  int segment = -1;
  double x = 0, z = 0;
  int node = -1;
};

// MODEL.md 11's elastic law between two anchors: F = max(0, P0 + k e), e the
// distance between the anchors less the free length (the rest distance when
// free_length <= 0).
struct ChainTendon {
  ChainAnchor from, to;
  double prestress = 0;   // P0 [N]
  double stiffness = 0;   // k [N/m]
  double free_length = 0; // [m]
};

struct ChainData {
  std::vector<ChainSegment> segments;
  std::vector<ChainTendon> tendons;
  Rayleigh rayleigh;  // a0, a1 of every segment's C = a0 M + a1 K
  double g = gravity;
  // Joint 0 held closed (a fixed base): it never opens, and takes any
  // impulse an impact sends it (no admissibility check there).
  bool base_held = false;
};

// The same structure split at nodes: joint k (k = 1..) stands on node
// joints[k-1].node of s (1..N-1, increasing) with the given half-width and slab
// mass; the segment above is rigid if s is or if `rigid` says so. Rayleigh
// coefficients are the whole structure's (rocking.beam).
struct ChainJointSpec {
  int node = 0;
  double half_width = 0;
  double base_mass = 0;
  bool rigid = false;
};
ChainData split_structure(const Structure& s, std::span<const ChainJointSpec> joints);

// Built once from ChainData (checked: std::invalid_argument naming the field).
// A flexible segment may not stand on a flexible one: its nodes, measured in
// a slab frame that turns with the face, would leave the face's rotation phi
// with (to first order) no inertia, a singular mass matrix (docs/chain.md).
struct Chain {
  ChainData data;
  int joints = 0;               // J + 1
  int size = 0;                 // coordinates (the fixed layout above)
  int augmented = 0;            // size + 2 (J + 1): with each joint's relative translation
  int points = 0;               // mass points
  std::vector<int> elastic_offset;  // first u of segment j (-1 if rigid)
  std::vector<int> rotation_index;  // phi of segment j's top node (-1 if none)
  std::vector<Eigen::VectorXd> local_heights;  // node heights above each slab
  std::vector<Eigen::MatrixXd> K, C;           // per flexible segment, on (u, phi)
  std::vector<double> rest_length;             // per tendon
  std::vector<double> rest_height;             // per mass point (the potential's zero)
  Eigen::VectorXd masses;                      // per mass point: each slab, then its nodes
  // Per segment, its points lumped in the slab frame (every point of a rigid
  // segment is at x = 0): mass sum m, first moment sum m z, second moment sum m z^2.
  std::vector<double> segment_mass, segment_moment, segment_inertia;
};
Chain make_chain(const ChainData& d);

// The phase of each joint (full contact or rocking about a pivot), one per joint.
using ChainPhases = std::span<const Phase>;

// Everything the equations work in, sized once: the hot path allocates nothing.
// A segment enters M and Q through its slab frame's Jacobian and the
// segment's lumped mass and moments (Chain::segment_*), a flexible one with
// its nodes' sums over u and u' and its own u columns' terms (each node moves
// only itself along them), so that the work goes with the segments and the
// coordinates, not with the mass points times the coordinates; with per_point
// set, every mass point's own Jacobian is summed instead (the general path;
// the same equations to round-off).
struct ChainWorkspace {
  bool per_point = false;
  // chain_acceleration and chain_reactions take the closed form of
  // docs/chain.md "A rigid top on a closed chain" where chain_rigid_top says
  // it holds (the same equations: a dense block on the top's theta, when it
  // rocks, and its face's u and phi, the rest diagonal; the closed joints'
  // reactions the balance of everything above them). False: the assembly
  // above in every phase, the reference the closed form is held to.
  bool rigid_top = true;
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;  // a Jacobian row contiguous
  Rows jac;                  // 2 rows per point (+ anchors) x augmented
  Eigen::MatrixXd points;    // per point: x, y, vx, vy, bias x, bias y (per_point)
  Eigen::MatrixXd anchors;   // per anchor: x, y, vx, vy
  Rows frames;               // per frame its Jacobian (O x, O y, psi): the face, the pivot, then each slab frame
  Rows slabs;                // per segment's slab frame: O x, y, cos, sin of psi, O', psi', O's bias; its nodes' sums
  Eigen::MatrixXd mass;      // augmented mass matrix
  Eigen::VectorXd force;     // augmented generalised force
  Eigen::MatrixXd reduced;   // free block, factorised in place
  Eigen::VectorXd rhs, solution, column, coupling;
  Rows lumped;               // scratch: a segment's Jacobian rows times its lumped mass
  std::vector<int> free, fixed;
  // Generalised forces the caller applies to the coordinates (size entries),
  // added to Q by every evaluation until changed: the moments -s D of devices
  // across a joint on its theta (virtual work, MODEL.md 11), which the chain
  // does not model itself (its tendons it does). Zero from make_workspace.
  Eigen::VectorXd applied;
};
ChainWorkspace make_workspace(const Chain& c);

struct ChainPower;

// q'' (size entries; closed joints' theta'' = 0). Allocates nothing. With
// `power`, also chain_power of the same state, from the same kinematics.
void chain_acceleration(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                        Eigen::Ref<const Eigen::VectorXd> q_dot, Eigen::Ref<Eigen::VectorXd> q_ddot, ChainWorkspace& w,
                        ChainPower* power = nullptr);

// Whether chain_acceleration and chain_reactions take the closed form for a
// rigid top on a closed chain (docs/chain.md): w.rigid_top and not
// per_point, no tendon, every joint closed but the top one, which rocks or
// is closed, the top segment rigid, and every segment below rigid but the
// one the top stands on.
bool chain_rigid_top(const Chain& c, ChainPhases phases, const ChainWorkspace& w);

// The reaction of joint j on the segment above, in the face's frame: N normal
// (compression > 0), V shear, M the joint's moment, signed as theta (M > 0 tips
// the part above toward the right corner). A rocking joint carries N and V at
// its pivot and M = 0.
struct JointReaction {
  double N = 0, V = 0, M = 0;
};
// corner_acceleration of a closed joint about each of its corners.
struct CornerAcceleration {
  double left = 0, right = 0;
  double operator[](Pivot s) const { return s == Pivot::left ? left : right; }
  // What a restraining moment m about each corner (the generalised force
  // -s m on theta_j) changes s theta_j'' by, per N m: -1 / the inertia of the
  // system about that corner. A restraint held at rest (MODEL.md 11's D_0)
  // lowers the corner's acceleration by D_0 / that inertia.
  double left_gain = 0, right_gain = 0;
  double gain(Pivot s) const { return s == Pivot::left ? left_gain : right_gain; }
};
// The reactions of every joint, with q'' as chain_acceleration gives it; with
// `corners` (one per joint), also every closed joint's corner_acceleration
// about both corners (0 for a rocking joint), from the same factorisation:
// the trial's rotation about the corner is the closed joint's rotation about
// its centre plus the lift B of its centre per radian (docs/chain.md).
void chain_reactions(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                     Eigen::Ref<const Eigen::VectorXd> q_dot, std::span<JointReaction> out,
                     Eigen::Ref<Eigen::VectorXd> q_ddot, ChainWorkspace& w, std::span<CornerAcceleration> corners = {});

// Uplift guard of closed joint j about pivot s: s M_j - N_j B_j (> 0: the
// resultant is past the corner).
double uplift_guard(const Chain& c, int joint, Pivot s, const JointReaction& r);
// |V| / N, the friction coefficient the joint needs not to slide (infinity when N <= 0).
double friction_demand(const JointReaction& r);
// s theta_j'' were closed joint j rocking about s now (theta_j = theta_j' = 0):
// > 0 when the corner's relative acceleration points away from the face.
double corner_acceleration(const Chain& c, ChainPhases phases, int joint, Pivot s, GroundAcceleration a,
                           Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w);

// Impact of joint j (theta_j = 0 while rocking about s).
struct ImpactCandidate {
  std::vector<Phase> phases;        // after the impact
  Eigen::VectorXd q_dot;            // after the impact
  std::vector<JointReaction> impulse;  // per joint [N s] (M: [N m s])
  // Why an outcome is not admissible, joint by joint (none where the joint's
  // condition holds): a tensile impulse (the part above would be thrown off
  // the joint), a closed joint's resultant past its corner, or a joint the
  // impact opens moving shut.
  enum class Refusal { none, tensile, past_corner, shutting };
  std::vector<Refusal> refused;
  // Admissible: no joint refuses it.
  bool consistent() const {
    for (Refusal r : refused)
      if (r != Refusal::none) return false;
    return true;
  }
};
std::string refusal_words(ImpactCandidate::Refusal r, int joint);  // "a tensile impulse at joint 1", ...
// beyond_search: more outcomes than max_impact_outcomes to examine (none examined).
enum class ImpactStatus { unique, non_unique, none, beyond_search };
// The most outcomes the momentum law examines at one impact: 2 x 3^10, the
// impacting joint's two with every combination of ten closed joints' three
// (for a rigid chain of 14 joints, some 80 MB of candidates held at once;
// each holds vectors over the joints and coordinates). Each closed joint more
// triples them; an impact with more closed joints free to open states its
// outcome undecided instead.
inline constexpr std::size_t max_impact_outcomes = 118098;
struct ImpactOutcome {
  ImpactStatus status = ImpactStatus::none;
  int may_open = 0;            // the closed joints, other than the impacting one, that the impact may open
  std::vector<Phase> phases;   // the outcome (when unique)
  Eigen::VectorXd q_dot;
  std::vector<int> uplifted;   // joints the impact opened (impact-induced uplift)
  std::vector<ImpactCandidate> candidates;  // every outcome examined
};
// The momentum law of MODEL.md 15 (restitution < 0), or a given r: joint j
// continues about -s with theta_j'+ = r theta_j'-, every other velocity continuous.
ImpactOutcome chain_impact(const Chain& c, ChainPhases before, int joint, Eigen::Ref<const Eigen::VectorXd> q,
                           Eigen::Ref<const Eigen::VectorXd> q_dot, double restitution = -1);
// Velocities after an impact into the given phases (the momentum law), with the
// impulses; `consistent()` tells whether the outcome is admissible.
ImpactCandidate impact_into(const Chain& c, ChainPhases before, int joint, ChainPhases after,
                            Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot);

// Energy (MODEL.md 7): kinetic, gravity (m g y from rest), elastic (1/2 x'K x),
// tendons' stored int F de; and the powers: of the ground, -sum m (a_g x' + a_v y'),
// and of the viscous damping, x'C x' (dE/dt = ground - damping).
struct ChainEnergy {
  double kinetic = 0, gravity = 0, elastic = 0, tendons = 0;
  double total() const { return kinetic + gravity + elastic + tendons; }
};
struct ChainPower {
  double ground = 0, damping = 0;
};
ChainEnergy chain_energy(const Chain& c, ChainPhases phases, Eigen::Ref<const Eigen::VectorXd> q,
                         Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w);
ChainPower chain_power(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                       Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w);

// Every joint closed, linearised about rest (q = q' = 0, a_g = 0): the
// elastic coordinates x = q[joints, size) obey
//   M x'' + C x' + K x = f a_g
// to first order in x, x' and a_g (docs/chain.md "Every joint closed"):
// M = sum m_i J_i'J_i at rest; K each flexible segment's stiffness plus
// gravity's, g sum m_i d2y_i/dx2 (the face turning with phi tips the segments
// above it over: P-delta, which lowers K); C each segment's Rayleigh C; f =
// -sum m_i dx_i/dx (the ground's acceleration as the frame's). What it drops
// is of second order: M's and gravity's change with phi, the velocity terms.
struct ChainAtRest {
  Eigen::MatrixXd M, K, C;
  Eigen::VectorXd f;
};
ChainAtRest chain_at_rest(const Chain& c);

// The mass matrix sum m_i J_i'J_i on every coordinate (size x size) at rest
// (q = q' = 0) in the given phases: a rocking joint's theta turns the part
// above about its corner; a closed joint's rows and columns are its rotation
// about its centre (which its constraint then holds). What rosw's linear
// solves take for the inertia of the current phases (docs/chain.md "Stiff
// steps").
Eigen::MatrixXd chain_mass_at_rest(const Chain& c, ChainPhases phases);

// Tendon k's elongation e [m] and force [N].
double tendon_elongation(const Chain& c, ChainPhases phases, int k, Eigen::Ref<const Eigen::VectorXd> q,
                         ChainWorkspace& w);
// Position of a point of a segment (an anchor) in the ground's frame [m].
Eigen::Vector2d anchor_position(const Chain& c, ChainPhases phases, const ChainAnchor& p,
                                Eigen::Ref<const Eigen::VectorXd> q, ChainWorkspace& w);

}  // namespace rocking
