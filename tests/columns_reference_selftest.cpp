// columns_reference_selftest.cpp -- checks tests/columns_reference.hpp (an
// independent reference for MODEL.md section 16) against the section's closed
// forms and against single-block results of sections 6, 14 and 15.
// Standalone:
//   clang++-19 -std=c++20 -O2 -I/usr/include/doctest columns_reference_selftest.cpp \
//       -lgsl -lgslcblas -o columns_reference_selftest && ./columns_reference_selftest
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_integration.h>

#include <cstdio>

#include "close.hpp"
#include "columns_reference.hpp"

using namespace colref;

namespace {

const double G = 9.81;

// Free rocking from rest at theta0 > 0 to theta = 0 of theta'' = -p2 sin(alpha - theta):
// t = int_0^theta0 dth / sqrt(2 p2 (cos(alpha - theta0) - cos(alpha - th))).
// With th = theta0 - w^2 the integrand is smooth:
// t = int_0^sqrt(theta0) 2 dw / sqrt(2 p2 sin(alpha - theta0 + w^2/2) sinc(w^2/2)).
double quad_impact_time(double alpha, double p2, double theta0) {
    struct P { double a, p2, t0; } par{alpha, p2, theta0};
    gsl_function F;
    F.function = [](double w, void* v) {
        const P& p = *static_cast<P*>(v);
        const double x = 0.5 * w * w;
        const double sinc = (x < 1e-8) ? 1.0 - x * x / 6.0 : std::sin(x) / x;
        return 2.0 / std::sqrt(2.0 * p.p2 * std::sin(p.a - p.t0 + x) * sinc);
    };
    F.params = &par;
    gsl_integration_workspace* ws = gsl_integration_workspace_alloc(1000);
    double res = 0, err = 0;
    gsl_integration_qag(&F, 0.0, std::sqrt(theta0), 0.0, 2e-14, 1000, GSL_INTEG_GAUSS61, ws, &res, &err);
    gsl_integration_workspace_free(ws);
    return res;
}

// An independently written single column (section 6's rigid block, uniform):
// theta'' = -P2 [ (1 + a_v/g) sin(s alpha - theta) + (a_h/g) cos(s alpha - theta) ],
// integrated sample by sample; first crossing of theta = 0 located by bisection.
struct Col { double alpha, P2; const Ground* gm; int seg; };
int col_rhs(double t, const double y[], double f[], void* v) {
    const Col& c = *static_cast<Col*>(v);
    double ah, av; c.gm->eval(c.seg, t, ah, av);
    const int s = y[0] > 0 ? 1 : -1;   // the pivot is fixed before the first impact
    const double ph = s * c.alpha - y[0];
    f[0] = y[1];
    f[1] = -c.P2 * ((1 + av / G) * std::sin(ph) + (ah / G) * std::cos(ph));
    return GSL_SUCCESS;
}
struct ColImpact { double t, thd; };
ColImpact single_column_first_impact(double alpha, double P2, double th0, const Ground& gm, double t_max) {
    Col c{alpha, P2, &gm, 0};
    gsl_odeiv2_system sys{col_rhs, nullptr, 2, &c};
    auto adv = [&](double ta, double tb, const double* ya, double* yb) {
        yb[0] = ya[0]; yb[1] = ya[1];
        if (tb <= ta) return;
        gsl_odeiv2_driver* d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk8pd, 1e-4, 1e-15, 1e-13);
        double t = ta;
        gsl_odeiv2_driver_apply(d, &t, tb, yb);
        gsl_odeiv2_driver_free(d);
    };
    const int s = th0 > 0 ? 1 : -1;
    double t = 0, y[2] = {th0, 0.0};
    const double h = 1e-3;    // probe interval (inside record segments)
    while (t < t_max) {
        double tn = t + h;
        const int k = gm.segment(t);
        if (k + 1 < static_cast<int>(gm.t.size()) && k >= 0) tn = std::min(tn, gm.t[k + 1]);
        if (k < 0 && !gm.t.empty()) tn = std::min(tn, gm.t.front());
        c.seg = gm.segment(0.5 * (t + tn));
        double yn[2];
        adv(t, tn, y, yn);
        if (s * yn[0] < 0) {      // bisection on [t, tn]
            double a = t, b = tn;
            while (b - a > 1e-14) {
                const double m = 0.5 * (a + b);
                double ym[2]; adv(t, m, y, ym);
                (s * ym[0] > 0 ? a : b) = m;
            }
            double ye[2]; adv(t, 0.5 * (a + b), y, ye);
            return {0.5 * (a + b), ye[1]};
        }
        t = tn; y[0] = yn[0]; y[1] = yn[1];
    }
    return {-1, 0};
}

