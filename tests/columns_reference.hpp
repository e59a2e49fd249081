// columns_reference.hpp -- an independent reference for MODEL.md section 16,
// a structure on rocking columns (the rocking frame).
//
// Written from /work/shared/design/MODEL.md alone (sections 1-4, 6, 11, 14, 15,
// 16), without reading the project's code.  Header-only: standard library and
// GSL (odeiv2 rk8pd, Brent root finding).  Plain rather than fast.
//
// The model (derivation in the comments of the functions below)
// ---------------------------------------------------------------
// * n identical rigid uniform columns: half-width b, height 2h, mass mc;
//   R = sqrt(b^2 + h^2), alpha = atan(b/h), moment of inertia about the
//   centre mc R^2 / 3, so (4/3) mc R^2 about a corner.
// * All columns rock together by theta about their bottom corners on side s
//   (s = +1: right corners, theta > 0; s = -1: left corners, theta < 0).  Each
//   column turns clockwise by theta (signed).  The cap beam rests on the top
//   corners diagonally opposite the pivots and translates without rotating by
//       dx = 2R s (sin alpha - sin(alpha - s theta)),
//       dy = 2R (cos(alpha - s theta) - cos alpha).
// * On the beam stands a structure in full contact with it: lumped masses m_i
//   at heights H_i above the column tops, on the beam's centre line.  Rigid:
//   the masses move with the beam.  Flexible: each mass has a horizontal
//   elastic displacement u_i relative to the beam; elastic forces K u, Rayleigh
//   damping C u' (section 1's condensed N x N matrices, given as inputs).  No
//   geometric stiffness (section 3/14: full contact has none, and the beam
//   does not tilt).
// * Ground motion (section 14): in the ground's frame every mass feels gravity
//   g + a_v(t) (a_v upward positive) and the inertial force -m a_h(t) (a_h the
//   ground's horizontal acceleration, + = right).  Records are piecewise
//   linear between samples; the integrator stops at every sample (kink).
// * Generalised coordinates q: rocking & flexible [u_1..u_N, theta];
//   rocking & rigid [theta]; full contact (s = 0, theta = 0 held) & flexible
//   [u]; full contact & rigid: none.
//   Lagrange: M(q) q'' = Q(q, q', t) with M = sum m J^T J (+ the columns'
//   rotational inertia), Q = - sum m J^T (J' q') - sum m J^T (a_h, g + a_v)
//   - [K u + C u'; 0] - sum_k F_k de_k/dq (devices, below).
// * Devices (MODEL.md 11, 16), each with a law: `elastic` F = max(0, P0 + k e)
//   (no state) or `bouc-wen` F = k eps e + k (1 - eps) d_y z with
//   d_y z' = e' - alpha |e'| z |z|^(n-1) - beta e' |z|^n (one state z, part of
//   the ODE state).  Kinematics:
//   - `chord` / `vertical` at the base of EVERY column alike (n copies), anchor
//     at x from the column's axis, lever l = b - s x about the pivot s;
//     e = 2 l sin(|th|/2) (chord) or sqrt((L + l sin|th|)^2 + (l (1 - cos th))^2) - L
//     (vertical, free length L), de/dth = s de/d|th| (section 11's forms).
//     A device acts while its anchor is lifted (s != 0, l > 0).
//   - `beam`: one device between a ground anchor (gx, gy) and an anchor on the
//     beam's underside at (bx, 2h) at rest, which moves with the beam by
//     (dx, dy); e = |anchor distance| - rest distance, de/dth = n . d(dx, dy)/dth.
//     Acts while the frame rocks about either side.
//   In full contact e = e' = 0: a device's states rest; its force at rest
//   F(0, z) restrains uplift by F(0, z) de/d|th| at th = 0 (section 11).
//
// Units: SI (m, kg, s, N, rad).  Angles in rad, angular rates in rad/s.
#pragma once

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace colref {

using Vec = std::vector<double>;

// ----------------------------------------------------------------- data ---

enum class Law { elastic, bouc_wen };
enum class Kinematics { chord, vertical, beam };

struct Device {
    Kinematics kin = Kinematics::chord;
    double x = 0.0;     // chord / vertical: anchor from each column's axis, |x| <= b (m);
                        // beam: the ground anchor's x from the frame's centre line (m)
    double L = 0.0;     // vertical: free length (m)
    double gy = 0.0;    // beam: the ground anchor's height above the columns' bottoms (m)
    double bx = 0.0;    // beam: the beam anchor's x from the centre line, at height 2h (m)
    Law law = Law::elastic;
    double k = 0.0;     // stiffness (N/m)
    double P0 = 0.0;    // elastic: prestress (N)
    double eps = 0.0, dy = 1e-3, alpha = 0.5, beta = 0.5, nbw = 1.0;  // bouc-wen
};

struct Frame {
    // columns
    int n = 2;          // number of identical columns (>= 1; >= 2 for contact forces)
    double b = 0.2;     // half-width (m)
    double h = 1.0;     // half-height (m): a column is 2h tall
    double mc = 1000.0; // mass of one column (kg)
    Vec xcol;           // column axes along the beam, from its centre line (m);
                        // used only by top_contact_forces (empty: n columns
                        // equally spaced over [-1, 1] m)
    // cap beam
    double mb = 0.0;    // beam mass (kg), a point on the centre line
    double hb = 0.0;    // height of the beam's mass centre above the column tops (m);
                        // contact forces only
    // structure standing on the beam
    Vec m;              // lumped masses (kg)
    Vec H;              // their heights above the column tops (m); contact forces only
    bool flexible = false;
    Vec K;              // N x N row-major stiffness (N/m), flexible only
    Vec C;              // N x N row-major damping (N s/m), flexible only (empty = 0)
    double g = 9.81;    // gravity (m/s^2)
    std::vector<Device> dev;  // devices (MODEL.md 11 / 16), none by default

    int N() const { return static_cast<int>(m.size()); }
    int ndof_u() const { return flexible ? N() : 0; }
    double R() const { return std::sqrt(b * b + h * h); }
    double alpha() const { return std::atan2(b, h); }
    double m_structure() const { double s = 0; for (double x : m) s += x; return s; }
    double m_deck() const { return mb + m_structure(); }  // everything carried by the beam
    double gamma() const { return m_deck() / (n * mc); }
    Vec column_x() const {
        if (!xcol.empty()) return xcol;
        Vec x(n, 0.0);
        for (int k = 0; k < n && n > 1; ++k) x[k] = -1.0 + 2.0 * k / (n - 1);
        return x;
    }
};

// Phase and continuous state.
struct State {
    int s = 0;          // +1 / -1 rocking about right / left bottom corners; 0 full contact
    double th = 0.0;    // columns' common angle (rad), s*th >= 0 while rocking
    double thd = 0.0;   // its rate (rad/s)
    Vec u, ud;          // elastic displacements / velocities relative to the beam (m, m/s);
                        // size N when flexible, empty when rigid
    Vec z;              // one Bouc-Wen state per device (0 for the others); empty = all 0
};

// Piecewise-linear ground motion: samples (t_k, ah_k, av_k).  Zero before the
// first and after the last sample (both are breakpoints).  No samples = no motion.
struct Ground {
    Vec t, ah, av;      // s, m/s^2 (ah + = right), m/s^2 (av + = up)

    static Ground none() { return {}; }
    static Ground constant(double ah, double av, double t_end) {
        return Ground{{0.0, t_end}, {ah, ah}, {av, av}};
    }
    // Breakpoints (sorted).
    const Vec& breaks() const { return t; }
    // Segment index containing time x, for evaluation "inside" the interval
    // [lo, hi] the integrator is working on: pass the interval's midpoint.
    int segment(double x) const {
        if (t.empty() || x < t.front()) return -1;
        if (x >= t.back()) return static_cast<int>(t.size()) - 1;
        auto it = std::upper_bound(t.begin(), t.end(), x);
        return static_cast<int>(it - t.begin()) - 1;
    }
    // Value on segment k (linear between samples k and k+1; 0 outside).
    void eval(int k, double x, double& a_h, double& a_v) const {
        if (k < 0 || k + 1 >= static_cast<int>(t.size())) { a_h = 0; a_v = 0; return; }
        const double w = (x - t[k]) / (t[k + 1] - t[k]);
        a_h = ah[k] + w * (ah[k + 1] - ah[k]);
        a_v = av[k] + w * (av[k + 1] - av[k]);
    }
    // Convenience for a time not on a kink.
    void at(double x, double& a_h, double& a_v) const { eval(segment(x), x, a_h, a_v); }
};

// ------------------------------------------------------ closed forms (16) ---

inline double p2_single(const Frame& f) { return 3.0 * f.g / (4.0 * f.R()); }   // p^2 (1/s^2)
inline double p2_hat(const Frame& f) {                                          // p̂^2 (1/s^2)
    const double ga = f.gamma();
    return p2_single(f) * (1 + 2 * ga) / (1 + 3 * ga);
}
inline double r_closed(const Frame& f) {                                        // section 16 r
    const double a = f.alpha(), ga = f.gamma();
    return (1 - 1.5 * std::sin(a) * std::sin(a) + 3 * ga * std::cos(2 * a)) / (1 + 3 * ga);
}

// --------------------------------------------------------- small algebra ---

// Solve A x = rhs (A n x n row-major) by Gaussian elimination, partial pivoting.
inline Vec solve(Vec A, Vec rhs) {
    const int n = static_cast<int>(rhs.size());
    for (int c = 0; c < n; ++c) {
        int p = c;
        for (int r = c + 1; r < n; ++r)
            if (std::fabs(A[r * n + c]) > std::fabs(A[p * n + c])) p = r;
        if (A[p * n + c] == 0.0) throw std::runtime_error("colref::solve: singular matrix");
        if (p != c) {
            for (int k = 0; k < n; ++k) std::swap(A[p * n + k], A[c * n + k]);
            std::swap(rhs[p], rhs[c]);
        }
        for (int r = c + 1; r < n; ++r) {
            const double l = A[r * n + c] / A[c * n + c];
            if (l == 0.0) continue;
            for (int k = c; k < n; ++k) A[r * n + k] -= l * A[c * n + k];
            rhs[r] -= l * rhs[c];
        }
    }
    Vec x(n);
    for (int r = n - 1; r >= 0; --r) {
        double s = rhs[r];
        for (int k = r + 1; k < n; ++k) s -= A[r * n + k] * x[k];
        x[r] = s / A[r * n + r];
    }
    return x;
}

// ------------------------------------------------------------ kinematics ---
//
// Column k rocking about its bottom corner s (at x = X_k + s b, y = 0) turns
// clockwise by theta.  Its centre, at (-s b, h) from the pivot at rest, is at
//     x = X_k + s R (sin alpha - sin(alpha - s th)),   y = R cos(alpha - s th);
// d/dth = (R cos(alpha - s th), s R sin(alpha - s th));
// d2/dth2 = (s R sin(alpha - s th), -R cos(alpha - s th))    (toward the pivot).
// The top corner diagonally opposite the pivot (at (-2 s b, 2h) from it) moves
// twice as far: the beam translation (dx, dy) of section 16, with derivatives
// twice the above.  Every structure mass i sits at (dx + u_i, 2h + H_i + dy).

struct Point {        // a mass point: mass, position, Jacobian row pair, J' q'
    double mass;
    double x, y;
    Vec Jx, Jy;       // d x / d q, d y / d q
    double ax, ay;    // (dJ/dt) q'  (velocity-product acceleration)
};

struct Layout {       // where things are in q
    int nq = 0;
    int iu = 0;       // first u index (flexible), u at iu..iu+N-1
    int ith = -1;     // theta index, -1 in full contact
};

inline Layout layout(const Frame& f, int s) {
    Layout L;
    const int nu = f.ndof_u();
    L.iu = 0;
    L.ith = (s != 0) ? nu : -1;
    L.nq = nu + (s != 0 ? 1 : 0);
    return L;
}

inline void to_q(const Frame& f, const State& st, Vec& q, Vec& qd) {
    const Layout L = layout(f, st.s);
    q.assign(L.nq, 0.0); qd.assign(L.nq, 0.0);
    for (int i = 0; i < f.ndof_u(); ++i) { q[L.iu + i] = st.u[i]; qd[L.iu + i] = st.ud[i]; }
    if (L.ith >= 0) { q[L.ith] = st.th; qd[L.ith] = st.thd; }
}

inline State from_q(const Frame& f, int s, const Vec& q, const Vec& qd) {
    const Layout L = layout(f, s);
    State st; st.s = s;
    st.u.assign(f.ndof_u(), 0.0); st.ud.assign(f.ndof_u(), 0.0);
    for (int i = 0; i < f.ndof_u(); ++i) { st.u[i] = q[L.iu + i]; st.ud[i] = qd[L.iu + i]; }
    if (L.ith >= 0) { st.th = q[L.ith]; st.thd = qd[L.ith]; }
    return st;
}

// All mass points (columns' centres, beam, structure masses) for phase st.s.
// In full contact theta = 0 is held: the points' theta columns are absent.
inline std::vector<Point> points(const Frame& f, const State& st) {
    const Layout L = layout(f, st.s);
    const int s = st.s;
    const double R = f.R(), a = f.alpha();
    const double th = (s != 0) ? st.th : 0.0, w2 = (s != 0) ? st.thd * st.thd : 0.0;
    const double ph = a - s * th;                       // alpha - s theta
    const double cx = (s != 0) ? s * R * (std::sin(a) - std::sin(ph)) : 0.0;
    const double cy = R * std::cos(ph);                 // = h when theta = 0
    const double dcx = R * std::cos(ph), dcy = s * R * std::sin(ph);
    const double acx = w2 * s * R * std::sin(ph), acy = -w2 * R * std::cos(ph);
    const Vec X = f.column_x();
    std::vector<Point> P;
    for (int k = 0; k < f.n; ++k) {
        Point p{f.mc, X[k] + cx, cy, Vec(L.nq, 0.0), Vec(L.nq, 0.0), acx, acy};
        if (L.ith >= 0) { p.Jx[L.ith] = dcx; p.Jy[L.ith] = dcy; }
        P.push_back(p);
    }
    // beam and structure: translate by (dx, dy) = twice the centre's motion
    const double dx = 2 * cx, dy = 2 * (cy - f.h);
    {
        Point p{f.mb, dx, 2 * f.h + f.hb + dy, Vec(L.nq, 0.0), Vec(L.nq, 0.0), 2 * acx, 2 * acy};
        if (L.ith >= 0) { p.Jx[L.ith] = 2 * dcx; p.Jy[L.ith] = 2 * dcy; }
        P.push_back(p);
    }
    for (int i = 0; i < f.N(); ++i) {
        const double ui = f.flexible ? st.u[i] : 0.0;
        Point p{f.m[i], dx + ui, 2 * f.h + f.H[i] + dy, Vec(L.nq, 0.0), Vec(L.nq, 0.0), 2 * acx, 2 * acy};
        if (L.ith >= 0) { p.Jx[L.ith] = 2 * dcx; p.Jy[L.ith] = 2 * dcy; }
        if (f.flexible) p.Jx[L.iu + i] = 1.0;
        P.push_back(p);
    }
    return P;
}

// Columns' rotational inertia about their centres, all n of them: adds
// (1/2) n mc R^2/3 theta'^2 to T (the column angle is -theta in both phases).
inline double columns_rot_inertia(const Frame& f) { return f.n * f.mc * f.R() * f.R() / 3.0; }

// --------------------------------------------------------------- devices ---
//
// Section 11's kinematics for the column devices (lever l = b - s x about the
// pivot s, e a function of |theta|), and the beam device's straight distance
// with the beam's translation (dx, dy) of section 16.

struct DeviceKin {
    bool acting = false;  // lifted anchor (column devices) / rocking (beam device)
    double e = 0.0;       // elongation (m)
    double dedth = 0.0;   // de/dtheta, theta signed (m/rad); e' = dedth theta'
    double copies = 1.0;  // n for a column device (one per column), 1 for the beam device
    double nx = 0.0, ny = 1.0;  // beam device: unit vector ground anchor -> beam anchor
    double ax = 0.0;      // beam device: the beam anchor's x relative to the beam's centre (= bx)
};

inline double z_of(const State& st, std::size_t k) { return st.z.empty() ? 0.0 : st.z[k]; }

// Device d in phase s at angle th (s = 0: full contact, e = 0).
inline DeviceKin device_kin(const Frame& f, const Device& d, int s, double th) {
    DeviceKin k;
    if (d.kin == Kinematics::beam) {
        const double R = f.R(), a = f.alpha(), ph = a - s * th;
        const double dx = s != 0 ? 2 * s * R * (std::sin(a) - std::sin(ph)) : 0.0;
        const double dy = s != 0 ? 2 * R * (std::cos(ph) - std::cos(a)) : 0.0;
        const double rx0 = d.bx - d.x, ry0 = 2 * f.h - d.gy;
        const double rx = rx0 + dx, ry = ry0 + dy, r = std::hypot(rx, ry);
        k.nx = rx / r;
        k.ny = ry / r;
        k.ax = d.bx;
        if (s == 0) return k;
        k.acting = true;
        k.e = r - std::hypot(rx0, ry0);
        k.dedth = k.nx * 2 * R * std::cos(ph) + k.ny * 2 * s * R * std::sin(ph);
        return k;
    }
    k.copies = f.n;
    const double l = f.b - s * d.x;
    if (s == 0 || l <= 0.0) return k;
    k.acting = true;
    const double a = std::fabs(th);
    double de = 0.0;  // de/d|theta|
    if (d.kin == Kinematics::chord) {
        k.e = 2 * l * std::sin(0.5 * a);
        de = l * std::cos(0.5 * a);
    } else {
        const double A = d.L + l * std::sin(a), B = l * (1 - std::cos(a)), r = std::hypot(A, B);
        k.e = r - d.L;
        de = (A * l * std::cos(a) + B * l * std::sin(a)) / r;
    }
    k.dedth = s * de;
    return k;
}

// Tension F (N) of one device at elongation e with state z.
inline double device_force(const Device& d, double e, double z) {
    if (d.law == Law::elastic) return std::max(0.0, d.P0 + d.k * e);
    return d.k * d.eps * e + d.k * (1 - d.eps) * d.dy * z;
}

// z' of a Bouc-Wen device at elongation rate edot.
inline double bouc_wen_rate(const Device& d, double edot, double z) {
    const double az = std::fabs(z);
    return (edot - d.alpha * std::fabs(edot) * z * std::pow(az, d.nbw - 1) - d.beta * edot * std::pow(az, d.nbw)) / d.dy;
}

// Stored energy of an elastic device, int_0^e max(0, P0 + k x) dx (J; 0 for Bouc-Wen).
inline double device_energy(const Device& d, double e) {
    if (d.law != Law::elastic) return 0.0;
    auto prim = [&](double x) { return d.P0 * x + 0.5 * d.k * x * x; };
    const double slack = d.k > 0 ? -d.P0 / d.k : -std::numeric_limits<double>::infinity();  // F = 0 below
    if (d.P0 >= 0) return e >= slack ? prim(e) : prim(slack);
    return e >= slack ? prim(e) - prim(slack) : 0.0;
}

// The devices' moment D = sum F de/d|theta| of phase st.s (N m): -s D on theta.
inline double device_moment(const Frame& f, const State& st) {
    double D = 0.0;
    for (std::size_t k = 0; k < f.dev.size(); ++k) {
        const DeviceKin K = device_kin(f, f.dev[k], st.s, st.th);
        if (K.acting) D += K.copies * device_force(f.dev[k], K.e, z_of(st, k)) * st.s * K.dedth;
    }
    return D;
}

// The devices' moment at rest about s, D_0(s) = sum F(0, z) de/d|theta| at theta = 0 (N m).
inline double device_moment_at_rest(const Frame& f, const State& st, int s) {
    State at = st;
    at.s = s;
    at.th = 0.0;
    return device_moment(f, at);
}

// M(q): nq x nq row-major.
inline Vec mass_matrix(const Frame& f, const State& st) {
    const Layout L = layout(f, st.s);
    const int nq = L.nq;
    Vec M(nq * nq, 0.0);
    for (const Point& p : points(f, st))
        for (int r = 0; r < nq; ++r)
            for (int c = 0; c < nq; ++c)
                M[r * nq + c] += p.mass * (p.Jx[r] * p.Jx[c] + p.Jy[r] * p.Jy[c]);
    if (L.ith >= 0) M[L.ith * nq + L.ith] += columns_rot_inertia(f);
    return M;
}

// Q(q, q', t): velocity terms, gravity g + a_v, ground a_h, elastic and damping.
inline Vec gen_forces(const Frame& f, const State& st, double a_h, double a_v) {
    const Layout L = layout(f, st.s);
    const int nq = L.nq;
    Vec Q(nq, 0.0);
    const double ge = f.g + a_v;
    for (const Point& p : points(f, st))
        for (int r = 0; r < nq; ++r)
            Q[r] -= p.mass * (p.Jx[r] * (p.ax + a_h) + p.Jy[r] * (p.ay + ge));
    if (f.flexible) {
        const int N = f.N();
        for (int i = 0; i < N; ++i) {
            double e = 0;
            for (int j = 0; j < N; ++j) {
                e += f.K[i * N + j] * st.u[j];
                if (!f.C.empty()) e += f.C[i * N + j] * st.ud[j];
            }
            Q[L.iu + i] -= e;
        }
    }
    if (L.ith >= 0) Q[L.ith] -= st.s * device_moment(f, st);  // - sum F de/dtheta
    return Q;
}

struct Accel {
    double thdd = 0.0;  // rad/s^2 (0 in full contact)
    Vec udd;            // m/s^2, relative to the beam (size N if flexible)
};

// Accelerations of the phase st.s at ground accelerations (a_h, a_v).
inline Accel accelerations(const Frame& f, const State& st, double a_h, double a_v) {
    const Layout L = layout(f, st.s);
    Accel A;
    A.udd.assign(f.ndof_u(), 0.0);
    if (L.nq == 0) return A;
    const Vec qdd = solve(mass_matrix(f, st), gen_forces(f, st, a_h, a_v));
    for (int i = 0; i < f.ndof_u(); ++i) A.udd[i] = qdd[L.iu + i];
    if (L.ith >= 0) A.thdd = qdd[L.ith];
    return A;
}

// ---------------------------------------------------------------- energy ---

struct Energy {
    double kinetic = 0, potential = 0, elastic = 0;
    double devices = 0;  // elastic devices' stored energy (Bouc-Wen devices not counted)
    double total() const { return kinetic + potential + elastic + devices; }
};

// Kinetic (1/2 q'^T M q'), gravitational potential with f.g (zero with every
// mass at its height at rest, theta = 0), elastic (1/2 u^T K u).  J.
inline Energy energy(const Frame& f, const State& st) {
    Energy E;
    Vec q, qd; to_q(f, st, q, qd);
    const int nq = static_cast<int>(q.size());
    const Vec M = mass_matrix(f, st);
    for (int r = 0; r < nq; ++r)
        for (int c = 0; c < nq; ++c) E.kinetic += 0.5 * qd[r] * M[r * nq + c] * qd[c];
    State rest = st; rest.th = 0; rest.thd = 0;
    const auto P = points(f, st), P0 = points(f, rest);
    for (size_t k = 0; k < P.size(); ++k) E.potential += P[k].mass * f.g * (P[k].y - P0[k].y);
    if (f.flexible) {
        const int N = f.N();
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j) E.elastic += 0.5 * st.u[i] * f.K[i * N + j] * st.u[j];
    }
    for (const Device& d : f.dev) {
        const DeviceKin K = device_kin(f, d, st.s, st.th);
        if (K.acting) E.devices += K.copies * device_energy(d, K.e);
    }
    return E;
}

