// chain_reference.hpp -- an independent, plainly written reference for a chain of
// RIGID rocking segments (MODEL.md section 15, with sections 2, 11 and 14).
//
// Written from /work/shared/design/MODEL.md alone, without reading the project's
// implementation, so that it can check that implementation's derivation.
// Header-only: C++20 standard library + GSL (link -lgsl -lgslcblas).
//
// Model (SI units: m, kg, s, N, rad):
//  * Segments j = 0..J from the ground up. Segment j stands on joint j, the face
//    at rest height h_j (h_0 = 0: joint 0 is the ground). Its slab has half-width
//    B_j (the joint's corners are at x = -B_j and x = +B_j) and a mass m0_j on the
//    centre line at height h_j. Further lumped masses of segment j sit on the
//    centre line at given rest heights above the ground; each segment lists its
//    own, so which body a mass at a joint level belongs to is never guessed.
//    Segments are rigid; masses are points (no rotational inertia).
//  * Phase of joint j: 0 = closed (full contact), +1 / -1 = rocking about the
//    corner x = s B_j of the face below (MODEL.md 2: theta > 0 about the right
//    corner).
//  * Coordinates q: theta_j of the OPEN joints, in increasing j. theta_j is
//    segment j's rotation relative to the face below, about the active corner;
//    theta > 0 tips the body to the right, i.e. it is a CLOCKWISE rotation, so
//    the body's ccw angle is -(sum of the thetas of the joints at or below it).
//  * Positions are in the ground frame (x right, y up, origin at the centre of
//    joint 0 at rest). The ground's accelerations a_h(t) (horizontal) and
//    a_v(t) (vertical, up) enter as the frame's: every mass feels the force
//    m (-a_h, -(g + a_v)) (MODEL.md 14).
//  * Optional vertical tendon (MODEL.md 11 'elastic' law): anchored at (x_t, 0)
//    on the ground and at (x_t, H_top) on the top segment (rest coordinates);
//    elongation e = |anchor distance| - L0, L0 = H_top (the rest distance);
//    force F = max(0, P0 + k e) (tension only); stored energy U(e) = int_0^e F.
//  * Optional devices across one joint (JointDevice, MODEL.md 11's chord form in
//    the joint's frame, Kelvin-Voigt law F = k e + c e'): a generalised force on
//    that joint's theta alone, while it is open.
//  * Tendons between segments (MODEL.md 15's devices; `from_segment`): elastic,
//    anchored at the base of segment `from` (the rest point (x, h_from) of that
//    segment; from = -1: the ground at (x, 0)) and at (x, y_top) on segment `to`
//    > from; e = |anchor distance| - rest distance. Each crosses the joints
//    from + 1 .. to, and a force on the anchors only: it is internal to every
//    part above a joint at or below `from`.
//  * Devices across the base joint (MODEL.md 11, one-body style): anchor at x on
//    the base, lever l = B_0 - s x about corner s; `chord` e = 2 l sin(|th_0|/2)
//    or `vertical` e = sqrt((L + l sin|th_0|)^2 + (l (1 - cos th_0))^2) - L;
//    de/dth_0 = s de/d|th_0|; acting while joint 0 rocks and l > 0, adding
//    - F de/dth_0 to Q. Laws: elastic F = max(0, P0 + k e), or Bouc-Wen
//    F = k eps e + k (1 - eps) d_y z, d_y z' = e' - alpha |e'| z |z|^(n-1) - beta e' |z|^n,
//    its z part of the ODE state (at rest while joint 0 is closed). As forces:
//    a chord device pulls its anchor on the base (rotated about the corner)
//    back along the chord toward its ground anchor (x, 0); a vertical one pulls
//    the point (x, L) of segment 0 toward (x, 0); at rest (joint 0 closed) each
//    pulls its anchor (x, 0) down with F(0, z).
//
// Derivation used (my own route, analytic Jacobians of the chain):
//  * Joint k's active corner c_k is a material point common to segments k-1 and
//    k. A point p of segment j moves, per unit theta_k (k <= j, k open), by a
//    clockwise rotation about the CURRENT position of c_k:
//        dp/dtheta_k = ( p_y - c_k,y , -(p_x - c_k,x) ).
//  * Velocity terms: with Omega_j = -sum_{k<=j} theta_k' (ccw angular velocity),
//    the acceleration of p at q'' = 0 ("bias", = J' q') follows the rigid-body
//    rule recursively: b(c_0) = 0, b(c_{j+1}) = b(c_j) - Omega_j^2 (c_{j+1} - c_j),
//    b(p on j) = b(c_j) - Omega_j^2 (p - c_j). (For a closed joint c_j is the
//    face centre; any point of the now-merged rigid body gives the same result.)
//  * Lagrange: M = sum m J^T J, Q = sum m J^T (f/m - b) - F_t (dhat^T J_top),
//    with f/m = (-a_h, -(g + a_v)) and dhat the unit vector ground anchor -> top anchor.
//
// Readings of MODEL.md where it leaves a choice (see also the comments at each function):
//  * Joint j's corners are those of the standing segment's slab, x = +-B_j.
//  * The tendon's lower anchor is fixed to the ground (not to segment 0's slab), so it
//    stretches when joint 0 opens too.
//  * closed_joint_reactions returns CONTACT forces (the closed joints' multipliers);
//    MODEL.md 15's "s M_j >= N_j B_j + device restraint" uses resultants without the
//    device, and the two criteria coincide (shown next to the function).
//  * energy() uses the potential m g y with the constant g (MODEL.md 14), so it is
//    conserved only without ground motion.
//  * momentum_impact takes the post-impact phases from the caller; impact_impulses
//    lets the caller check that no closed joint needs a tensile impulse.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_odeiv2.h>