// Shear building: storey stiffness k_i between levels i-1 and i.
Vec shear_K(const Vec& k) {
    const int N = static_cast<int>(k.size());
    Vec K(N * N, 0.0);
    for (int i = 0; i < N; ++i) {
        K[i * N + i] += k[i];
        if (i > 0) { K[i * N + i] += 0; K[(i - 1) * N + (i - 1)] += k[i];
                     K[i * N + i - 1] -= k[i]; K[(i - 1) * N + i] -= k[i]; }
    }
    return K;
}

// Modes of K phi = w^2 diag(m) phi, mass-normalised.
void modes(const Vec& m, const Vec& K, Vec& w, Vec& Phi /* N x N, column j = mode j */) {
    const int N = static_cast<int>(m.size());
    gsl_matrix* A = gsl_matrix_alloc(N, N);
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) gsl_matrix_set(A, i, j, K[i * N + j] / std::sqrt(m[i] * m[j]));
    gsl_vector* ev = gsl_vector_alloc(N);
    gsl_matrix* V = gsl_matrix_alloc(N, N);
    gsl_eigen_symmv_workspace* ws = gsl_eigen_symmv_alloc(N);
    gsl_eigen_symmv(A, ev, V, ws);
    gsl_eigen_symmv_sort(ev, V, GSL_EIGEN_SORT_VAL_ASC);
    w.resize(N); Phi.assign(N * N, 0.0);
    for (int j = 0; j < N; ++j) {
        w[j] = std::sqrt(gsl_vector_get(ev, j));
        for (int i = 0; i < N; ++i) Phi[i * N + j] = gsl_matrix_get(V, i, j) / std::sqrt(m[i]);
    }
    gsl_eigen_symmv_free(ws); gsl_matrix_free(V); gsl_vector_free(ev); gsl_matrix_free(A);
}

// Rayleigh C with ratio zeta on modes 1 and 2.
Vec rayleigh(const Vec& m, const Vec& K, double zeta, double& a0, double& a1) {
    Vec w, Phi; modes(m, K, w, Phi);
    a1 = 2 * zeta / (w[0] + w[1]);
    a0 = a1 * w[0] * w[1];
    const int N = static_cast<int>(m.size());
    Vec C(N * N);
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) C[i * N + j] = a1 * K[i * N + j] + (i == j ? a0 * m[i] : 0.0);
    return C;
}

// Fixed-base structure  M u'' + C u' + K u = -M 1 a_h  (C Rayleigh), solved
// mode by mode, exactly over each linear piece of a_h (first-order hold).
// Returns u at every record sample.
std::vector<Vec> fixed_base_exact(const Vec& m, const Vec& K, double a0, double a1, const Ground& gm) {
    const int N = static_cast<int>(m.size());
    Vec w, Phi; modes(m, K, w, Phi);
    Vec part(N, 0.0);
    for (int j = 0; j < N; ++j) for (int i = 0; i < N; ++i) part[j] += Phi[i * N + j] * m[i];
    const size_t ns = gm.t.size();
    std::vector<Vec> xs(ns, Vec(N, 0.0));
    for (int j = 0; j < N; ++j) {
        const double wj = w[j], c = a0 + a1 * wj * wj, z = c / (2 * wj), wd = wj * std::sqrt(1 - z * z);
        double x = 0, v = 0;
        for (size_t k = 0; k + 1 < ns; ++k) {
            const double D = gm.t[k + 1] - gm.t[k];
            const double p0 = -part[j] * gm.ah[k], p1 = -part[j] * gm.ah[k + 1], kk = (p1 - p0) / D;
            auto xp = [&](double tau) { return (p0 + kk * tau) / (wj * wj) - c * kk / (wj * wj * wj * wj); };
            const double A = x - xp(0), B = (v - kk / (wj * wj) + z * wj * A) / wd;
            const double e = std::exp(-z * wj * D), cs = std::cos(wd * D), sn = std::sin(wd * D);
            const double xn = e * (A * cs + B * sn) + xp(D);
            const double vn = e * (-z * wj * (A * cs + B * sn) + wd * (-A * sn + B * cs)) + kk / (wj * wj);
            x = xn; v = vn;
            xs[k + 1][j] = x;
        }
    }
    std::vector<Vec> us(ns, Vec(N, 0.0));
    for (size_t k = 0; k < ns; ++k)
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j) us[k][i] += Phi[i * N + j] * xs[k][j];
    return us;
}