// ---------------------------------------------------- uplift from contact ---
//
// In full contact (columns and beam at rest, theta = 0) the structure's base
// shear V = 1^T (K u + C u') pushes the beam (structure's reaction), the beam
// (+ its own mass) feels -(mb) a_h and the columns -mc a_h at mid-height.
// About the bottom corners s, with the frame as the mechanism of section 16
// (tops at 2h, the deck's weight acting at the top corners 2b from the pivot):
//   overturning  O_s = s [ 2h (V - mb a_h) - h n mc a_h ]     (rigid: V = -m_s a_h)
//   restoring    W_s = (g + a_v) [ n mc b + 2b (mb + m_s) ]
// and g_s = O_s - W_s - D_0(s), D_0(s) the devices' moment at rest about s
// (section 11: F(0, z) de/d|theta| at theta = 0).  Uplift about s when g_s > 0.  (g_s equals the rocking
// equations' s theta'' at theta = theta' = 0 times (J - (2h)^2 m_s) for the
// flexible case, J for the rigid one: the self-test checks it.)  N m.
inline double uplift_guard(const Frame& f, const State& st, int s, double a_h, double a_v) {
    double V = 0;
    if (f.flexible) {
        const int N = f.N();
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j) {
                V += f.K[i * N + j] * st.u[j];
                if (!f.C.empty()) V += f.C[i * N + j] * st.ud[j];
            }
    } else {
        V = -f.m_structure() * a_h;
    }
    const double O = s * (2 * f.h * (V - f.mb * a_h) - f.h * f.n * f.mc * a_h);
    const double W = (f.g + a_v) * (f.n * f.mc * f.b + 2 * f.b * f.m_deck());
    return O - W - device_moment_at_rest(f, st, s);
}