namespace chainref {

inline constexpr double kG = 9.81;  // m/s^2, MODEL.md's value

struct Segment {
    double h = 0.0;   // rest height of joint j (the face segment j stands on), m; h_0 = 0
    double B = 0.0;   // half-width of joint j's face / segment j's slab, m
    double m0 = 0.0;  // slab mass, kg, point on the centre line at height h
    std::vector<std::pair<double, double>> masses;  // (rest height above ground m, mass kg)
};

struct Tendon {
    bool present = false;
    double x_t = 0.0;  // anchors' horizontal position from the centre line, m
    double P0 = 0.0;   // prestress, N
    double k = 0.0;    // stiffness, N/m
};

// A device across one joint (MODEL.md 11 in that joint's frame, 15): anchored
// at x on the face below and at x on the slab of the segment above, both at
// the joint's height at rest, in section 11's chord form: while joint j rocks
// about s, e = 2 l sin(|theta_j| / 2), l = B_j - s x, and e' = (de/dtheta_j)
// theta_j'. Its law is the Kelvin-Voigt one, F = k e + c e'; it adds
// -F de/dtheta_j to Q on theta_j and nothing while the joint is closed.
struct JointDevice {
    int joint = 1;
    double x = 0.0;  // m from the centre line
    double k = 0.0;  // N/m
    double c = 0.0;  // N s/m
};

// A tendon between segments (or from the ground): see the header.
struct SegmentTendon {
    int from = -1;       // segment whose base holds the lower anchor; -1 = the ground
    int to = 0;          // segment of the upper anchor (> from)
    double x = 0.0;      // both anchors' x from the centre line at rest, m
    double y_top = 0.0;  // the upper anchor's rest height, m
    double P0 = 0.0;     // prestress, N
    double k = 0.0;      // stiffness, N/m
};

enum class Law { elastic, bouc_wen };
enum class BaseKinematics { chord, vertical };

// A device across the base joint: see the header.
struct BaseDevice {
    BaseKinematics kin = BaseKinematics::chord;
    double x = 0.0;   // anchor on the base from the centre line, |x| <= B_0, m
    double L = 0.0;   // vertical: free length, m
    Law law = Law::elastic;
    double k = 0.0, P0 = 0.0;                                           // N/m, N (P0: elastic)
    double eps = 0.0, dy = 1e-3, alpha = 0.5, beta = 0.5, nbw = 1.0;  // Bouc-Wen
};

struct Chain {
    std::vector<Segment> seg;  // j = 0..J
    double H_top = 0.0;        // rest height of the top segment's top (tendon anchor), m
    Tendon tendon;
    std::vector<JointDevice> devices;
    std::vector<SegmentTendon> tendons;
    std::vector<BaseDevice> base;  // one state z each (used by the Bouc-Wen ones)
    double g = kG;
};

// Piecewise-linear record (times strictly increasing); zero outside [t.front(), t.back()].
struct Record {
    std::vector<double> t, a;
    double at(double tt) const {
        if (t.empty() || tt < t.front() || tt > t.back()) return 0.0;
        auto it = std::upper_bound(t.begin(), t.end(), tt);
        if (it == t.end()) return a.back();
        std::size_t i = static_cast<std::size_t>(it - t.begin());  // t[i-1] <= tt < t[i]
        double w = (tt - t[i - 1]) / (t[i] - t[i - 1]);
        return a[i - 1] + w * (a[i] - a[i - 1]);
    }
};

// Ground motion: a_h(t) and a_v(t) in m/s^2, each = record (if any) + function (if any).
// Only the records' samples are breakpoints; functions must be smooth.
struct Ground {
    Record ah_rec, av_rec;
    std::function<double(double)> ah_fn, av_fn;
    double ah(double t) const { return ah_rec.at(t) + (ah_fn ? ah_fn(t) : 0.0); }
    double av(double t) const { return av_rec.at(t) + (av_fn ? av_fn(t) : 0.0); }
    std::vector<double> breakpoints() const {
        std::vector<double> b = ah_rec.t;
        b.insert(b.end(), av_rec.t.begin(), av_rec.t.end());
        std::sort(b.begin(), b.end());
        b.erase(std::unique(b.begin(), b.end()), b.end());
        return b;
    }
};

using Phases = std::vector<int>;  // per joint: 0 closed, +1 / -1 rocking about corner s

// ---------------------------------------------------------------- kinematics
struct PointKin {
    double m = 0.0;
    int seg = 0;
    double x = 0.0, y = 0.0;     // position, ground frame
    std::vector<double> Jx, Jy;  // dp/dq (one entry per open coordinate)
    double bx = 0.0, by = 0.0;   // J' q' (acceleration at q'' = 0)
};

struct Kin {
    int n = 0;                      // number of open joints
    std::vector<int> idx;           // joint -> coordinate index, -1 if closed
    std::vector<int> joint_of;      // coordinate index -> joint
    std::vector<double> Phi;        // ccw angle of segment j = -sum_{k<=j} theta_k
    std::vector<double> Om;         // ccw angular velocity of segment j
    std::vector<std::array<double, 2>> cor;   // current position of joint j's reference corner
    std::vector<std::array<double, 2>> corb;  // its bias acceleration
    std::vector<std::array<double, 2>> tr;    // translation: p = R(Phi_j) p_rest + tr_j
    std::vector<PointKin> pts;      // mass points (slab first, then listed masses), by segment
};

inline void check_inputs(const Chain& c, const Phases& ph, const std::vector<double>& q) {
    if (c.seg.empty()) throw std::invalid_argument("chainref: no segments");
    if (ph.size() != c.seg.size()) throw std::invalid_argument("chainref: phases size != segments");
    std::size_t n = 0;
    for (int s : ph) {
        if (s != 0 && s != 1 && s != -1) throw std::invalid_argument("chainref: phase must be 0, +1, -1");
        if (s != 0) ++n;
    }
    if (q.size() != n) throw std::invalid_argument("chainref: q size != number of open joints");
}

// A point of segment j given by its rest coordinates (xr, yr).
inline PointKin point_on(const Kin& K, int j, double xr, double yr, double m) {
    PointKin P;
    P.m = m;
    P.seg = j;
    const double c = std::cos(K.Phi[j]), s = std::sin(K.Phi[j]);
    P.x = c * xr - s * yr + K.tr[j][0];
    P.y = s * xr + c * yr + K.tr[j][1];
    P.Jx.assign(K.n, 0.0);
    P.Jy.assign(K.n, 0.0);
    for (int k = 0; k <= j; ++k) {
        int i = K.idx[k];
        if (i < 0) continue;
        P.Jx[i] = P.y - K.cor[k][1];
        P.Jy[i] = -(P.x - K.cor[k][0]);
    }
    const double w2 = K.Om[j] * K.Om[j];
    P.bx = K.corb[j][0] - w2 * (P.x - K.cor[j][0]);
    P.by = K.corb[j][1] - w2 * (P.y - K.cor[j][1]);
    return P;
}

inline Kin kinematics(const Chain& C, const Phases& ph, const std::vector<double>& q,
                      const std::vector<double>& qd) {
    check_inputs(C, ph, q);
    if (qd.size() != q.size()) throw std::invalid_argument("chainref: qd size != q size");
    const int nj = static_cast<int>(C.seg.size());
    Kin K;
    K.idx.assign(nj, -1);
    for (int j = 0; j < nj; ++j)
        if (ph[j] != 0) {
            K.idx[j] = K.n++;
            K.joint_of.push_back(j);
        }
    K.Phi.resize(nj);
    K.Om.resize(nj);
    K.cor.resize(nj);
    K.corb.resize(nj);
    K.tr.resize(nj);
    double Phi_prev = 0.0, Om_prev = 0.0;
    std::array<double, 2> tr_prev{0.0, 0.0};
    for (int j = 0; j < nj; ++j) {
        const double xr = ph[j] != 0 ? ph[j] * C.seg[j].B : 0.0, yr = C.seg[j].h;
        // current position of the corner: a point of segment j-1 (or of the ground)
        const double cp = std::cos(Phi_prev), sp = std::sin(Phi_prev);
        K.cor[j] = {cp * xr - sp * yr + tr_prev[0], sp * xr + cp * yr + tr_prev[1]};
        if (j == 0) {
            K.corb[0] = {0.0, 0.0};
        } else {
            const double w2 = Om_prev * Om_prev;
            K.corb[j] = {K.corb[j - 1][0] - w2 * (K.cor[j][0] - K.cor[j - 1][0]),
                         K.corb[j - 1][1] - w2 * (K.cor[j][1] - K.cor[j - 1][1])};
        }
        const double th = K.idx[j] >= 0 ? q[K.idx[j]] : 0.0;
        const double thd = K.idx[j] >= 0 ? qd[K.idx[j]] : 0.0;
        K.Phi[j] = Phi_prev - th;
        K.Om[j] = Om_prev - thd;
        const double c = std::cos(K.Phi[j]), s = std::sin(K.Phi[j]);
        K.tr[j] = {K.cor[j][0] - (c * xr - s * yr), K.cor[j][1] - (s * xr + c * yr)};
        Phi_prev = K.Phi[j];
        Om_prev = K.Om[j];
        tr_prev = K.tr[j];
    }
    for (int j = 0; j < nj; ++j) {
        K.pts.push_back(point_on(K, j, 0.0, C.seg[j].h, C.seg[j].m0));
        for (auto [y, m] : C.seg[j].masses) K.pts.push_back(point_on(K, j, 0.0, y, m));
    }
    return K;
}

// ---------------------------------------------------------------- tendon
struct TendonState {
    double e = 0.0, edot = 0.0, F = 0.0, U = 0.0;
    std::array<double, 2> dir{0.0, 1.0};  // unit vector ground anchor -> top anchor
    PointKin top;
};

inline double tendon_force(const Tendon& T, double e) { return std::max(0.0, T.P0 + T.k * e); }

// U(e) = int_0^e max(0, P0 + k s) ds
inline double tendon_energy(const Tendon& T, double e) {
    auto prim = [&](double x) { return T.P0 * x + 0.5 * T.k * x * x; };
    if (T.k > 0.0) {
        const double es = -T.P0 / T.k;  // where the force reaches zero
        if (es <= 0.0) return e >= es ? prim(e) : prim(es);  // P0 >= 0: slack below es
        return e >= es ? prim(e) - prim(es) : 0.0;           // P0 < 0: slack until es
    }
    return T.P0 > 0.0 ? T.P0 * e : 0.0;
}

inline TendonState tendon_state(const Chain& C, const Kin& K, const std::vector<double>& qd) {
    TendonState S;
    const int top = static_cast<int>(C.seg.size()) - 1;
    S.top = point_on(K, top, C.tendon.x_t, C.H_top, 0.0);
    const double dx = S.top.x - C.tendon.x_t, dy = S.top.y - 0.0;
    const double L = std::hypot(dx, dy);
    S.dir = {dx / L, dy / L};
    S.e = L - C.H_top;
    double vx = 0.0, vy = 0.0;
    for (int i = 0; i < K.n; ++i) {
        vx += S.top.Jx[i] * qd[i];
        vy += S.top.Jy[i] * qd[i];
    }
    S.edot = S.dir[0] * vx + S.dir[1] * vy;
    S.F = tendon_force(C.tendon, S.e);
    S.U = tendon_energy(C.tendon, S.e);
    return S;
}

// ---------------------------------------------------------------- tendons between segments
struct SegmentTendonState {
    double e = 0.0, F = 0.0, U = 0.0;
    std::array<double, 2> dir{0.0, 1.0};  // unit vector lower anchor -> upper anchor
    PointKin low, up;                      // the anchors (the ground's: zero Jacobian)
};

inline SegmentTendonState segment_tendon_state(const Chain& C, const Kin& K, const SegmentTendon& T) {
    SegmentTendonState S;
    const double y_low = T.from < 0 ? 0.0 : C.seg[T.from].h;
    if (T.from < 0) {
        S.low.x = T.x;
        S.low.y = 0.0;
        S.low.Jx.assign(K.n, 0.0);
        S.low.Jy.assign(K.n, 0.0);
    } else {
        S.low = point_on(K, T.from, T.x, y_low, 0.0);
    }
    S.up = point_on(K, T.to, T.x, T.y_top, 0.0);
    const double dx = S.up.x - S.low.x, dy = S.up.y - S.low.y, L = std::hypot(dx, dy);
    S.dir = {dx / L, dy / L};
    S.e = L - (T.y_top - y_low);
    Tendon as_law{true, T.x, T.P0, T.k};
    S.F = tendon_force(as_law, S.e);
    S.U = tendon_energy(as_law, S.e);
    return S;
}

// ---------------------------------------------------------------- devices across the base joint
struct BaseDeviceState {
    bool acting = false;
    double e = 0.0, dedth = 0.0;   // m, m/rad (theta_0 signed)
    double F = 0.0;                // N
    double px = 0.0, py = 0.0;     // where it pulls on the base (ground frame), m
    double fx = 0.0, fy = -1.0;    // unit direction of its pull on the base
};

inline double base_device_force(const BaseDevice& d, double e, double z) {
    if (d.law == Law::elastic) return std::max(0.0, d.P0 + d.k * e);
    return d.k * d.eps * e + d.k * (1 - d.eps) * d.dy * z;
}

inline double base_device_rate(const BaseDevice& d, double edot, double z) {
    const double az = std::fabs(z);
    return (edot - d.alpha * std::fabs(edot) * z * std::pow(az, d.nbw - 1) - d.beta * edot * std::pow(az, d.nbw)) / d.dy;
}

// Device d with state z, joint 0 in phase s0 at theta_0 = th.
inline BaseDeviceState base_device_state(const Chain& C, const BaseDevice& d, int s0, double th, double z) {
    BaseDeviceState S;
    S.px = d.x;
    S.py = 0.0;
    const double B = C.seg[0].B, l = s0 != 0 ? B - s0 * d.x : 0.0;
    if (s0 == 0 || l <= 0.0) {  // at rest: its force at rest pulls the anchor down
        S.F = base_device_force(d, 0.0, z);
        return S;
    }
    S.acting = true;
    const double a = std::fabs(th), c = std::cos(th), sn = std::sin(th);
    double de = 0.0;  // de/d|theta_0|
    // A rest point (x, y) of the base, clockwise by th about the corner (s0 B, 0).
    auto turned = [&](double y, double& X, double& Y) {
        const double rx = d.x - s0 * B;
        X = s0 * B + rx * c + y * sn;
        Y = -rx * sn + y * c;
    };
    if (d.kin == BaseKinematics::chord) {
        S.e = 2 * l * std::sin(0.5 * a);
        de = l * std::cos(0.5 * a);
        turned(0.0, S.px, S.py);
        // the anchor has moved toward the corner: the chord back to (x, 0) leans |th|/2 from the vertical
        S.fx = -s0 * std::sin(0.5 * a);
        S.fy = -std::cos(0.5 * a);
    } else {
        const double A = d.L + l * std::sin(a), Bv = l * (1 - std::cos(a)), r = std::hypot(A, Bv);
        S.e = r - d.L;
        de = (A * l * std::cos(a) + Bv * l * std::sin(a)) / r;
        turned(d.L, S.px, S.py);
        S.fx = -(S.px - d.x) / r;
        S.fy = -S.py / r;
    }
    S.dedth = s0 * de;
    S.F = base_device_force(d, S.e, z);
    return S;
}

inline double z_at(const std::vector<double>& z, std::size_t k) { return k < z.size() ? z[k] : 0.0; }

// ---------------------------------------------------------------- dynamics
struct Dyn {
    int n = 0;
    std::vector<double> M;  // n x n, row-major
    std::vector<double> Q;  // n
};

inline Dyn mass_and_forces(const Chain& C, const Phases& ph, const std::vector<double>& q,
                           const std::vector<double>& qd, double t, const Ground& G,
                           const std::vector<double>& z = {}) {
    Kin K = kinematics(C, ph, q, qd);
    Dyn D;
    D.n = K.n;
    const int n = K.n;
    D.M.assign(n * n, 0.0);
    D.Q.assign(n, 0.0);
    const double fx = -G.ah(t), fy = -(C.g + G.av(t));  // force per unit mass, ground frame
    for (const auto& P : K.pts) {
        for (int a = 0; a < n; ++a) {
            for (int b = 0; b < n; ++b) D.M[a * n + b] += P.m * (P.Jx[a] * P.Jx[b] + P.Jy[a] * P.Jy[b]);
            D.Q[a] += P.m * (P.Jx[a] * (fx - P.bx) + P.Jy[a] * (fy - P.by));
        }
    }
    if (C.tendon.present) {
        TendonState S = tendon_state(C, K, qd);
        for (int a = 0; a < n; ++a) D.Q[a] -= S.F * (S.dir[0] * S.top.Jx[a] + S.dir[1] * S.top.Jy[a]);
    }
    for (const JointDevice& dv : C.devices) {
        int a = -1;  // theta_j's place among the open joints' coordinates
        for (int i = 0; i < n; ++i)
            if (K.joint_of[i] == dv.joint) a = i;
        if (a < 0) continue;  // closed: no elongation
        const int s = ph[dv.joint];
        const double l = C.seg[dv.joint].B - s * dv.x, th = q[a];
        const double e = 2.0 * l * std::sin(s * th / 2.0);
        const double de = s * l * std::cos(th / 2.0);
        D.Q[a] -= (dv.k * e + dv.c * de * qd[a]) * de;
    }
    for (const SegmentTendon& T : C.tendons) {
        const SegmentTendonState S = segment_tendon_state(C, K, T);
        for (int a = 0; a < n; ++a)
            D.Q[a] -= S.F * (S.dir[0] * (S.up.Jx[a] - S.low.Jx[a]) + S.dir[1] * (S.up.Jy[a] - S.low.Jy[a]));
    }
    if (ph[0] != 0)
        for (std::size_t k = 0; k < C.base.size(); ++k) {
            const BaseDeviceState S = base_device_state(C, C.base[k], ph[0], q[K.idx[0]], z_at(z, k));
            if (S.acting) D.Q[K.idx[0]] -= S.F * S.dedth;
        }
    return D;
}

inline std::vector<double> solve(std::vector<double> A, std::vector<double> b) {
    const int n = static_cast<int>(b.size());
    if (n == 0) return {};
    gsl_matrix_view Am = gsl_matrix_view_array(A.data(), n, n);
    gsl_vector_view bv = gsl_vector_view_array(b.data(), n);
    std::vector<double> x(n);
    gsl_vector_view xv = gsl_vector_view_array(x.data(), n);
    gsl_permutation* p = gsl_permutation_alloc(n);
    int sg = 0;
    gsl_linalg_LU_decomp(&Am.matrix, p, &sg);
    gsl_linalg_LU_solve(&Am.matrix, p, &bv.vector, &xv.vector);
    gsl_permutation_free(p);
    return x;
}

// q'' (rad/s^2) of the open joints, for the given phases, state and time.
inline std::vector<double> accelerations(const Chain& C, const Phases& ph, const std::vector<double>& q,
                                         const std::vector<double>& qd, double t, const Ground& G,
                                         const std::vector<double>& z = {}) {
    Dyn D = mass_and_forces(C, ph, q, qd, t, G, z);
    return solve(D.M, D.Q);
}

// Kinetic (relative to the ground frame) + potential sum m g y (g = C.g, constant,
// as MODEL.md 14 keeps it) + the tendon's stored energy. J.
inline double energy(const Chain& C, const Phases& ph, const std::vector<double>& q,
                     const std::vector<double>& qd) {
    Kin K = kinematics(C, ph, q, qd);
    double E = 0.0;
    for (const auto& P : K.pts) {
        double vx = 0.0, vy = 0.0;
        for (int i = 0; i < K.n; ++i) {
            vx += P.Jx[i] * qd[i];
            vy += P.Jy[i] * qd[i];
        }
        E += 0.5 * P.m * (vx * vx + vy * vy) + P.m * C.g * P.y;
    }
    if (C.tendon.present) E += tendon_state(C, K, qd).U;
    for (const SegmentTendon& T : C.tendons) E += segment_tendon_state(C, K, T).U;
    if (ph[0] != 0)  // the elastic base devices' stored energy (a Bouc-Wen device's is not counted)
        for (const BaseDevice& d : C.base) {
            if (d.law != Law::elastic) continue;
            const BaseDeviceState S = base_device_state(C, d, ph[0], q[K.idx[0]], 0.0);
            if (S.acting) E += tendon_energy(Tendon{true, d.x, d.P0, d.k}, S.e);
        }
    return E;
}

// ---------------------------------------------------------------- integration
struct IntegOpts {
    double rtol = 1e-12;   // relative tolerance of rk8pd's step control
    double atol = 1e-14;   // absolute tolerance (rad, rad/s)
    double t_loc = 1e-13;  // bisection stops when the bracket is shorter (s)
    double h0 = 1e-5;      // first trial step (s)
};

struct ImpactResult {
    double t = 0.0;             // impact time, or t_end
    std::vector<double> q, qd;  // state at t (open coordinates of the given phases)
    int joint = -1;             // joint whose theta returned to 0; -1 if t_end was reached
};

namespace detail {
struct OdeCtx {
    const Chain* C;
    const Phases* ph;
    const Ground* G;
    int n;
};
inline int rhs(double t, const double y[], double dydt[], void* params) {
    auto* X = static_cast<OdeCtx*>(params);
    const int n = X->n;
    std::vector<double> q(y, y + n), qd(y + n, y + 2 * n);
    std::vector<double> qdd = accelerations(*X->C, *X->ph, q, qd, t, *X->G);
    for (int i = 0; i < n; ++i) {
        dydt[i] = qd[i];
        dydt[n + i] = qdd[i];
    }
    return GSL_SUCCESS;
}
// min over open joints of s_j theta_j, and the joint attaining it
inline std::pair<double, int> gap(const Kin& K0, const Phases& ph, const double* y) {
    double f = std::numeric_limits<double>::infinity();
    int jj = -1;
    for (int i = 0; i < K0.n; ++i) {
        int j = K0.joint_of[i];
        double v = ph[j] * y[i];
        if (v < f) {
            f = v;
            jj = j;
        }
    }
    return {f, jj};
}
}  // namespace detail

// Integrate from (t0, q, qd) with the phases held until an open theta_j returns to
// 0 (s_j theta_j goes from >= 0 to < 0), or t_end. The crossing is located by
// bisection (re-integrating from the last accepted step) to opts.t_loc; the state
// returned is the one at the bracket's early end (s_j theta_j >= 0, |theta_j| ~ rate*t_loc).
// The record's samples are breakpoints: each sample interval is integrated on its own.
// A joint released at theta_j = 0 that immediately goes the wrong way is reported
// as an impact at t0.
inline ImpactResult first_impact(const Chain& C, const Phases& ph, std::vector<double> q, std::vector<double> qd,
                                 double t0, double t_end, const Ground& G, IntegOpts o = {}) {
    check_inputs(C, ph, q);
    Kin K0 = kinematics(C, ph, q, qd);
    const int n = K0.n;
    ImpactResult R;
    if (n == 0) {
        R.t = t_end;
        R.q = q;
        R.qd = qd;
        return R;
    }
    detail::OdeCtx ctx{&C, &ph, &G, n};
    gsl_odeiv2_system sys{detail::rhs, nullptr, static_cast<std::size_t>(2 * n), &ctx};
    gsl_odeiv2_step* st = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, 2 * n);
    gsl_odeiv2_control* ct = gsl_odeiv2_control_y_new(o.atol, o.rtol);
    gsl_odeiv2_evolve* ev = gsl_odeiv2_evolve_alloc(2 * n);
    std::vector<double> y(2 * n), yprev(2 * n);
    for (int i = 0; i < n; ++i) {
        y[i] = q[i];
        y[n + i] = qd[i];
    }
    // breakpoints strictly inside (t0, t_end), then t_end
    std::vector<double> stops;
    for (double b : G.breakpoints())
        if (b > t0 && b < t_end) stops.push_back(b);
    stops.push_back(t_end);