// A deterministic wiggly record (m/s^2), samples every dt.
Ground wiggly_record(double dt, int n, double pga_h, double pga_v) {
    Ground g;
    unsigned long long s = 12345;
    auto rnd = [&] { s = s * 6364136223846793005ULL + 1442695040888963407ULL; return ((s >> 11) * 0x1.0p-53) * 2 - 1; };
    for (int k = 0; k < n; ++k) {
        const double t = k * dt, env = std::sin(M_PI * t / (dt * (n - 1)));
        g.t.push_back(t);
        g.ah.push_back(pga_h * env * (0.7 * std::sin(2 * M_PI * 2.3 * t) + 0.3 * rnd()));
        g.av.push_back(pga_v * env * (0.6 * std::sin(2 * M_PI * 5.1 * t + 0.4) + 0.4 * rnd()));
    }
    return g;
}

Frame rigid_frame() {
    Frame f;
    f.n = 3; f.b = 0.25; f.h = 2.0; f.mc = 2000; f.mb = 6000;
    f.m = {4000, 3000}; f.H = {1.0, 3.0};
    f.xcol = {-3.0, 0.0, 3.0};
    return f;
}

Frame flexible_frame(bool damped) {
    Frame f;
    f.n = 2; f.b = 0.3; f.h = 2.5; f.mc = 3000; f.mb = 8000;
    f.m = {10000, 8000, 6000}; f.H = {3.0, 6.0, 9.0};
    f.xcol = {-2.0, 2.0};
    f.flexible = true;
    f.K = shear_K({3.0e7, 2.5e7, 2.0e7});
    if (damped) { double a0, a1; f.C = rayleigh(f.m, f.K, 0.05, a0, a1); }
    return f;
}

double rel(double a, double b) { return std::fabs(a - b) / std::max(std::fabs(b), 1e-300); }

}  // namespace

TEST_CASE("closed forms: p-hat and r of section 16 (rigid deck) from free rocking") {
    gsl_set_error_handler_off();
    for (double Hscale : {0.0, 1.0, 10.0}) {
        Frame f = rigid_frame();
        for (double& x : f.H) x *= Hscale;
        for (double frac : {0.2, 0.6, 0.95}) {
            for (int s : {+1, -1}) {
                State st; st.s = s; st.th = s * frac * f.alpha();
                const RunResult r = first_impact(f, st, 0.0, Ground::none());
                REQUIRE(r.outcome == Outcome::Impact);
                const double tq = quad_impact_time(f.alpha(), p2_hat(f), frac * f.alpha());
                CHECK(std::fabs(r.t - tq) < 1e-8);
                CHECK(std::fabs(r.state.th) < 1e-12);
                // energy equation at impact: 1/2 th'^2 = p̂^2 (cos(a - th0) - cos a)
                const double thd = std::sqrt(2 * p2_hat(f) * (std::cos(f.alpha() * (1 - frac)) - std::cos(f.alpha())));
                CHECK(rel(std::fabs(r.state.thd), thd) < 1e-10);
                const ImpactOutcome im = momentum_impact(f, r.state);
                CHECK(im.rocking);
                CHECK(im.post.s == -s);
                CHECK(std::fabs(im.ratio - r_closed(f)) < 1e-10);
                if (Hscale == 1.0 && frac == 0.6 && s == 1)
                    std::printf("rigid deck: t_impact %.15f quad %.15f (diff %.2e); r %.15f closed %.15f (diff %.2e)\n",
                                r.t, tq, r.t - tq, im.ratio, r_closed(f), im.ratio - r_closed(f));
            }
        }
    }
}

TEST_CASE("gamma = 0: the frame is the single uniform column (p, Housner's r)") {
    Frame f; f.n = 2; f.b = 0.3; f.h = 1.7; f.mc = 1500; f.mb = 0; f.xcol = {-1, 1};
    CHECK(f.gamma() == 0.0);
    CHECK(p2_hat(f) == close_to(3 * G / (4 * f.R()), 1e-15));
    const double a = f.alpha();
    State st; st.s = 1; st.th = 0.7 * a;
    const RunResult r = first_impact(f, st, 0.0, Ground::none());
    REQUIRE(r.outcome == Outcome::Impact);
    const double tq = quad_impact_time(a, 3 * G / (4 * f.R()), 0.7 * a);
    CHECK(std::fabs(r.t - tq) < 1e-8);
    const ImpactOutcome im = momentum_impact(f, r.state);
    const double housner = 1 - 1.5 * std::sin(a) * std::sin(a);
    CHECK(std::fabs(im.ratio - housner) < 1e-12);
    // section 15: r = 1 - 2 m B^2 / J_p, with J_p = (4/3) m R^2 for the uniform block
    CHECK(std::fabs(im.ratio - (1 - 2 * f.b * f.b / (4.0 / 3.0 * f.R() * f.R()))) < 1e-12);
    // with no deck, the column tops carry nothing
    const ContactForces cf = top_contact_forces(f, r.state, 0, 0);
    CHECK(std::fabs(cf.Nmin) < 1e-9);
    CHECK(std::fabs(cf.F[0]) < 1e-9);
    std::printf("gamma=0: t %.2e from quadrature, r %.2e from Housner\n", r.t - tq, im.ratio - housner);
}