// ------------------------------------------------- column-top contact forces ---
//
// The beam with the structure (everything above the column tops) is one free
// body: column k pushes it up with N_k and sideways with -F_k at the contact
// point xi_k = X_k - s b (the top corner opposite the pivot; X_k in full
// contact), fixed relative to the beam.  With a the points' accelerations in
// the ground frame and the fields (a_h, g + a_v) added:
//   sum N_k = Fy = sum m (a_y + g + a_v),   sum F_k = -Fx = -sum m (a_x + a_h),
//   sum xi_k N_k = Mo = sum m [ (x - x_O) (a_y + g + a_v) - (y - y_O)(a_x + a_h) ]
// about the beam's underside centre O.  The beam neither rotates nor tilts.
// With n = 2 this fixes N; with n > 2 the split is statically indeterminate
// and this reference takes the minimum-norm one (N linear in xi, as for equal
// axial flexibility).  Each column's own equation (about its pivot) then gives
// its F_k:  2R [F_k cos(alpha - s th) - s N_k sin(alpha - s th)]
//         = (4/3) mc R^2 th'' + mc R [(g + a_v) s sin(alpha - s th) + a_h cos(alpha - s th)].
// Devices: a beam device pulls the deck with -F n at its anchor on the beam's
// underside (F(0, z) along the rest direction in full contact), so its (Px, Py)
// leaves the sums above: sum N_k = Fy - Py, sum xi_k N_k = Mo - bx Py,
// sum F_k = Px - Fx.  A column device acts on its column, adding F de/dth to
// the right-hand side of the column's equation.
// `residual` = sum F_k + Fx - Px: zero when Lagrange's theta equation and the
// bodies' Newton-Euler equations agree (a consistency check).
// In full contact F_k is -Fx/n (indeterminate too).  N (newtons).
struct ContactForces {
    Vec N;              // normal (compressive > 0) force at each column top (N)
    Vec F;              // horizontal force of the beam on each column top (N)
    double Nmin = 0;    // smallest N
    double Fy = 0, Fx = 0, Mo = 0;
    double residual = 0;
};