    auto integrate_to = [&](double ta, std::vector<double> ya, double tb) {
        gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd,
                                                             std::min(o.h0, tb - ta), o.atol, o.rtol);
        double tt = ta;
        int status = gsl_odeiv2_driver_apply(d, &tt, tb, ya.data());
        gsl_odeiv2_driver_free(d);
        if (status != GSL_SUCCESS) throw std::runtime_error("chainref: driver failed");
        return ya;
    };

    double t = t0, h = o.h0;
    bool done = false;
    for (double t1 : stops) {
        if (done) break;
        gsl_odeiv2_evolve_reset(ev);
        while (t < t1) {
            const double tprev = t;
            yprev = y;
            int status = gsl_odeiv2_evolve_apply(ev, ct, st, &sys, &t, t1, &h, y.data());
            if (status != GSL_SUCCESS) throw std::runtime_error("chainref: evolve failed");
            auto [f, jj] = detail::gap(K0, ph, y.data());
            if (f < 0.0) {
                // bisection on [lo, hi], re-integrating from lo
                double lo = tprev, hi = t;
                std::vector<double> ylo = yprev;
                while (hi - lo > o.t_loc) {
                    const double mid = 0.5 * (lo + hi);
                    if (mid <= lo || mid >= hi) break;
                    std::vector<double> ym = integrate_to(lo, ylo, mid);
                    auto [fm, jm] = detail::gap(K0, ph, ym.data());
                    if (fm < 0.0) {
                        hi = mid;
                        jj = jm;
                    } else {
                        lo = mid;
                        ylo = ym;
                    }
                }
                R.t = lo;
                R.q.assign(ylo.begin(), ylo.begin() + n);
                R.qd.assign(ylo.begin() + n, ylo.end());
                R.joint = jj;
                done = true;
                break;
            }
        }
        if (!done) t = t1;
    }
    gsl_odeiv2_evolve_free(ev);
    gsl_odeiv2_control_free(ct);
    gsl_odeiv2_step_free(st);
    if (!done) {
        R.t = t_end;
        R.q.assign(y.begin(), y.begin() + n);
        R.qd.assign(y.begin() + n, y.end());
    }
    return R;
}