TEST_CASE("ground motion (a_h, a_v): frame = single column with p-hat, gamma = 0 and > 0 (sections 14, 16)") {
    const Ground gm = wiggly_record(0.01, 301, 0.25 * G, 0.2 * G);
    for (bool deck : {false, true}) {
        Frame f = deck ? rigid_frame() : Frame{};
        if (!deck) { f.n = 2; f.b = 0.25; f.h = 2.0; f.mc = 2000; f.mb = 0; }
        for (double frac : {0.3, -0.5}) {
            State st; st.s = frac > 0 ? 1 : -1; st.th = frac * f.alpha();
            const RunResult r = first_impact(f, st, 0.0, gm);
            REQUIRE(r.outcome == Outcome::Impact);
            const ColImpact c = single_column_first_impact(f.alpha(), p2_hat(f), st.th, gm, 5.0);
            CHECK(std::fabs(r.t - c.t) < 1e-8);
            CHECK(std::fabs(r.state.thd - c.thd) < 1e-8 * std::fabs(c.thd));
            std::printf("record, gamma %.3f, th0 %+.3f: t %.6f, frame - column %.2e s\n",
                        f.gamma(), st.th, r.t, r.t - c.t);
        }
    }
}

TEST_CASE("energy is constant between impacts (no damping, no ground motion)") {
    for (bool flexible : {false, true}) {
        Frame f = flexible ? flexible_frame(false) : rigid_frame();
        State st; st.s = -1; st.th = -0.8 * f.alpha(); st.thd = 0.05;
        if (flexible) { st.u = {0.004, -0.002, 0.006}; st.ud = {0.05, -0.1, 0.02}; }
        const double E0 = energy(f, st).total();
        double worst = 0;
        Options o; o.t_end = 0.3;
        RunResult r = first_impact(f, st, 0.0, Ground::none(), o);
        REQUIRE(r.outcome == Outcome::End);
        worst = std::max(worst, rel(energy(f, r.state).total(), E0));
        RunResult ri = first_impact(f, st, 0.0, Ground::none());
        REQUIRE(ri.outcome == Outcome::Impact);
        const Energy E1 = energy(f, ri.state);
        worst = std::max(worst, rel(E1.total(), E0));
        CHECK(worst < 1e-10);
        // the impact only loses energy
        const ImpactOutcome im = momentum_impact(f, ri.state);
        CHECK(energy(f, im.post).total() < E1.total());
        std::printf("energy drift (%s): %.2e relative; impact loss %.4f of kinetic\n",
                    flexible ? "flexible" : "rigid", worst,
                    (E1.total() - energy(f, im.post).total()) / E1.kinetic);
    }
}

TEST_CASE("flexible deck: the momentum law's closed form (derived for this reference)") {
    Frame f = flexible_frame(false);
    State pre; pre.s = 1; pre.th = 0; pre.thd = -0.3; pre.u = {0.01, 0.02, 0.03}; pre.ud = {0.1, -0.2, 0.3};
    const ImpactOutcome im = momentum_impact(f, pre);
    const double R = f.R(), a = f.alpha(), ms = f.m_structure(), n = f.n, mc = f.mc;
    const double ratio = ((4.0 / 3.0) * n * mc * R * R * (1 - 1.5 * std::sin(a) * std::sin(a))
                          + 4 * f.mb * R * R * std::cos(2 * a) - 4 * ms * f.b * f.b)
                       / ((4.0 / 3.0) * n * mc * R * R + 4 * f.mb * R * R + 4 * ms * f.b * f.b);
    CHECK(std::fabs(im.ratio - ratio) < 1e-12);
    for (int i = 0; i < 3; ++i) {
        CHECK(im.post.u[i] == pre.u[i]);
        CHECK(std::fabs(im.post.ud[i] - (pre.ud[i] + 2 * f.h * (pre.thd - im.post.thd))) < 1e-12);
    }
    // the rigid deck of the same masses gives section 16's r instead
    Frame fr = f; fr.flexible = false; fr.K.clear();
    State pr; pr.s = 1; pr.thd = -0.3;
    CHECK(std::fabs(momentum_impact(fr, pr).ratio - r_closed(fr)) < 1e-12);
    std::printf("impact ratio: flexible deck %.6f, rigid deck (16's r) %.6f\n", im.ratio, r_closed(fr));
    // stopping: a rate ratio that would reverse -> full contact, u'+ = u'- + 2h th'-
    Frame squat = f; squat.b = 2.0; squat.h = 0.5;  // alpha > ~ 55 deg: r < 0
    const ImpactOutcome st = momentum_impact(squat, pre);
    CHECK(!st.rocking);
    CHECK(st.post.s == 0);
    for (int i = 0; i < 3; ++i)
        CHECK(std::fabs(st.post.ud[i] - (pre.ud[i] + 2 * squat.h * pre.thd)) < 1e-12);
}