inline ContactForces top_contact_forces(const Frame& f, const State& st, double a_h, double a_v) {
    if (f.n < 2) throw std::runtime_error("top_contact_forces: needs n >= 2 columns");
    const Layout L = layout(f, st.s);
    const Accel A = accelerations(f, st, a_h, a_v);
    Vec qd, q; to_q(f, st, q, qd);
    Vec qdd(L.nq, 0.0);
    for (int i = 0; i < f.ndof_u(); ++i) qdd[L.iu + i] = A.udd[i];
    if (L.ith >= 0) qdd[L.ith] = A.thdd;
    const auto P = points(f, st);
    const Point& beam = P[f.n];
    const double xO = beam.x, yO = 2 * f.h + (beam.y - 2 * f.h - f.hb);
    ContactForces CF;
    const double ge = f.g + a_v;
    for (size_t k = f.n; k < P.size(); ++k) {
        const Point& p = P[k];
        double ax = p.ax, ay = p.ay;
        for (int r = 0; r < L.nq; ++r) { ax += p.Jx[r] * qdd[r]; ay += p.Jy[r] * qdd[r]; }
        CF.Fx += p.mass * (ax + a_h);
        CF.Fy += p.mass * (ay + ge);
        CF.Mo += p.mass * ((p.x - xO) * (ay + ge) - (p.y - yO) * (ax + a_h));
    }
    double Px = 0, Py = 0, Mp = 0, Gdev = 0;  // beam devices' pull and its moment about O; column devices' F de/dth
    for (std::size_t k = 0; k < f.dev.size(); ++k) {
        const DeviceKin K = device_kin(f, f.dev[k], st.s, st.th);
        const double F = device_force(f.dev[k], K.e, z_of(st, k));
        if (f.dev[k].kin == Kinematics::beam) {
            Px -= F * K.nx;
            Py -= F * K.ny;
            Mp -= F * K.ny * K.ax;
        } else if (K.acting) {
            Gdev += F * K.dedth;
        }
    }
    const Vec X = f.column_x();
    Vec xi(f.n);
    for (int k = 0; k < f.n; ++k) xi[k] = X[k] - st.s * f.b;
    double xm = 0; for (double x : xi) xm += x; xm /= f.n;
    double sxx = 0; for (double x : xi) sxx += (x - xm) * (x - xm);
    if (sxx <= 0) throw std::runtime_error("top_contact_forces: columns must not coincide");
    const double Ny = CF.Fy - Py, My = CF.Mo - Mp;
    const double slope = (My - xm * Ny) / sxx;
    CF.N.resize(f.n); CF.F.resize(f.n);
    for (int k = 0; k < f.n; ++k) CF.N[k] = Ny / f.n + slope * (xi[k] - xm);
    if (st.s == 0) {
        for (int k = 0; k < f.n; ++k) CF.F[k] = (Px - CF.Fx) / f.n;
    } else {
        const int s = st.s;
        const double R = f.R(), ph = f.alpha() - s * st.th;
        const double G = (4.0 / 3.0) * f.mc * R * R * A.thdd
                       + f.mc * R * (ge * s * std::sin(ph) + a_h * std::cos(ph)) + Gdev;
        for (int k = 0; k < f.n; ++k)
            CF.F[k] = (G / (2 * R) + s * CF.N[k] * std::sin(ph)) / std::cos(ph);
    }
    double sF = 0; for (double x : CF.F) sF += x;
    CF.residual = sF + CF.Fx - Px;
    CF.Nmin = *std::min_element(CF.N.begin(), CF.N.end());
    return CF;
}

