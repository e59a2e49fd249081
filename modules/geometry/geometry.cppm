// rocking.geometry: the structure as plain constant data, and what follows from
// its geometry alone (MODEL.md 1 and 8; the paper's Table 1 and Eq. 10).
// Nodes 1..N at heights H with lumped masses m (no rotational inertia), a rigid
// foundation beam (node 0, height 0, mass m0), two pivot axes at x = -B and +B,
// Euler-Bernoulli elements with section stiffness E*I_e (element e spans node
// e-1 to e). SI units: m, kg, N, rad.
module;
#include <rocking/eigen.hpp>

#include <cstddef>
#include <optional>
#include <string_view>
export module rocking.geometry;

export namespace rocking {

// The acceleration of gravity, for every module and unit [m/s^2].
inline constexpr double gravity = 9.81;

struct Structure {
  double half_width = 0;       // B: half the distance between the pivots [m]
  Eigen::VectorXd heights;     // H: heights of nodes 1..N, increasing [m]
  Eigen::VectorXd masses;      // m: lumped masses of nodes 1..N [kg]
  double base_mass = 0;        // m0: foundation beam [kg]
  Eigen::VectorXd EI;          // E*I_e of element e (node e-1 to e) [N m^2]
  double EI_scale = 1;         // multiplies every EI (parametric studies)
  double damping_ratio = 0;    // zeta on the first two fixed-base modes [-]
  bool rigid = false;          // a rigid block: no elastic coordinates, EI unused
};

// The base rotation theta with the sine and cosine of theta / 2, computed
// once: sin theta, cos theta and the damper's chord 4B sin(|theta|/2) all
// follow from them, so an evaluation of the equations needs no other trig.
// For |theta| <= 1.6 rad (every rocking angle short of overturning a squat
// block) they come from Taylor polynomials accurate to round-off, whose short
// dependency chain starts each rocking right-hand side sooner than a library
// call; beyond, from std::sin and std::cos. Converts implicitly from theta.
struct Tilt {
  double theta = 0, sin_half = 0, cos_half = 1;
  Tilt(double th = 0);  // NOLINT(google-explicit-constructor): theta is a tilt
  double sin() const { return 2.0 * sin_half * cos_half; }
  double cos() const { return 1.0 - 2.0 * sin_half * sin_half; }
};

// The two pivot axes: the right corner (x = +B), about which theta > 0 tips
// the structure, and the left (x = -B). sign() is the s of MODEL.md's
// equations (+1 right, -1 left); index() the slot of a per-pivot array.
enum class Pivot : signed char { left = -1, right = +1 };
constexpr int sign(Pivot p) { return static_cast<int>(p); }
constexpr std::size_t index(Pivot p) { return p == Pivot::right ? 1 : 0; }
constexpr Pivot opposite(Pivot p) { return p == Pivot::right ? Pivot::left : Pivot::right; }
inline constexpr Pivot pivots[] = {Pivot::right, Pivot::left};
std::string_view pivot_name(Pivot p);  // "right", "left"

// The phase of the motion (MODEL.md 6): full contact with the ground, or
// rocking about one pivot.
class Phase {
 public:
  constexpr Phase() = default;  // full contact
  static constexpr Phase full_contact() { return {}; }
  static constexpr Phase rocking(Pivot p) {
    Phase ph;
    ph.pivot_ = p;
    return ph;
  }
  constexpr bool is_rocking() const { return pivot_.has_value(); }
  constexpr std::optional<Pivot> pivot() const { return pivot_; }
  // s while rocking, 0 in full contact (the history's phase column).
  constexpr int sign() const { return pivot_ ? rocking::sign(*pivot_) : 0; }
  constexpr bool operator==(const Phase&) const = default;

 private:
  std::optional<Pivot> pivot_;
};
std::string_view phase_name(Phase p);  // "full_contact", "rocking(+1)", "rocking(-1)"

// Throws std::invalid_argument naming the first field that breaks an
// invariant (sizes agree, masses and EI positive, heights increasing from > 0;
// EI is not looked at for a rigid structure).
void check(const Structure& s);

Eigen::Index node_count(const Structure& s);          // N
double total_mass(const Structure& s);                // m0 + sum m
double pivot_inertia(const Structure& s);             // J_p = m0 B^2 + sum m (H^2 + B^2)
double centre_of_gravity_height(const Structure& s);  // H_cg = sum m H / total mass
double slenderness(const Structure& s);               // alpha_cg = atan(B / H_cg)
double restitution_eq10(const Structure& s);          // r = 1 - 2 (1'M1 + m0) B^2 / J_p

}  // namespace rocking