// ---------------------------------------------------------------- impact
struct PostImpact {
    std::vector<double> q, qd;  // open coordinates of the post-impact phases
};

// Map a configuration between phase sets. Positions are continuous at an impact:
// joints open in both with the same corner keep theta; every other post-open
// joint starts at theta = 0 (a joint that changes corner or opens can only do so
// at theta = 0). The impacting joint j is snapped to theta_j = 0.
inline std::vector<double> map_coordinates(const Phases& pre, const std::vector<double>& q_pre, int j,
                                           const Phases& post) {
    std::vector<double> th(pre.size(), 0.0);
    int i = 0;
    for (std::size_t k = 0; k < pre.size(); ++k)
        if (pre[k] != 0) th[k] = q_pre[i++];
    th[j] = 0.0;
    std::vector<double> q;
    for (std::size_t k = 0; k < post.size(); ++k)
        if (post[k] != 0) q.push_back(post[k] == pre[k] ? th[k] : 0.0);
    return q;
}

// MODEL.md 15's impact law at joint j: p_k = sum_i m_i v_i^- . dp_i/dq_k^+ is
// conserved for every post-impact coordinate k (derivatives with the post-impact
// kinematics, i.e. about the post-impact corners), so M^+ q'^+ = J^+T M v^-.
// v^- is computed with the pre-impact kinematics at theta_j = 0 (snapped).
// Returns the post-impact coordinates and rates (rad, rad/s) for ph_post.
inline PostImpact momentum_impact(const Chain& C, const Phases& ph_pre, const std::vector<double>& q_pre,
                                  const std::vector<double>& qd_pre, int j, const Phases& ph_post) {
    check_inputs(C, ph_pre, q_pre);
    if (ph_pre[j] == 0) throw std::invalid_argument("chainref: impacting joint is not open");
    std::vector<double> qs = map_coordinates(ph_pre, q_pre, j, ph_pre);  // snap theta_j = 0
    Kin Km = kinematics(C, ph_pre, qs, qd_pre);
    PostImpact P;
    P.q = map_coordinates(ph_pre, q_pre, j, ph_post);
    Kin Kp = kinematics(C, ph_post, P.q, std::vector<double>(P.q.size(), 0.0));
    const int n = Kp.n;
    std::vector<double> M(n * n, 0.0), p(n, 0.0);
    for (std::size_t a = 0; a < Km.pts.size(); ++a) {
        const auto& A = Km.pts[a];
        const auto& Bp = Kp.pts[a];
        double vx = 0.0, vy = 0.0;
        for (int i = 0; i < Km.n; ++i) {
            vx += A.Jx[i] * qd_pre[i];
            vy += A.Jy[i] * qd_pre[i];
        }
        for (int k = 0; k < n; ++k) {
            p[k] += A.m * (vx * Bp.Jx[k] + vy * Bp.Jy[k]);
            for (int l = 0; l < n; ++l) M[k * n + l] += A.m * (Bp.Jx[k] * Bp.Jx[l] + Bp.Jy[k] * Bp.Jy[l]);
        }
    }
    P.qd = solve(M, p);
    return P;
}