// ---------------------------------------------------------------- impact ---
//
// Section 15's law applied to the frame.  At theta = 0 the pivots switch from
// s to -s, and the beam moves from the top corners -s b to +s b.  The impulses
// act only at the new contacts, which the post-impact kinematics keeps fixed
// together, so the momentum conjugate to every post-impact coordinate,
//     p_k = sum m v^- . d p^+ / d q_k   (+ the columns' I theta'^- for theta),
// is conserved: M^+ q'^+ = p.  Tried first: rocking about -s.  If that gives
// -s theta'^+ <= 0 (or |theta'^-| <= min_rate) the columns stay down: full
// contact, with the post-impact coordinates u only (rigid: everything stops).
// Rigid structure: theta'^+ / theta'^- = r of section 16.  Flexible: u keeps its
// value and u'^+ = u'^- + 2h (theta'^- - theta'^+) (the masses' horizontal
// momenta are conserved), and theta'^+ / theta'^- =
//   [(4/3) n mc R^2 (1 - 1.5 sin^2 a) + 4 (mb) R^2 cos 2a - 4 m_s b^2]
// / [(4/3) n mc R^2 + 4 (mb) R^2 + 4 m_s b^2].
struct ImpactOutcome {
    State post;         // post-impact state (theta = 0)
    bool rocking = false; // true: rocking about -s; false: full contact
    double ratio = 0;   // theta'^+ / theta'^- of the rocking trial (even if rejected)
};