TEST_CASE("uplift from full contact: guard = the rocking equations' s theta'' at rest; ramp threshold g tan(alpha)") {
    // consistency of the statics (overturning vs restoring moment) with Lagrange
    for (bool flexible : {false, true}) {
        Frame f = flexible ? flexible_frame(true) : rigid_frame();
        State st; st.s = 0;
        if (flexible) { st.u = {0.01, -0.004, 0.02}; st.ud = {0.2, 0.1, -0.3}; }
        const double J = (4.0 / 3.0) * f.n * f.mc * f.R() * f.R() + 4 * f.R() * f.R() * f.m_deck();
        const double D = J - (flexible ? 4 * f.h * f.h * f.m_structure() : 0.0);
        for (double ah : {-3.0, 0.5, 2.0})
            for (double av : {-2.0, 0.0, 1.5})
                for (int s : {+1, -1}) {
                    State rs = st; rs.s = s;
                    const double thdd = accelerations(f, rs, ah, av).thdd;
                    const double gs = uplift_guard(f, st, s, ah, av);
                    CHECK(std::fabs(gs - D * s * thdd) < 1e-10 * std::fabs(gs));
                }
    }
    // rigid frame under a ramp: lifts at |a_h| = (g + a_v) tan(alpha), as a single column
    for (double av : {0.0, -0.3 * G, 0.2 * G}) {
        Frame f = rigid_frame();
        const double c = 1.7;
        Ground gm{{0.0, 20.0}, {0.0, -20.0 * c}, {av, av}};
        const RunResult r = full_contact_until_uplift(f, State{}, 0.0, gm);
        REQUIRE(r.outcome == Outcome::Uplift);
        CHECK(r.uplift_s == +1);
        const double t_exact = (G + av) * std::tan(f.alpha()) / c;
        CHECK(std::fabs(r.t - t_exact) < 1e-10);
        std::printf("ramp uplift (a_v %.2f): t %.15f exact %.15f\n", av, r.t, t_exact);
    }
}

TEST_CASE("squat columns: the structure on the beam = the fixed-base structure") {
    Frame f = flexible_frame(true);
    f.b = 1.2; f.h = 0.5;                 // alpha = 67 deg: cannot rock under this record
    double a0, a1; f.C = rayleigh(f.m, f.K, 0.05, a0, a1);
    const Ground gm = wiggly_record(0.02, 151, 0.35 * G, 0.0);
    Options o; o.t_end = gm.t.back(); o.out_times = gm.t;
    const RunResult r = full_contact_until_uplift(f, State{0, 0, 0, {0, 0, 0}, {0, 0, 0}, {}}, 0.0, gm, o);
    CHECK(r.outcome == Outcome::End);
    REQUIRE(r.out.size() == gm.t.size());
    // the same structure on a fixed base (its beam's mass carried by the ground)
    const std::vector<Vec> ue = fixed_base_exact(f.m, f.K, a0, a1, gm);
    double peak = 0, err = 0;
    for (size_t k = 0; k < ue.size(); ++k)
        for (int i = 0; i < 3; ++i) {
            peak = std::max(peak, std::fabs(ue[k][i]));
            err = std::max(err, std::fabs(r.out[k].u[i] - ue[k][i]));
        }
    CHECK(err < 1e-8 * peak);
    std::printf("squat: peak u %.4e m, max |reference - fixed-base modal exact| %.2e m (%.2e of peak)\n",
                peak, err, err / peak);
    // the same structure on slender columns does lift
    Frame sl = f; sl.b = 0.15; sl.h = 2.5;
    const RunResult rs = full_contact_until_uplift(sl, State{0, 0, 0, {0, 0, 0}, {0, 0, 0}, {}}, 0.0, gm, o);
    CHECK(rs.outcome == Outcome::Uplift);
    std::printf("slender columns lift at t = %.6f s about s = %+d\n", rs.t, rs.uplift_s);
}