// Impulses transmitted through each joint at an impact (Newton-Euler on the parts
// above each joint: impulse = sum m (v+ - v-); no finite force contributes).
// Same frame and sign conventions as closed_joint_reactions (N s, N s, N m s): the
// impulse resultant of joint k lies at x_r = M/N along its face. Use: at the
// impacting joint it must sit at the new corner (M = -s B N, N > 0); at an open
// joint at its corner; at a closed joint N >= 0 and |M| <= N B, or that joint
// needs a tensile impulse and must open instead (MODEL.md 15's impact-induced uplift).
inline std::vector<std::array<double, 3>> impact_impulses(const Chain& C, const Phases& ph_pre,
                                                          const std::vector<double>& q_pre,
                                                          const std::vector<double>& qd_pre, int j,
                                                          const Phases& ph_post, const PostImpact& P) {
    std::vector<double> qs = map_coordinates(ph_pre, q_pre, j, ph_pre);
    Kin Km = kinematics(C, ph_pre, qs, qd_pre);
    Kin Kp = kinematics(C, ph_post, P.q, P.qd);
    const int nj = static_cast<int>(C.seg.size());
    std::vector<std::array<double, 3>> out(nj);
    for (int k = 0; k < nj; ++k) {
        double Ox = 0.0, Oy = C.seg[k].h, Phi = 0.0;
        if (k > 0) {
            PointKin O = point_on(Kp, k - 1, 0.0, C.seg[k].h, 0.0);
            Ox = O.x;
            Oy = O.y;
            Phi = Kp.Phi[k - 1];
        }
        double Ix = 0.0, Iy = 0.0, Mo = 0.0;
        for (std::size_t a = 0; a < Kp.pts.size(); ++a) {
            const auto& A = Km.pts[a];
            const auto& Bp = Kp.pts[a];
            if (Bp.seg < k) continue;
            double dvx = 0.0, dvy = 0.0;
            for (int i = 0; i < Kp.n; ++i) {
                dvx += Bp.Jx[i] * P.qd[i];
                dvy += Bp.Jy[i] * P.qd[i];
            }
            for (int i = 0; i < Km.n; ++i) {
                dvx -= A.Jx[i] * qd_pre[i];
                dvy -= A.Jy[i] * qd_pre[i];
            }
            Ix += Bp.m * dvx;
            Iy += Bp.m * dvy;
            Mo += (Bp.x - Ox) * Bp.m * dvy - (Bp.y - Oy) * Bp.m * dvx;
        }
        const double c = std::cos(Phi), s = std::sin(Phi);
        out[k] = {-s * Ix + c * Iy, c * Ix + s * Iy, Mo};  // {N, V, M}
    }
    return out;
}