inline ImpactOutcome momentum_impact(const Frame& f, const State& pre, double min_rate = 0.0) {
    if (pre.s == 0) throw std::runtime_error("momentum_impact: not rocking");
    State pm = pre; pm.th = 0.0;                 // impact at theta = 0
    Vec q, qdm; to_q(f, pm, q, qdm);
    const auto Pm = points(f, pm);
    auto post_for = [&](int s_new) {
        State pp = pm; pp.s = s_new;
        const Layout Lp = layout(f, s_new);
        const auto Pp = points(f, pp);
        Vec p(Lp.nq, 0.0);
        for (size_t k = 0; k < Pm.size(); ++k) {
            double vx = 0, vy = 0;
            for (size_t r = 0; r < qdm.size(); ++r) { vx += Pm[k].Jx[r] * qdm[r]; vy += Pm[k].Jy[r] * qdm[r]; }
            for (int c = 0; c < Lp.nq; ++c) p[c] += Pm[k].mass * (vx * Pp[k].Jx[c] + vy * Pp[k].Jy[c]);
        }
        if (Lp.ith >= 0) p[Lp.ith] += columns_rot_inertia(f) * pm.thd;
        Vec qd_new = (Lp.nq > 0) ? solve(mass_matrix(f, pp), p) : Vec{};
        Vec qq(Lp.nq, 0.0);
        for (int i = 0; i < f.ndof_u(); ++i) qq[Lp.iu + i] = pm.u[i];
        State post = from_q(f, s_new, qq, qd_new);
        post.z = pm.z;                           // the devices' states carry through
        return post;
    };
    ImpactOutcome out;
    State rock = post_for(-pre.s);
    out.ratio = rock.thd / pre.thd;
    if (-pre.s * rock.thd > 0 && std::fabs(pre.thd) > min_rate) {
        out.post = rock; out.rocking = true;
    } else {
        out.post = post_for(0); out.rocking = false;
    }
    return out;
}

// ------------------------------------------------------------ integration ---

struct Options {
    double epsabs = 1e-14;      // rk8pd absolute tolerance (state units)
    double epsrel = 1e-12;      // rk8pd relative tolerance
    double t_tol = 1e-14;       // event location tolerance (s)
    double t_end = 1e9;         // stop here at the latest (outcome End)
    double overturn_angle = -1; // |theta| limit, default alpha
    bool stop_on_tensile = false; // rocking: stop when a column-top force turns tensile
    Vec out_times;              // record the state at these times (sorted)
};

enum class Outcome { Impact, Overturned, TensileTop, Uplift, End };