TEST_CASE("column-top contact forces: statics, consistency with Lagrange, tensile detection") {
    // at rest, full contact: the deck's weight shared equally (symmetric columns)
    {
        Frame f = rigid_frame();
        const ContactForces cf = top_contact_forces(f, State{}, 0, 0);
        for (double N : cf.N) CHECK(N == close_to(f.m_deck() * G / f.n, 1e-14));
    }
    // rocking states: the Newton-Euler split closes on Lagrange's theta equation
    for (bool flexible : {false, true}) {
        Frame f = flexible ? flexible_frame(true) : rigid_frame();
        State st; st.s = 1; st.th = 0.3 * f.alpha(); st.thd = -0.2;
        if (flexible) { st.u = {0.01, -0.004, 0.02}; st.ud = {0.2, 0.1, -0.3}; }
        const ContactForces cf = top_contact_forces(f, st, 1.3, -0.7);
        CHECK(std::fabs(cf.residual) < 1e-9 * f.m_deck() * G);
        double sN = 0; for (double N : cf.N) sN += N;
        CHECK(sN == close_to(cf.Fy, 1e-13));
    }
    // (a) vertical ground acceleration ramping downward while the frame rocks
    {
        Frame f = rigid_frame();
        Ground gm{{0.0, 10.0}, {0.0, 0.0}, {0.0, -10.0 * 2.0 * G}};
        State st; st.s = 1; st.th = 0.5 * f.alpha();
        Options o; o.stop_on_tensile = true;
        const RunResult r = first_impact(f, st, 0.0, gm, o);
        REQUIRE(r.outcome == Outcome::TensileTop);
        double ah, av; gm.at(r.t, ah, av);
        const ContactForces cf = top_contact_forces(f, r.state, ah, av);
        CHECK(std::fabs(cf.Nmin) < 1e-8 * f.m_deck() * G);
        CHECK(r.t > 0.0);
        std::printf("(a) a_v ramp: tensile top at t = %.9f s, a_v = %.3f g, N_min = %.2e N\n",
                    r.t, av / G, cf.Nmin);
    }
    // (b) a tall rigid structure on a narrow frame released from a tilt: the
    // beam's horizontal acceleration grows toward the impact, and the
    // overturning moment of the structure lifts one column top off the beam.
    {
        Frame f; f.n = 2; f.b = 0.15; f.h = 1.5; f.mc = 500; f.mb = 1000;
        f.m = {5000}; f.H = {12.0}; f.xcol = {-0.5, 0.5};
        State st; st.s = 1; st.th = 0.8 * f.alpha();
        const ContactForces c0 = top_contact_forces(f, st, 0, 0);
        CHECK(c0.Nmin > 0);
        Options o; o.stop_on_tensile = true;
        const RunResult r = first_impact(f, st, 0.0, Ground::none(), o);
        const RunResult ri = first_impact(f, st, 0.0, Ground::none());
        REQUIRE(r.outcome == Outcome::TensileTop);
        REQUIRE(ri.outcome == Outcome::Impact);
        CHECK(r.t < ri.t);
        const ContactForces cf = top_contact_forces(f, r.state, 0, 0);
        CHECK(std::fabs(cf.Nmin) < 1e-8 * f.m_deck() * G);
        CHECK(cf.Fy > 0);   // the total stays compressive: it is the moment that lifts a top
        CHECK(ri.min_top_N < 0);
        // the same deck low on the beam stays compressive to the impact
        Frame lo = f; lo.H = {0.5};
        const RunResult rl = first_impact(lo, st, 0.0, Ground::none(), o);
        CHECK(rl.outcome == Outcome::Impact);
        CHECK(rl.min_top_N > 0);
        std::printf("(b) tall deck: N_min %.1f N at release, tensile at t = %.9f s (impact at %.9f s)\n",
                    c0.Nmin, r.t, ri.t);
    }
}

TEST_CASE("phases chain: uplift under a record, rocking, impact, momentum law") {
    Frame f = flexible_frame(true);
    f.b = 0.15; f.h = 2.5;
    const Ground gm = wiggly_record(0.02, 151, 0.35 * G, 0.1 * G);
    Options o; o.t_end = gm.t.back();
    const RunResult up = full_contact_until_uplift(f, State{0, 0, 0, {0, 0, 0}, {0, 0, 0}, {}}, 0.0, gm, o);
    REQUIRE(up.outcome == Outcome::Uplift);
    State st = up.state; st.s = up.uplift_s;
    double ah, av; gm.at(up.t, ah, av);
    CHECK(std::fabs(uplift_guard(f, up.state, up.uplift_s, ah, av)) < 1e-6 * f.m_deck() * G * f.b);
    const RunResult ro = first_impact(f, st, up.t, gm, o);
    CHECK(ro.outcome == Outcome::Impact);
    CHECK(ro.t - up.t > 1e-3);
    const ImpactOutcome im = momentum_impact(f, ro.state);
    CHECK(energy(f, im.post).kinetic < energy(f, ro.state).kinetic);
    std::printf("chain: uplift t %.9f (s %+d), impact t %.9f, th'- %.5f, th'+ %.5f (%s)\n",
                up.t, up.uplift_s, ro.t, ro.state.thd, im.post.thd, im.rocking ? "rocks on" : "full contact");
}

// ------------------------------------------------------------- devices (11) ---