// ---------------------------------------------------------------- joint reactions
// Contact force that joint j's face (the top of segment j-1, or the ground) exerts
// on everything above it, in the face's own frame (e_t along the face, rotated
// with segment j-1; e_n its upward normal):
//   N = normal component (N > 0 compression), V = tangential component (+ along e_t),
//   M = moment of the contact force about the face centre, ccw positive, i.e.
//       M = N * x_r with x_r the resultant's position along the face.
// The resultant reaches corner s when s M = N B_j (uplift about s), so for an open
// joint M = s_j B_j N_j. These are the CONTACT forces: the tendon is a separate
// force on the body above (it crosses the cut), so with prestress P0 the contact
// N includes P0; s M >= N B is then the same as MODEL.md 15's
// "s M' >= N' B + P0 l_s" with N', M' the resultants excluding the tendon.
// Route: Newton-Euler on the parts above each joint in the ground frame, with the
// accelerations from accelerations(): sum m (a - f/m) = R + T_tendon, and the
// same for moments about the face centre.
struct Reaction {
    double N = 0.0, V = 0.0, M = 0.0;  // N, N, N m
};

inline std::vector<Reaction> closed_joint_reactions(const Chain& C, const Phases& ph, const std::vector<double>& q,
                                                    const std::vector<double>& qd, double t, const Ground& G,
                                                    const std::vector<double>& z = {}) {
    std::vector<double> qdd = accelerations(C, ph, q, qd, t, G, z);
    Kin K = kinematics(C, ph, q, qd);
    const int nj = static_cast<int>(C.seg.size());
    const double fx = -G.ah(t), fy = -(C.g + G.av(t));
    TendonState S;
    if (C.tendon.present) S = tendon_state(C, K, qd);
    const double Tx = -S.F * S.dir[0], Ty = -S.F * S.dir[1];  // tendon force on the top anchor
    std::vector<Reaction> out(nj);
    for (int j = 0; j < nj; ++j) {
        // face centre O_j and frame: rest point (0, h_j) of segment j-1 (ground for j = 0)
        double Ox = 0.0, Oy = C.seg[j].h, Phi = 0.0;
        if (j > 0) {
            PointKin O = point_on(K, j - 1, 0.0, C.seg[j].h, 0.0);
            Ox = O.x;
            Oy = O.y;
            Phi = K.Phi[j - 1];
        }
        double Rx = 0.0, Ry = 0.0, Mo = 0.0;
        for (const auto& P : K.pts) {
            if (P.seg < j) continue;
            double ax = P.bx, ay = P.by;
            for (int i = 0; i < K.n; ++i) {
                ax += P.Jx[i] * qdd[i];
                ay += P.Jy[i] * qdd[i];
            }
            const double Fx = P.m * (ax - fx), Fy = P.m * (ay - fy);  // = sum of external forces on m
            Rx += Fx;
            Ry += Fy;
            Mo += (P.x - Ox) * Fy - (P.y - Oy) * Fx;
        }
        if (C.tendon.present) {
            Rx -= Tx;
            Ry -= Ty;
            Mo -= (S.top.x - Ox) * Ty - (S.top.y - Oy) * Tx;
        }
        // tendons between segments: external to the part above joint j when they cross it
        for (const SegmentTendon& T : C.tendons) {
            if (!(T.from < j && j <= T.to)) continue;
            const SegmentTendonState ST = segment_tendon_state(C, K, T);
            const double fx_t = -ST.F * ST.dir[0], fy_t = -ST.F * ST.dir[1];  // on the upper anchor
            Rx -= fx_t;
            Ry -= fy_t;
            Mo -= (ST.up.x - Ox) * fy_t - (ST.up.y - Oy) * fx_t;
        }
        // devices across the base joint: external to everything above the ground
        if (j == 0)
            for (std::size_t k = 0; k < C.base.size(); ++k) {
                const BaseDeviceState B = base_device_state(C, C.base[k], ph[0], ph[0] != 0 ? q[K.idx[0]] : 0.0, z_at(z, k));
                const double fx_b = B.F * B.fx, fy_b = B.F * B.fy;
                Rx -= fx_b;
                Ry -= fy_b;
                Mo -= (B.px - Ox) * fy_b - (B.py - Oy) * fx_b;
            }
        const double c = std::cos(Phi), s = std::sin(Phi);
        out[j].V = c * Rx + s * Ry;
        out[j].N = -s * Rx + c * Ry;
        out[j].M = Mo;
    }
    return out;
}

