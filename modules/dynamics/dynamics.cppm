// rocking.dynamics: the equations of motion of MODEL.md 3 and 4 as free
// functions of (model, pivot, ground acceleration, state).
// Full contact (Eq. 1): M u'' + C u' + K u = -M 1 a_g.
// The ground's vertical acceleration a_v (upward, MODEL.md 14) replaces g by
// g + a_v in every gravity term of the rocking equations (and of the uplift
// guard, rocking.contact); full contact does not feel it (no geometric
// stiffness). Its power on the structure, -a_v sum m_i y_i', joins the ground's
// input, the potential staying m g y.
// Rocking about pivot s (Eqs. 4-5 from the Lagrangian, with the gravity sign
// of MODEL.md 9.2): with w = B1 - s u and J(u) = J_p + u'Mu - 2sB 1'Mu,
//   [M  MH; H'M  J(u)] [u''; th''] = [rhs_u; rhs_th]  (MODEL.md 4).
// M is diagonal (lumped), so the system is solved in closed form:
//   th'' = (rhs_th - H' rhs_u) / (m0 B^2 + w'Mw),  u'' = M^-1 rhs_u - H th''.
// Devices enter as a given number, their generalised moment
// D = sum_k F_k de_k/d|th| (rocking.devices owns it), as -s D in rhs_th; for
// the paper's edge damper D = F_hd 2B cos(th/2).
// A rigid block (Structure::rigid) has u = 0 throughout (its K and C are
// zero): J_p th'' = rhs_th(u = 0), the constrained equation, not the free one.
// The elastic coordinates q of a state are the nodal displacements (q = u) or
// the amplitudes of the fixed-base modes (u = Phi q, Phi'M Phi = mu I with mu
// = 1'M1, so that q is in metres; Chopra, Dynamics of Structures, ch. 12). The
// equations keep their form in either; projected on the modes (with
// Rayleigh damping, which the modes diagonalise) every term is a diagonal or a
// dot product with a fixed vector:
//   M u -> mu q, 1'M u -> mu r'q, H'M u -> mu h'q, K u + C u' -> mu (k q + c q'),
// r = Phi^-1 1, h = Phi^-1 H, k = omega^2, c = a0 + a1 omega^2, so that a
// right-hand side costs O(N) instead of a pass over K (O(N^2)).
// mechanical_energy is kinetic + gravity (from rest) + elastic, and
// ground_input_power the power of the a_g and a_v terms on (u', th'), for the energy
// bookkeeping of MODEL.md 7: dE/dt = P_ground - u'Cu' - sum_k F_k e_k'. SI units.
module;
#include <rocking/eigen.hpp>
export module rocking.dynamics;
export import rocking.geometry;
export import rocking.beam;

export namespace rocking {

enum class ElasticCoordinates { nodal, modal };

// The ground's acceleration at an instant [m/s^2]: h along the model's plane
// (a_g), v upward (a_v). A horizontal acceleration alone converts to one
// without vertical shaking.
struct GroundAcceleration {
  double h = 0, v = 0;
  constexpr GroundAcceleration(double horizontal = 0, double vertical = 0) : h(horizontal), v(vertical) {}
};

// The fixed-base modes as coordinates (see the top of this file).
struct ModalBasis {
  double mu = 0;                // 1'M1, the mass of each mode [kg]
  Eigen::MatrixXd Phi, inverse; // u = Phi q, q = Phi^-1 u = Phi'M u / mu
  Eigen::VectorXd k, c;         // omega^2 [1/s^2], a0 + a1 omega^2 [1/s]
  Eigen::VectorXd r, h;         // Phi^-1 1 [-], Phi^-1 H [m]
  Eigen::VectorXd hk, hc;       // h k, h c (H'(K u + C u') = mu (hk'q + hc'q'))
};

// Constant data the equations need, built once.
struct RockingBody {
  Structure structure;
  StructuralMatrices matrices;
  double g = gravity;
  // Derived once by make_body: H'M1 [kg m], m0 + 1'M1 [kg], m0 B^2 [kg m^2],
  // m0 B [kg m], 1/m per node [1/kg], and [K'H; C'H] (2N: H'(K u + C u'),
  // the moment of the elastic forces about the base, as one dot product with
  // [u; u']; empty for a rigid block).
  double HM1 = 0, total_mass = 0, base_inertia = 0, base_moment = 0;
  Eigen::VectorXd inverse_masses, moment_row;
  // The state's elastic coordinates; moment_row is on [q; q'].
  ElasticCoordinates coordinates = ElasticCoordinates::nodal;
  ModalBasis modes;  // filled when modal
};
RockingBody make_body(const Structure& s, double g = gravity);
// The same body with the fixed-base modes as its elastic coordinates (a
// flexible body; a rigid block is returned as it is).
RockingBody in_modal_coordinates(RockingBody b);

// Sums over the nodes of elastic coordinates x, y in the body's coordinates:
// 1'M u, u'M v, u'M u and H'M u [kg m, kg m^2, kg m^2, kg m^2].
double mass_sum(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x);
double mass_dot(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x, Eigen::Ref<const Eigen::VectorXd> y);
double mass_norm(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x);
double moment_sum(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x);
// H and 1 in the body's coordinates (the velocity jump H th' of an impact,
// the influence of a_g): the heights and ones, or h and r.
const Eigen::VectorXd& heights_in_coordinates(const RockingBody& b);
// u'C u' [W] for elastic velocities in the body's coordinates.
double viscous_power(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> v);
// Nodal displacements from elastic coordinates, and back.
void to_nodal(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> u);
void from_nodal(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<Eigen::VectorXd> q);

// The elastic (in the body's coordinates) and rocking coordinates of a
// state, by reference (the tilt carries theta with its half-angle sine and cosine).
struct Coordinates {
  Eigen::Ref<const Eigen::VectorXd> u, u_dot;
  Tilt tilt;
  double theta_dot;
};

// (u', u'') under full contact (theta = 0) into rates (2N entries: u' is a
// copy of u_dot).
void full_contact_acceleration(const RockingBody& b, double a_g, Eigen::Ref<const Eigen::VectorXd> u,
                               Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> rates);

// (u', u'') into rates (2N entries: u' is a copy of q.u_dot) and th'' as the
// result, while rocking about pivot p (s = sign(p): +1 right, -1 left) with device moment
// D [N m]. Allocates nothing (it runs in every right-hand side).
double rocking_acceleration(const RockingBody& b, Pivot p, GroundAcceleration a, double device_moment, const Coordinates& q,
                            Eigen::Ref<Eigen::VectorXd> rates);

// th'' of a rigid block rocking about pivot p (u = u' = 0).
double rigid_rocking_acceleration(const RockingBody& b, Pivot p, GroundAcceleration a, double device_moment, const Tilt& tilt);

// Power of the ground-acceleration terms of MODEL.md 4 and 14 on (u', th')
// [W]: -a_g times the horizontal momentum's rate terms, -a_v sum m_i y_i'
// (full contact: theta = theta' = 0 gives -a_g 1'M u', the heights fixed).
double ground_input_power(const RockingBody& b, Pivot p, GroundAcceleration a, const Coordinates& q);

// Kinetic + gravity (zero at rest) + elastic energy [J]; p is the pivot (either when theta = 0).
double mechanical_energy(const RockingBody& b, Pivot p, const Coordinates& q);

}  // namespace rocking