namespace {

// A column device at the left edge of each column (chord, prestressed), a
// vertical tendon on each column's axis, and an inclined tendon from the
// ground at x = -1 m to the beam at x = 2 m.
std::vector<Device> elastic_devices(const Frame& f) {
    Device chord; chord.kin = Kinematics::chord; chord.x = -f.b; chord.k = 2e6; chord.P0 = 5e3;
    Device tendon; tendon.kin = Kinematics::vertical; tendon.x = 0.0; tendon.L = 2 * f.h; tendon.k = 5e6; tendon.P0 = 1e4;
    Device beam; beam.kin = Kinematics::beam; beam.x = -1.0; beam.gy = 0.0; beam.bx = 2.0; beam.k = 3e5; beam.P0 = 2e4;
    return {chord, tendon, beam};
}

// The same point of a column rigidly turned clockwise by th about its pivot
// corner s: the distance from a ground point, by rotation (not section 11's forms).
double turned_distance(double X, double Y, double th, double gx, double gy) {
    const double c = std::cos(th), s = std::sin(th);
    return std::hypot(X * c + Y * s - gx, -X * s + Y * c - gy);
}

}  // namespace

TEST_CASE("devices: section 11's elongations are the anchors' distances under the columns' rigid rotation; de/dtheta by differences") {
    const Frame f = rigid_frame();
    for (const Device& d : elastic_devices(f))
        for (int s : {+1, -1})
            for (double a : {0.01, 0.1, 0.7 * f.alpha()}) {
                const double th = s * a;
                const DeviceKin K = device_kin(f, d, s, th);
                CAPTURE(static_cast<int>(d.kin)); CAPTURE(s); CAPTURE(a);
                double e = 0;
                if (d.kin == Kinematics::beam) {
                    // the beam rides on the top corner opposite the pivot, (-2 s b, 2h) from it
                    const double X = -2 * s * f.b, Y = 2 * f.h;
                    const double c = std::cos(th), sn = std::sin(th);
                    const double dx = X * c + Y * sn - X, dy = -X * sn + Y * c - Y;
                    e = std::hypot(d.bx + dx - d.x, 2 * f.h + dy - d.gy) - std::hypot(d.bx - d.x, 2 * f.h - d.gy);
                } else {
                    // the anchor at (x, L) on the column (L = 0: chord), the ground anchor at (x, 0); from the pivot
                    const double Lc = d.kin == Kinematics::vertical ? d.L : 0.0, X = d.x - s * f.b;
                    e = turned_distance(X, Lc, th, X, 0.0) - Lc;
                    if (s * d.x >= f.b) { CHECK(!K.acting); continue; }  // the anchor at the pivot: not lifted
                }
                REQUIRE(K.acting);
                CHECK(K.e == close_to(e, 1e-12, 1e-15));
                const double hstep = 1e-6;
                const double num = (device_kin(f, d, s, th + hstep).e - device_kin(f, d, s, th - hstep).e) / (2 * hstep);
                CHECK(K.dedth == close_to(num, 1e-7, 1e-12));
            }
}

TEST_CASE("devices: the uplift guard with devices at rest is the rocking equations' s theta'' times the inertia") {
    for (bool flexible : {false, true}) {
        Frame f = flexible ? flexible_frame(true) : rigid_frame();
        f.dev = elastic_devices(f);
        Device yielding; yielding.kin = Kinematics::chord; yielding.x = f.b; yielding.law = Law::bouc_wen;
        yielding.k = 4e6; yielding.eps = 0.05; yielding.dy = 2e-3; yielding.alpha = 0.6; yielding.beta = 0.4; yielding.nbw = 2;
        f.dev.push_back(yielding);
        State st;
        st.z = {0, 0, 0, -0.4};  // the yielding device holds a stored force
        if (flexible) { st.u = {0.01, -0.004, 0.02}; st.ud = {0.2, 0.1, -0.3}; }
        const double ah = 1.7, av = -0.9;
        for (int s : {+1, -1}) {
            State r = st; r.s = s; r.th = 0; r.thd = 0;
            const Accel A = accelerations(f, r, ah, av);
            const double ms = f.m_structure();
            const double J = (4.0 / 3.0) * f.n * f.mc * f.R() * f.R() + 4 * f.R() * f.R() * f.m_deck();
            const double inertia = flexible ? J - 4 * f.h * f.h * ms : J;
            CAPTURE(flexible); CAPTURE(s);
            CHECK(s * A.thdd * inertia == close_to(uplift_guard(f, st, s, ah, av), 1e-10, 1e-9 * f.m_deck() * G * f.b));
        }
        // what the devices hold: the beam tendon's lever differs by side, the yielding device holds about s = -1 only
        const double D_right = device_moment_at_rest(f, st, +1), D_left = device_moment_at_rest(f, st, -1);
        const double rx = 3.0, ry = 2 * f.h, r = std::hypot(rx, ry);
        const double beam_right = 2e4 * (rx * 2 * f.h + ry * 2 * f.b) / r, beam_left = 2e4 * (-rx * 2 * f.h + ry * 2 * f.b) / r;
        const double yield_force = 4e6 * 0.95 * 2e-3 * -0.4;
        CHECK(D_right == close_to(f.n * (5e3 * 2 * f.b + 1e4 * f.b) + beam_right, 1e-12));
        CHECK(D_left == close_to(f.n * (1e4 * f.b + yield_force * 2 * f.b) + beam_left, 1e-12));
    }
}