// ---------------------------------------------------------------- phases with devices and uplift
// A run with the phases held from (t0, q, q', z) to the first event: an open
// joint's theta returning to 0 (impact), or a closed joint lifting about a
// corner s, when both of MODEL.md 15's conditions hold:
//   s M_j - N_j B_j >= 0 (closed_joint_reactions, devices included), and
//   s theta_j'' > 0 were joint j open about s at theta_j = theta_j' = 0.
// y = [q, q', z]; z (one per base device) changes only while joint 0 rocks.
// Events are located by bisection to opts.t_loc; the state returned is at the
// bracket's early end for an impact, its late end (where both uplift
// conditions hold) for an uplift. A joint that starts the phase at theta = 0
// (just opened) arms its impact once s theta > 0: at its uplift instant its
// s theta'' is zero to round-off. With no open joint nothing moves (rigid segments): the
// guards vary with the record alone and are sampled every 1 ms between its samples.
// out_times (sorted): the state is recorded at those in [t0, event).
struct PhaseState {
    double t = 0.0;
    std::vector<double> q, qd, z;
};
struct PhaseEvent {
    enum class Kind { impact, uplift, end } kind = Kind::end;
    double t = 0.0;
    int joint = -1;  // the joint that strikes or lifts
    int side = 0;    // an uplift's corner
    std::vector<double> q, qd, z;
    std::vector<PhaseState> out;  // the state at each of the out_times passed before the event
};

// Joint j (closed in ph) opened about s at theta_j = theta_j' = 0: its s theta_j''.
inline double opening_acceleration(const Chain& C, const Phases& ph, const std::vector<double>& q,
                                   const std::vector<double>& qd, const std::vector<double>& z, double t,
                                   const Ground& G, int j, int s) {
    Phases p2 = ph;
    p2[j] = s;
    std::vector<double> q2, qd2;
    int i = 0, at = -1;
    for (std::size_t k = 0; k < ph.size(); ++k) {
        if (static_cast<int>(k) == j) {
            at = static_cast<int>(q2.size());
            q2.push_back(0.0);
            qd2.push_back(0.0);
        } else if (ph[k] != 0) {
            q2.push_back(q[i]);
            qd2.push_back(qd[i]);
            ++i;
        }
    }
    return s * accelerations(C, p2, q2, qd2, t, G, z)[at];
}

namespace detail {
struct PhaseCtx {
    const Chain* C;
    const Phases* ph;
    const Ground* G;
    int n;
    int nz;
};
inline int phase_rhs(double t, const double y[], double dydt[], void* params) {
    auto* X = static_cast<PhaseCtx*>(params);
    const int n = X->n, nz = X->nz;
    std::vector<double> q(y, y + n), qd(y + n, y + 2 * n), z(y + 2 * n, y + 2 * n + nz);
    const std::vector<double> qdd = accelerations(*X->C, *X->ph, q, qd, t, *X->G, z);
    for (int i = 0; i < n; ++i) {
        dydt[i] = qd[i];
        dydt[n + i] = qdd[i];
    }
    const Phases& ph = *X->ph;
    for (int k = 0; k < nz; ++k) {
        dydt[2 * n + k] = 0.0;
        const BaseDevice& d = X->C->base[k];
        if (ph[0] == 0 || d.law != Law::bouc_wen) continue;
        const BaseDeviceState S = base_device_state(*X->C, d, ph[0], q[0], z[k]);  // theta_0 is q[0] when open
        if (S.acting) dydt[2 * n + k] = base_device_rate(d, S.dedth * qd[0], z[k]);
    }
    return GSL_SUCCESS;
}
}  // namespace detail