inline const char* name(Outcome o) {
    switch (o) {
        case Outcome::Impact: return "impact";
        case Outcome::Overturned: return "overturned";
        case Outcome::TensileTop: return "tensile top contact";
        case Outcome::Uplift: return "uplift";
        default: return "end";
    }
}

struct RunResult {
    Outcome outcome = Outcome::End;
    double t = 0;              // time of the event (s)
    State state;               // state at t (the pre-impact state for Impact)
    int uplift_s = 0;          // pivot side at Uplift
    double min_top_N = std::numeric_limits<double>::infinity(); // over accepted steps + event (rocking, n >= 2)
    std::vector<State> out;    // states at opts.out_times (those reached)
    long steps = 0;
};

namespace detail {

struct OdeCtx {
    const Frame* f;
    const Ground* gm;
    int s;
    int seg;                   // record segment in use
};

// y = [q, q', z]: z one state per device (the Bouc-Wen ones evolve while they act).
inline int ode_rhs(double t, const double y[], double dydt[], void* par) {
    const OdeCtx& c = *static_cast<const OdeCtx*>(par);
    const Layout L = layout(*c.f, c.s);
    const int nq = L.nq;
    const std::size_t nz = c.f->dev.size();
    Vec q(y, y + nq), qd(y + nq, y + 2 * nq);
    State st = from_q(*c.f, c.s, q, qd);
    st.z.assign(y + 2 * nq, y + 2 * nq + nz);
    double a_h, a_v; c.gm->eval(c.seg, t, a_h, a_v);
    const Accel A = (nq > 0) ? accelerations(*c.f, st, a_h, a_v) : Accel{};
    for (int r = 0; r < nq; ++r) dydt[r] = qd[r];
    for (int i = 0; i < c.f->ndof_u(); ++i) dydt[nq + L.iu + i] = A.udd[i];
    if (L.ith >= 0) dydt[nq + L.ith] = A.thdd;
    for (std::size_t k = 0; k < nz; ++k) {
        const Device& d = c.f->dev[k];
        const DeviceKin K = device_kin(*c.f, d, c.s, st.th);
        dydt[2 * nq + k] = (d.law == Law::bouc_wen && K.acting) ? bouc_wen_rate(d, K.dedth * st.thd, st.z[k]) : 0.0;
    }
    return GSL_SUCCESS;
}

// Integrate y from t0 to t1 (inside one record segment) with a fresh driver.
inline Vec advance(OdeCtx& c, const Options& o, Vec y, double t0, double t1) {
    if (t1 == t0 || y.empty() || layout(*c.f, c.s).nq == 0) return y;  // nothing moves: z rests too
    gsl_odeiv2_system sys{ode_rhs, nullptr, y.size(), &c};
    gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd,
                                                         (t1 - t0) / 8, o.epsabs, o.epsrel);
    double t = t0;
    const int rc = gsl_odeiv2_driver_apply(d, &t, t1, y.data());
    gsl_odeiv2_driver_free(d);
    if (rc != GSL_SUCCESS) throw std::runtime_error("colref: driver failed");
    return y;
}

// Brent on [a, b] for ev(t) = event(y(t)), with ev(a) >= 0 > ev(b) (or <=/>).
inline double locate(const std::function<double(double)>& ev, double a, double b, double tol) {
    double fa = ev(a), fb = ev(b);
    if (fa == 0) return a;
    if (fb == 0) return b;
    if ((fa > 0) == (fb > 0)) return b;     // no sign change seen: take the step end
    struct P { const std::function<double(double)>* e; } par{&ev};
    gsl_function F;
    F.function = [](double x, void* p) { return (*static_cast<P*>(p)->e)(x); };
    F.params = &par;
    gsl_root_fsolver* s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    gsl_root_fsolver_set(s, &F, a, b);
    double r = b;
    for (int it = 0; it < 300; ++it) {
        gsl_root_fsolver_iterate(s);
        r = gsl_root_fsolver_root(s);
        const double lo = gsl_root_fsolver_x_lower(s), hi = gsl_root_fsolver_x_upper(s);
        if (hi - lo < tol) break;
    }
    gsl_root_fsolver_free(s);
    return r;
}

}  // namespace detail