TEST_CASE("devices: free rocking with elastic devices conserves gravity's, the structure's and the devices' energy; the contact forces close on Lagrange's equation") {
    for (bool flexible : {false, true}) {
        Frame f = flexible ? flexible_frame(false) : rigid_frame();
        f.dev = elastic_devices(f);
        for (int s : {+1, -1}) {
            State st; st.s = s; st.th = s * 0.6 * f.alpha(); st.thd = 0.05 * s;
            if (flexible) { st.u = {0.004, -0.002, 0.006}; st.ud = {0.05, -0.1, 0.02}; }
            const double E0 = energy(f, st).total();
            const RunResult ri = first_impact(f, st, 0.0, Ground::none());
            REQUIRE(ri.outcome == Outcome::Impact);
            const Energy E1 = energy(f, ri.state);
            CAPTURE(flexible); CAPTURE(s);
            CHECK(E1.total() == close_to(E0, 1e-10));
            CHECK(energy(f, st).devices > 0);
            const ContactForces cf = top_contact_forces(f, st, 0.8, 0.3);
            CHECK(std::fabs(cf.residual) < 1e-9 * f.m_deck() * G);
            std::printf("devices, %s, s %+d: impact at %.9f s, energy %.12e -> %.12e J\n", flexible ? "flexible" : "rigid",
                        s, ri.t, E0, E1.total());
        }
    }
    // at rest the beam tendon's pull adds to the columns' load
    Frame f = rigid_frame();
    f.dev = elastic_devices(f);
    const ContactForces cf = top_contact_forces(f, State{}, 0, 0);
    double sN = 0; for (double N : cf.N) sN += N;
    CHECK(sN == close_to(f.m_deck() * G + 2e4 * 2 * f.h / std::hypot(3.0, 2 * f.h), 1e-13));
}

TEST_CASE("devices: a Bouc-Wen device follows its closed form while it stretches, and with eps = 1 is the elastic law") {
    Frame f = rigid_frame();
    Device bw; bw.kin = Kinematics::beam; bw.x = -1.0; bw.gy = 0.5; bw.bx = 1.0; bw.law = Law::bouc_wen;
    bw.k = 2e6; bw.eps = 0.1; bw.dy = 5e-4; bw.alpha = 0.7; bw.beta = 0.3; bw.nbw = 1;
    f.dev = {bw};
    // Lifted about the right corners at theta = 0 with theta' > 0: the device
    // stretches until theta' turns; with e' > 0 and z >= 0,
    // d_y z' = e' (1 - (alpha + beta) z), so z = (1 - exp(-(alpha + beta) e / d_y)) / (alpha + beta).
    State st; st.s = 1; st.thd = 0.15; st.z = {0.0};
    Options o; o.out_times = {0.01, 0.02, 0.04, 0.06};
    const RunResult r = first_impact(f, st, 0.0, Ground::none(), o);
    REQUIRE(r.outcome == Outcome::Impact);
    REQUIRE(r.out.size() == o.out_times.size());
    for (const State& x : r.out) {
        if (x.thd <= 0) continue;
        const double e = device_kin(f, bw, 1, x.th).e, ab = bw.alpha + bw.beta;
        CHECK(x.z[0] == close_to((1 - std::exp(-ab * e / bw.dy)) / ab, 1e-9));
    }
    // eps = 1: F = k e, the elastic law with P0 = 0
    Frame fe = f, fb = f;
    fb.dev[0].eps = 1.0;
    fe.dev[0].law = Law::elastic; fe.dev[0].P0 = 0;
    State s0; s0.s = 1; s0.th = 0.5 * f.alpha(); s0.z = {0.3};  // tipped right the device stays stretched (the elastic law's F >= 0 never binds)
    REQUIRE(device_kin(f, bw, 1, 1e-3).e > 0);
    const RunResult a = first_impact(fb, s0, 0.0, Ground::none()), b = first_impact(fe, s0, 0.0, Ground::none());
    REQUIRE(a.outcome == Outcome::Impact);
    CHECK(a.t == close_to(b.t, 1e-10));
    CHECK(a.state.thd == close_to(b.state.thd, 1e-10));
}
