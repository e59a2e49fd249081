module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>
#include <cmath>
module rocking.dynamics;

namespace rocking {

namespace {

// f = -(K u + C u') for N nodes (N static when S > 0, see static_size.hpp):
// this runs in every right-hand side, at sizes where loop control would cost
// more than the arithmetic.
template <int S>
void restoring_force(const StructuralMatrices& sm, const double* u, const double* u_dot, double* f, long n_runtime) {
  if constexpr (S == 0) {
    // Beyond the unrolled sizes the matrices outgrow the cache lines a pass
    // touches: with C = a0 M + a1 K (Rayleigh, as assembled),
    // K u + C u' = K (u + a1 u') + a0 M u' is one pass over K, not over K and C.
    const long n = n_runtime;
    const double a0 = sm.rayleigh.a0, a1 = sm.rayleigh.a1;
    const double* K = sm.K.data();
    const double* M = sm.M.data();  // diagonal (lumped masses) at (i, i)
    for (long i = 0; i < n; ++i) f[i] = -a0 * M[i * n + i] * u_dot[i];
    for (long j = 0; j < n; ++j) {
      const double wj = u[j] + a1 * u_dot[j];
      const double* Kj = K + j * n;
      for (long i = 0; i < n; ++i) f[i] -= Kj[i] * wj;
    }
    return;
  }
  const long n = static_or<S>(n_runtime);
  const double* K = sm.K.data();  // column-major, n x n
  const double* C = sm.C.data();
  double local[S > 0 ? S : 1];  // see rocking_acceleration_n
  double* r = S > 0 ? local : f;
  for (long i = 0; i < n; ++i) r[i] = 0.0;
  subtract_stiffness_damping<S>(K, C, u, u_dot, r, n);
  if (S > 0)
    for (long i = 0; i < n; ++i) f[i] = r[i];
}

// The body of rocking_acceleration (below) for static size S.
template <int S>
double rocking_acceleration_n(const RockingBody& b, Pivot p, double a_g, double g, double device_moment,
                              const Coordinates& q, double* vel, double* acc) {
  const int s = sign(p);
  const Structure& st = b.structure;
  const long n = static_or<S>(q.u.size());
  const double* m = st.masses.data();
  const double* H = st.heights.data();
  const double* inv_m = b.inverse_masses.data();
  const double* u = q.u.data();
  const double* u_dot = q.u_dot.data();
  const double B = st.half_width, thd = q.theta_dot;
  const double c = q.tilt.cos(), sn = q.tilt.sin();
  // At a static size the work is done in a local array, which the compiler
  // knows aliases nothing (the output may, for all it can tell, be the input).
  double local[S > 0 ? S : 1];
  double* r = S > 0 ? local : acc;
  // rhs_u = -M1 a_g cos th - M (sB1 - u) th'^2 - C u' - K u + M1 g sin th (g: b.g + a_v), with
  // w = B1 - s u the lever arms (sB1 - u = s w)
  restoring_force<S>(b.matrices, u, u_dot, r, n);
  const double per_mass = -a_g * c + g * sn, spin = s * thd * thd;
  const double* KH = b.moment_row.data();  // [K'H; C'H]
  double Mw = 0, wMw = 0, wMu_dot = 0, HMw = 0, moment = 0;  // 1'Mw, w'Mw, w'Mu', H'Mw, H'(Ku + Cu')
  for (long i = 0; i < n; ++i) {
    const double w = B - s * u[i], mw = m[i] * w;
    Mw += mw;
    wMw += mw * w;
    wMu_dot += mw * u_dot[i];
    HMw += H[i] * mw;
    moment += KH[i] * u[i] + KH[n + i] * u_dot[i];
    r[i] += m[i] * per_mass - spin * mw;
  }
  const double rhs_th = 2.0 * s * wMu_dot * thd - s * device_moment
                        - a_g * (b.HM1 * c + s * (Mw + b.base_moment) * sn)
                        - g * (-b.HM1 * sn + s * (Mw + b.base_moment) * c);
  // Schur complement of the diagonal M: J - H'MH = m0 B^2 + w'Mw > 0. H'rhs_u
  // from dot products of its parts, not from rhs_u itself, so that th'' need
  // not wait for the restoring forces.
  const double H_rhs_u = -moment + b.HM1 * per_mass - spin * HMw;
  const double th_ddot = (rhs_th - H_rhs_u) / (b.base_inertia + wMw);
  for (long i = 0; i < n; ++i) acc[i] = r[i] * inv_m[i] - H[i] * th_ddot;
  for (long i = 0; i < n; ++i) vel[i] = u_dot[i];
  return th_ddot;
}

// The rocking right-hand side in modal coordinates (see dynamics.cppm): the
// same terms as rocking_acceleration_n, each a diagonal or a dot product
// (Eigen's, vectorised with several partial sums: a plain loop's sum is one
// chain of dependent additions).
double rocking_acceleration_modal(const RockingBody& b, Pivot p, double a_g, double g, double device_moment,
                                  const Coordinates& q, Eigen::Ref<Eigen::VectorXd> rates) {
  const int s = sign(p);
  const ModalBasis& md = b.modes;
  const auto& x = q.u;
  const auto& v = q.u_dot;
  const double B = b.structure.half_width, thd = q.theta_dot, mu = md.mu;
  const double cs = q.tilt.cos(), sn = q.tilt.sin();
  const double per_mass = -a_g * cs + g * sn, spin = s * thd * thd;
  const double rx = md.r.dot(x), rv = md.r.dot(v), xx = x.squaredNorm(), xv = x.dot(v), hx = md.h.dot(x);
  const double hf = md.hk.dot(x) + md.hc.dot(v);  // h'(k q + c q')
  const double Mw = mu * (B - s * rx);             // 1'M w
  const double wMw = mu * (B * B - 2.0 * s * B * rx + xx);
  const double wMu_dot = mu * (B * rv - s * xv);
  const double HMw = B * b.HM1 - s * mu * hx;
  const double rhs_th = 2.0 * s * wMu_dot * thd - s * device_moment
                        - a_g * (b.HM1 * cs + s * (Mw + b.base_moment) * sn)
                        - g * (-b.HM1 * sn + s * (Mw + b.base_moment) * cs);
  const double H_rhs_u = -mu * hf + b.HM1 * per_mass - spin * HMw;
  const double th_ddot = (rhs_th - H_rhs_u) / (b.base_inertia + wMw);
  // rhs_u / mu in the modes, less h th''
  const Eigen::Index n = x.size();
  rates.head(n) = v;
  rates.tail(n).array() = -(md.k.array() * x.array() + md.c.array() * v.array()) +
                          (per_mass - spin * B) * md.r.array() + (spin * s) * x.array() - th_ddot * md.h.array();
  return th_ddot;
}

}  // namespace

RockingBody make_body(const Structure& s, double g) {
  RockingBody b;
  b.structure = s;
  b.g = g;
  if (s.rigid) {  // no elastic coordinates: nothing strains or damps
    const Eigen::Index n = s.masses.size();
    b.matrices.M = s.masses.asDiagonal();
    b.matrices.K.setZero(n, n);
    b.matrices.C.setZero(n, n);
  } else {
    b.matrices = assemble(s);
  }
  b.HM1 = s.heights.dot(s.masses);
  if (!s.rigid) {
    b.moment_row.resize(2 * s.heights.size());
    b.moment_row << b.matrices.K.transpose() * s.heights, b.matrices.C.transpose() * s.heights;
  }
  b.total_mass = total_mass(s);
  b.inverse_masses = s.masses.cwiseInverse();
  b.base_moment = s.base_mass * s.half_width;
  b.base_inertia = b.base_moment * s.half_width;
  return b;
}

RockingBody in_modal_coordinates(RockingBody b) {
  if (b.structure.rigid || b.coordinates == ElasticCoordinates::modal) return b;
  const Structure& st = b.structure;
  const StructuralMatrices& sm = b.matrices;
  ModalBasis& md = b.modes;
  md.mu = st.masses.sum();
  md.Phi = sm.fixed_base.shapes * std::sqrt(md.mu);  // shapes' M shapes = I
  md.inverse = md.Phi.transpose() * st.masses.asDiagonal() / md.mu;
  md.k = sm.fixed_base.omega.array().square().matrix();
  md.c = (sm.rayleigh.a0 + sm.rayleigh.a1 * md.k.array()).matrix();
  md.r = md.inverse * Eigen::VectorXd::Ones(st.masses.size());
  md.h = md.inverse * st.heights;
  md.hk = md.h.cwiseProduct(md.k);
  md.hc = md.h.cwiseProduct(md.c);
  const Eigen::Index n = st.masses.size();
  b.moment_row.resize(2 * n);  // H'(K u + C u') = mu h'(k q + c q')
  b.moment_row << md.mu * md.hk, md.mu * md.hc;
  b.coordinates = ElasticCoordinates::modal;
  return b;
}

double mass_sum(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x) {
  if (b.coordinates == ElasticCoordinates::modal) return b.modes.mu * b.modes.r.dot(x);
  return (b.structure.masses.array() * x.array()).sum();
}

double mass_dot(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x, Eigen::Ref<const Eigen::VectorXd> y) {
  if (b.coordinates == ElasticCoordinates::modal) return b.modes.mu * x.dot(y);
  return (b.structure.masses.array() * x.array() * y.array()).sum();
}

double mass_norm(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x) {
  if (b.coordinates == ElasticCoordinates::modal) return b.modes.mu * x.squaredNorm();
  return (b.structure.masses.array() * x.array().square()).sum();
}

double moment_sum(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> x) {
  if (b.coordinates == ElasticCoordinates::modal) return b.modes.mu * b.modes.h.dot(x);
  return (b.structure.heights.array() * b.structure.masses.array() * x.array()).sum();
}

const Eigen::VectorXd& heights_in_coordinates(const RockingBody& b) {
  return b.coordinates == ElasticCoordinates::modal ? b.modes.h : b.structure.heights;
}

double viscous_power(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> v) {
  if (b.coordinates == ElasticCoordinates::modal)
    return b.modes.mu * (b.modes.c.array() * v.array().square()).sum();
  // v'C v, unrolled for the node count as the right-hand side is (it is
  // integrated beside it whenever the energy balance is tracked)
  double power = 0;
  with_static_size(v.size(), [&](auto size) {
    const long n = static_or<decltype(size)::value>(v.size());
    const double* C = b.matrices.C.data();  // column-major
    const double* x = v.data();
    for (long j = 0; j < n; ++j) {
      double column = 0;
      for (long i = 0; i < n; ++i) column += C[j * n + i] * x[i];
      power += x[j] * column;
    }
  });
  return power;
}

void to_nodal(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> u) {
  if (b.coordinates == ElasticCoordinates::modal) u.noalias() = b.modes.Phi * q;
  else u = q;
}

void from_nodal(const RockingBody& b, Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<Eigen::VectorXd> q) {
  if (b.coordinates == ElasticCoordinates::modal) q.noalias() = b.modes.inverse * u;
  else q = u;
}

void full_contact_acceleration(const RockingBody& b, double a_g, Eigen::Ref<const Eigen::VectorXd> u,
                               Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> rates) {
  const Eigen::Index n_all = u.size();
  if (b.coordinates == ElasticCoordinates::modal) {
    const ModalBasis& md = b.modes;
    rates.head(n_all) = u_dot;
    rates.tail(n_all) = -(md.k.cwiseProduct(u) + md.c.cwiseProduct(u_dot)) - a_g * md.r;
    return;
  }
  with_static_size(n_all, [&](auto size) {
    constexpr int S = decltype(size)::value;
    const long n = static_or<S>(n_all);
    double* vel = rates.data();
    double* acc = vel + n;
    const double* inv_m = b.inverse_masses.data();
    restoring_force<S>(b.matrices, u.data(), u_dot.data(), acc, n);
    for (long i = 0; i < n; ++i) acc[i] = acc[i] * inv_m[i] - a_g;
    for (long i = 0; i < n; ++i) vel[i] = u_dot[i];
  });
}

// Unrolled for the node count (static_size.hpp): the right-hand side of
// every rocking step.
double rocking_acceleration(const RockingBody& b, Pivot p, GroundAcceleration a, double device_moment, const Coordinates& q,
                            Eigen::Ref<Eigen::VectorXd> rates) {
  const double g = b.g + a.v;  // the gravity the rocking structure feels (MODEL.md 14)
  if (b.coordinates == ElasticCoordinates::modal)
    return rocking_acceleration_modal(b, p, a.h, g, device_moment, q, rates);
  double th_ddot = 0;
  const Eigen::Index n = q.u.size();
  with_static_size(n, [&](auto size) {
    th_ddot = rocking_acceleration_n<decltype(size)::value>(b, p, a.h, g, device_moment, q, rates.data(), rates.data() + n);
  });
  return th_ddot;
}

double rigid_rocking_acceleration(const RockingBody& b, Pivot p, GroundAcceleration a, double device_moment, const Tilt& tilt) {
  const int s = sign(p);
  const Structure& st = b.structure;
  const double B = st.half_width, c = tilt.cos(), sn = tilt.sin();
  const double BM = B * b.total_mass;
  const double rhs_th = -s * device_moment - a.h * (b.HM1 * c + s * BM * sn) -
                        (b.g + a.v) * (-b.HM1 * sn + s * BM * c);
  return rhs_th / pivot_inertia(st);
}

double ground_input_power(const RockingBody& b, Pivot p, GroundAcceleration a, const Coordinates& q) {
  const int s = sign(p);
  const Structure& st = b.structure;
  const double B = st.half_width, c = q.tilt.cos(), sn = q.tilt.sin();
  double Mw = 0, Mu_dot = 0;  // 1'M w, 1'M u'
  if (b.coordinates == ElasticCoordinates::modal) {
    Mw = B * b.modes.mu - s * mass_sum(b, q.u);
    Mu_dot = mass_sum(b, q.u_dot);
  } else {  // unrolled for the node count, as the right-hand side it is integrated beside
    with_static_size(q.u.size(), [&](auto size) {
      const long n = static_or<decltype(size)::value>(q.u.size());
      const double *m = st.masses.data(), *u = q.u.data(), *u_dot = q.u_dot.data();
      for (long i = 0; i < n; ++i) {
        Mw += m[i] * (B - s * u[i]);
        Mu_dot += m[i] * u_dot[i];
      }
    });
  }
  const double horizontal = -a.h * c * Mu_dot - a.h * (b.HM1 * c + s * (Mw + b.base_moment) * sn) * q.theta_dot;
  if (a.v == 0) return horizontal;
  // y = s w sin th + H (cos th - 1) (s B sin th for the foundation beam), w = B1 - s u:
  // sum m y' = -sin th 1'M u' + th' (s cos th (1'M w + m0 B) - H'M1 sin th)
  const double momentum_up = -sn * Mu_dot + q.theta_dot * (s * c * (Mw + b.base_moment) - b.HM1 * sn);
  return horizontal - a.v * momentum_up;
}

double mechanical_energy(const RockingBody& b, Pivot p, const Coordinates& q) {
  const int s = sign(p);
  const Structure& st = b.structure;
  if (b.coordinates == ElasticCoordinates::modal) {
    const double B = st.half_width, thd = q.theta_dot, c = q.tilt.cos(), sn = q.tilt.sin();
    const double Mu = mass_sum(b, q.u);
    const double J = pivot_inertia(st) - 2.0 * s * B * Mu + mass_dot(b, q.u, q.u);
    const double kinetic = 0.5 * mass_dot(b, q.u_dot, q.u_dot) + 0.5 * J * thd * thd + thd * moment_sum(b, q.u_dot);
    const double Mw = B * b.modes.mu - s * Mu;
    const double gravity = b.g * (s * Mw * sn + b.HM1 * (c - 1.0) + st.base_mass * s * B * sn);
    const double elastic = 0.5 * b.modes.mu * (b.modes.k.array() * q.u.array().square()).sum();
    return kinetic + gravity + elastic;
  }
  const auto& m = st.masses.array();
  const double B = st.half_width, thd = q.theta_dot;
  const double c = q.tilt.cos(), sn = q.tilt.sin();
  const Eigen::ArrayXd w = B - s * q.u.array();
  const double J = st.base_mass * B * B + (m * (w.square() + st.heights.array().square())).sum();  // J(u)
  const double kinetic = 0.5 * (m * q.u_dot.array().square()).sum() + 0.5 * J * thd * thd +
                         thd * (m * st.heights.array() * q.u_dot.array()).sum();
  // heights: Y = s w sin th + H cos th for the nodes, s B sin th for the foundation beam
  const double gravity = b.g * ((m * (s * w * sn + st.heights.array() * (c - 1.0))).sum() + st.base_mass * s * B * sn);
  const double elastic = 0.5 * q.u.dot(b.matrices.K * q.u);
  return kinetic + gravity + elastic;
}

}  // namespace rocking