inline PhaseEvent run_phase(const Chain& C, const Phases& ph, std::vector<double> q, std::vector<double> qd,
                            std::vector<double> z, double t0, double t_end, const Ground& G, IntegOpts o = {},
                            const std::vector<double>& out_times = {}) {
    check_inputs(C, ph, q);
    const int n = static_cast<int>(q.size()), nz = static_cast<int>(C.base.size());
    z.resize(static_cast<std::size_t>(nz), 0.0);
    const int nj = static_cast<int>(ph.size());
    const std::vector<int> open = [&] {
        std::vector<int> v;
        for (int j = 0; j < nj; ++j)
            if (ph[j] != 0) v.push_back(j);
        return v;
    }();
    auto split = [&](const std::vector<double>& y, std::vector<double>& qq, std::vector<double>& vv,
                     std::vector<double>& zz) {
        qq.assign(y.begin(), y.begin() + n);
        vv.assign(y.begin() + n, y.begin() + 2 * n);
        zz.assign(y.begin() + 2 * n, y.end());
    };
    std::vector<bool> armed(open.size());
    for (std::size_t i = 0; i < open.size(); ++i) armed[i] = ph[open[i]] * q[i] > 0.0;
    // The first event at (t, y): {-1, ...} none, else {joint, side (0 for an impact)}.
    auto events = [&](double t, const std::vector<double>& y) -> std::pair<int, int> {
        std::vector<double> qq, vv, zz;
        split(y, qq, vv, zz);
        for (std::size_t i = 0; i < open.size(); ++i)
            if (armed[i] && ph[open[i]] * qq[i] < 0.0) return {open[i], 0};
        const std::vector<Reaction> R = closed_joint_reactions(C, ph, qq, vv, t, G, zz);
        for (int j = 0; j < nj; ++j) {
            if (ph[j] != 0) continue;
            for (int s : {+1, -1})
                if (s * R[j].M - R[j].N * C.seg[j].B >= 0.0 && opening_acceleration(C, ph, qq, vv, zz, t, G, j, s) > 0.0)
                    return {j, s};
        }
        return {-1, 0};
    };
    detail::PhaseCtx ctx{&C, &ph, &G, n, nz};
    const std::size_t dim = static_cast<std::size_t>(2 * n + nz);
    gsl_odeiv2_system sys{detail::phase_rhs, nullptr, dim, &ctx};
    auto integrate_to = [&](double ta, std::vector<double> ya, double tb) {
        if (n == 0 || tb <= ta) return ya;  // nothing moves, and z rests with joint 0 closed
        gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd,
                                                             std::min(o.h0, tb - ta), o.atol, o.rtol);
        double tt = ta;
        const int status = gsl_odeiv2_driver_apply(d, &tt, tb, ya.data());
        gsl_odeiv2_driver_free(d);
        if (status != GSL_SUCCESS) throw std::runtime_error("chainref: driver failed");
        return ya;
    };
    std::vector<double> y(dim);
    for (int i = 0; i < n; ++i) {
        y[i] = q[i];
        y[n + i] = qd[i];
    }
    for (int k = 0; k < nz; ++k) y[2 * n + k] = z[k];
    PhaseEvent E;
    auto finish = [&](PhaseEvent::Kind kind, double t, const std::vector<double>& yy, std::pair<int, int> ev) {
        E.kind = kind;
        E.t = t;
        E.joint = ev.first;
        E.side = ev.second;
        split(yy, E.q, E.qd, E.z);
        return E;
    };
    {  // a closed joint already past its guards lifts at once
        const auto ev = events(t0, y);
        if (ev.first >= 0 && ev.second != 0) return finish(PhaseEvent::Kind::uplift, t0, y, ev);
    }
    std::vector<double> stops;
    for (double b : G.breakpoints())
        if (b > t0 && b < t_end) stops.push_back(b);
    for (double b : out_times)
        if (b > t0 && b < t_end) stops.push_back(b);
    stops.push_back(t_end);
    std::sort(stops.begin(), stops.end());
    stops.erase(std::unique(stops.begin(), stops.end()), stops.end());
    auto record = [&](double tt, const std::vector<double>& yy) {
        if (!std::binary_search(out_times.begin(), out_times.end(), tt)) return;
        PhaseState S;
        S.t = tt;
        split(yy, S.q, S.qd, S.z);
        E.out.push_back(S);
    };
    record(t0, y);
    gsl_odeiv2_step* st = n > 0 ? gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, dim) : nullptr;
    gsl_odeiv2_control* ct = n > 0 ? gsl_odeiv2_control_y_new(o.atol, o.rtol) : nullptr;
    gsl_odeiv2_evolve* evo = n > 0 ? gsl_odeiv2_evolve_alloc(dim) : nullptr;
    auto cleanup = [&] {
        if (evo) gsl_odeiv2_evolve_free(evo);
        if (ct) gsl_odeiv2_control_free(ct);
        if (st) gsl_odeiv2_step_free(st);
    };
    double t = t0, h = o.h0;
    for (double t1 : stops) {
        if (evo) gsl_odeiv2_evolve_reset(evo);
        while (t < t1) {
            const double tprev = t;
            const std::vector<double> yprev = y;
            if (n > 0) {
                const int status = gsl_odeiv2_evolve_apply(evo, ct, st, &sys, &t, t1, &h, y.data());
                if (status != GSL_SUCCESS) {
                    cleanup();
                    throw std::runtime_error("chainref: evolve failed");
                }
            } else {
                t = std::min(t1, t + 1e-3);
            }
            auto ev = events(t, y);
            if (ev.first < 0) {
                for (std::size_t i = 0; i < open.size(); ++i) armed[i] = armed[i] || ph[open[i]] * y[i] > 0.0;
                continue;
            }
            double lo = tprev, hi = t;
            std::vector<double> ylo = yprev;
            while (hi - lo > o.t_loc) {
                const double mid = 0.5 * (lo + hi);
                if (mid <= lo || mid >= hi) break;
                const std::vector<double> ym = integrate_to(lo, ylo, mid);
                const auto em = events(mid, ym);
                if (em.first >= 0) {
                    hi = mid;
                    ev = em;
                } else {
                    lo = mid;
                    ylo = ym;
                }
            }
            cleanup();
            if (ev.second == 0) return finish(PhaseEvent::Kind::impact, lo, ylo, ev);
            return finish(PhaseEvent::Kind::uplift, hi, integrate_to(lo, ylo, hi), ev);
        }
        record(t1, y);
    }
    cleanup();
    return finish(PhaseEvent::Kind::end, t, y, {-1, 0});
}

}  // namespace chainref