// Integrate from state st0 at t0 in its phase until an event:
//  * rocking (s = +-1): impact (s theta crossing 0 downward) -> Impact;
//    |theta| reaching the overturning angle -> Overturned; optionally the
//    smallest column-top force turning negative -> TensileTop.
//  * full contact (s = 0): the uplift guard about either side turning
//    positive (also checked at t0) -> Uplift (uplift_s the side).
//  * t_end -> End.
// Events are located by Brent to opts.t_tol, re-integrating from the last
// accepted step.  The integrator never steps across a record sample.
inline RunResult run_phase(const Frame& f, const State& st0, double t0, const Ground& gm,
                           const Options& opts = {}) {
    const int s = st0.s;
    const Layout L = layout(f, s);
    const int nq = L.nq;
    const double th_max = opts.overturn_angle > 0 ? opts.overturn_angle : f.alpha();
    detail::OdeCtx ctx{&f, &gm, s, 0};
    RunResult res;

    const int nz = static_cast<int>(f.dev.size());
    const int ny = 2 * nq + nz;
    auto state_of = [&](const Vec& y) {
        Vec q(y.begin(), y.begin() + nq), qd(y.begin() + nq, y.begin() + 2 * nq);
        State st = from_q(f, s, q, qd);
        st.z.assign(y.begin() + 2 * nq, y.end());
        if (s == 0) { st.th = 0; st.thd = 0; }
        return st;
    };
    // Event functions: >= 0 while nothing happens.  Index: 0 impact, 1 overturn,
    // 2 tensile, 3 uplift right, 4 uplift left.
    auto events = [&](double t, const Vec& y, int seg, bool track = false) {
        const State st = state_of(y);
        double a_h, a_v; gm.eval(seg, t, a_h, a_v);
        std::vector<double> e(5, 1.0);
        if (s != 0) {
            e[0] = s * st.th;
            e[1] = th_max - s * st.th;
            if (f.n >= 2 && (opts.stop_on_tensile || track))
                e[2] = top_contact_forces(f, st, a_h, a_v).Nmin;
        } else {
            e[3] = -uplift_guard(f, st, +1, a_h, a_v);
            e[4] = -uplift_guard(f, st, -1, a_h, a_v);
        }
        return e;
    };
    auto finish = [&](Outcome o, double t, const Vec& y, int which) {
        res.outcome = o; res.t = t; res.state = state_of(y);
        if (o == Outcome::Uplift) res.uplift_s = (which == 3) ? +1 : -1;
        if (s != 0 && f.n >= 2) {
            double a_h, a_v; gm.eval(ctx.seg, t, a_h, a_v);
            res.min_top_N = std::min(res.min_top_N, top_contact_forces(f, res.state, a_h, a_v).Nmin);
        }
        return res;
    };

    Vec qv, qdv; to_q(f, st0, qv, qdv);
    Vec y(qv); y.insert(y.end(), qdv.begin(), qdv.end());
    for (int k = 0; k < nz; ++k) y.push_back(z_of(st0, static_cast<std::size_t>(k)));

    // Stop times: record samples, output times, t_end.
    Vec stops = gm.breaks();
    for (double x : opts.out_times) stops.push_back(x);
    stops.push_back(opts.t_end);
    std::sort(stops.begin(), stops.end());
    size_t io = 0;
    while (io < opts.out_times.size() && opts.out_times[io] < t0) ++io;

    double t = t0;
    {   // events already true at the start (uplift checked when contact begins)
        ctx.seg = gm.segment(t0);
        const auto e = events(t, y, ctx.seg, true);
        if (s != 0 && f.n >= 2) res.min_top_N = std::min(res.min_top_N, e[2]);
        if (s == 0) {
            if (e[3] < 0 || e[4] < 0) return finish(Outcome::Uplift, t, y, e[3] < e[4] ? 3 : 4);
        } else {
            if (e[1] < 0) return finish(Outcome::Overturned, t, y, 1);
            if (opts.stop_on_tensile && e[2] < 0) return finish(Outcome::TensileTop, t, y, 2);
        }
    }
    while (io < opts.out_times.size() && opts.out_times[io] == t0) { res.out.push_back(state_of(y)); ++io; }

    double hstep = 1e-3;
    while (t < opts.t_end) {
        double t1 = opts.t_end;
        for (double x : stops) if (x > t) { t1 = std::min(t1, x); break; }
        ctx.seg = gm.segment(0.5 * (t + t1));
        // Sub-interval loop with its own evolve (no step across t1).
        gsl_odeiv2_system sys{detail::ode_rhs, nullptr, static_cast<size_t>(std::max(1, ny)), &ctx};
        gsl_odeiv2_step* stp = nullptr; gsl_odeiv2_control* ctl = nullptr; gsl_odeiv2_evolve* evo = nullptr;
        if (nq > 0) {
            stp = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, ny);
            ctl = gsl_odeiv2_control_y_new(opts.epsabs, opts.epsrel);
            evo = gsl_odeiv2_evolve_alloc(ny);
        }
        auto cleanup = [&] {
            if (evo) gsl_odeiv2_evolve_free(evo);
            if (ctl) gsl_odeiv2_control_free(ctl);
            if (stp) gsl_odeiv2_step_free(stp);
        };
        while (t < t1) {
            const double ta = t; const Vec ya = y;
            if (nq > 0) {
                hstep = std::min(hstep, t1 - t);
                const int rc = gsl_odeiv2_evolve_apply(evo, ctl, stp, &sys, &t, t1, &hstep, y.data());
                if (rc != GSL_SUCCESS) { cleanup(); throw std::runtime_error("colref: evolve failed"); }
            } else {
                t = t1;   // nothing moves (rigid, full contact): events vary with the record only
            }
            ++res.steps;
            const auto e = events(t, y, ctx.seg, true);
            int first = -1; double tev = t;
            for (int k = 0; k < 5; ++k) {
                if (e[k] >= 0) continue;
                if (k == 2 && !opts.stop_on_tensile) continue;
                auto ev = [&, k](double x) {
                    const Vec yy = detail::advance(ctx, opts, ya, ta, x);
                    return events(x, yy, ctx.seg)[k];
                };
                const double tk = detail::locate(ev, ta, t, opts.t_tol);
                if (first < 0 || tk < tev) { first = k; tev = tk; }
            }
            if (first < 0 && s != 0 && f.n >= 2) res.min_top_N = std::min(res.min_top_N, e[2]);
            if (first >= 0) {
                const Vec yev = detail::advance(ctx, opts, ya, ta, tev);
                cleanup();
                const Outcome o = first == 0 ? Outcome::Impact : first == 1 ? Outcome::Overturned
                                : first == 2 ? Outcome::TensileTop : Outcome::Uplift;
                return finish(o, tev, yev, first);
            }
        }
        cleanup();
        while (io < opts.out_times.size() && opts.out_times[io] <= t) { res.out.push_back(state_of(y)); ++io; }
    }
    return finish(Outcome::End, t, y, -1);
}

// First impact from a rocking state (e.g. released from a tilt, s = sign(theta)).
// Returns the pre-impact state at the located time (theta ~ 0 to ~1e-15),
// or Overturned / TensileTop / End.
inline RunResult first_impact(const Frame& f, const State& st0, double t0, const Ground& gm,
                              const Options& opts = {}) {
    if (st0.s == 0) throw std::runtime_error("first_impact: start rocking (s = +-1)");
    return run_phase(f, st0, t0, gm, opts);
}

// Full contact (theta = 0 held) until the frame lifts (or t_end): the
// structure on the beam as on a fixed base.
inline RunResult full_contact_until_uplift(const Frame& f, State st0, double t0, const Ground& gm,
                                           const Options& opts = {}) {
    st0.s = 0; st0.th = 0; st0.thd = 0;
    return run_phase(f, st0, t0, gm, opts);
}

}  // namespace colref
