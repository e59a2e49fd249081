module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
module rocking.columns;

namespace rocking {

namespace {

// sin and cos of phi = alpha - s theta from the tilt's, without trig calls.
struct Angle {
  double sin = 0, cos = 1;
};
Angle phi_of(const Columns& c, Pivot p, const Tilt& tilt) {
  const int s = sign(p);
  const double st = tilt.sin(), ct = tilt.cos();
  return {c.sin_alpha * ct - s * c.cos_alpha * st, c.cos_alpha * ct + s * c.sin_alpha * st};
}

Eigen::Index nodes(const Columns& c) { return c.flexible ? c.structure.heights.size() : 0; }

// f = -M1 a - (K u + C u') into f (n entries; n static when S > 0, see
// static_size.hpp), a column of K and C at a time: this runs in every
// right-hand side, at sizes where loop control costs more than arithmetic.
// The work is done in a local array at a static size, which the compiler
// knows aliases nothing.
template <int S>
void elastic_force(const Columns& c, double a, const double* u, const double* u_dot, double* f, long n_runtime) {
  const long n = static_or<S>(n_runtime);
  const double *K = c.matrices.K.data(), *C = c.matrices.C.data(), *m = c.structure.masses.data();  // column-major
  double local[S > 0 ? S : 1];
  double* r = S > 0 ? local : f;
  for (long i = 0; i < n; ++i) r[i] = -a * m[i];
  subtract_stiffness_damping<S>(K, C, u, u_dot, r, n);
  if (S > 0)
    for (long i = 0; i < n; ++i) f[i] = r[i];
}

// x'A x without a temporary (n static when S > 0).
template <int S>
double quadratic(const Eigen::MatrixXd& A, const double* x, long n_runtime) {
  const long n = static_or<S>(n_runtime);
  const double* a = A.data();
  double sum = 0;
  for (long j = 0; j < n; ++j) {
    double column = 0;
    for (long i = 0; i < n; ++i) column += a[j * n + i] * x[i];
    sum += x[j] * column;
  }
  return sum;
}
double quadratic(const Eigen::MatrixXd& A, Eigen::Ref<const Eigen::VectorXd> x) {
  double sum = 0;
  with_static_size(x.size(), [&](auto size) { sum = quadratic<decltype(size)::value>(A, x.data(), x.size()); });
  return sum;
}

// The flexible deck's rates while rocking (rocking_acceleration, below) for
// static size S: f with a = a_g + bias, then theta'' from 1'f = -m_s a -
// 1'(K u + C u') (two dot products, so that theta'' need not wait for f).
template <int S>
double rocking_rates(const Columns& c, double a, double rhs_theta, double ax, const double* u, const double* u_dot,
                     double* vel, double* acc, long n_runtime) {
  const long n = static_or<S>(n_runtime);
  const double *inv_m = c.inverse_masses.data(), *sK = c.shear_K.data(), *sC = c.shear_C.data();
  double f[S > 0 ? S : 1];
  double* r = S > 0 ? f : acc;
  elastic_force<S>(c, a, u, u_dot, r, n);
  double shear = 0;
  for (long i = 0; i < n; ++i) shear += sK[i] * u[i] + sC[i] * u_dot[i];
  const double theta_ddot = (rhs_theta - ax * (-a * c.structure_mass - shear)) / (c.inertia - ax * ax * c.structure_mass);
  for (long i = 0; i < n; ++i) acc[i] = r[i] * inv_m[i] - ax * theta_ddot;
  for (long i = 0; i < n; ++i) vel[i] = u_dot[i];
  return theta_ddot;
}

// Contacts at x_k = X_k - s b (the top corners opposite the pivots; the
// axes in full contact, s = 0), fixed on the beam: sum N = normal, sum x N =
// moment, the minimum-norm split N_k = normal / n + slope (x_k - mean), into
// normal and out.smallest.
void split_over_columns(const Columns& c, Phase phase, TopContact& out, std::span<double> normal) {
  const int s = phase.sign();
  const int count = c.group.count;
  const double offset = -s * c.group.half_width;
  if (count == 2) {  // determined: N_1 (x_2 - x_1) = x_2 sum N - sum x N, one division
    const double x1 = c.axes[0] + offset, x2 = c.axes[1] + offset;
    const double N1 = (x2 * out.normal - out.moment) / (x2 - x1), N2 = out.normal - N1;
    if (normal.size() >= 2) {
      normal[0] = N1;
      normal[1] = N2;
    }
    out.smallest = std::min(N1, N2);
    return;
  }
  double mean = 0, sxx = 0;
  for (int k = 0; k < count; ++k) mean += c.axes[k] + offset;
  mean /= count;
  for (int k = 0; k < count; ++k) sxx += (c.axes[k] + offset - mean) * (c.axes[k] + offset - mean);
  const double slope = sxx > 0 ? (out.moment - mean * out.normal) / sxx : 0.0;
  out.smallest = out.normal;
  for (int k = 0; k < count; ++k) {
    const double N = out.normal / count + slope * (c.axes[k] + offset - mean);
    if (k < static_cast<int>(normal.size())) normal[k] = N;
    out.smallest = k == 0 ? N : std::min(out.smallest, N);
  }
}

}  // namespace

Columns make_columns(const ColumnGroup& group, const Structure& structure, double g) {
  auto fail = [](const std::string& what) { throw std::invalid_argument(what); };
  if (group.count < 1) fail("columns.count must be at least 1");
  if (!(group.half_width > 0) || !std::isfinite(group.half_width)) fail("columns.half_width must be positive");
  if (!(group.half_height > 0) || !std::isfinite(group.half_height)) fail("columns.half_height must be positive");
  if (!(group.mass > 0) || !std::isfinite(group.mass)) fail("columns.mass must be positive");
  if (group.count >= 2 && !(group.spacing >= 2 * group.half_width && std::isfinite(group.spacing)))
    fail("columns.spacing must be at least a column's width (2 half_width)");
  if (!(g > 0)) fail("g must be positive");
  Columns c;
  c.group = group;
  c.structure = structure;
  c.g = g;
  const bool bare = structure.heights.size() == 0;
  if (bare) {
    if (structure.masses.size() != 0) fail("structure.masses must have one entry per height");
    if (!(structure.base_mass >= 0) || !std::isfinite(structure.base_mass)) fail("structure.base_mass must be non-negative");
  } else {
    Structure checked = structure;  // its own half_width does not enter: the beam carries it
    checked.half_width = group.half_width;
    check(checked);
  }
  c.flexible = !bare && !structure.rigid;
  if (c.flexible) {
    c.matrices = assemble(structure);
    c.inverse_masses = structure.masses.cwiseInverse();
    c.shear_K = c.matrices.K.colwise().sum().transpose();
    c.shear_C = c.matrices.C.colwise().sum().transpose();
    c.moment_K = c.matrices.K.transpose() * structure.heights;
    c.moment_C = c.matrices.C.transpose() * structure.heights;
  }
  const double b = group.half_width, h = group.half_height;
  c.R = std::hypot(b, h);
  c.alpha = std::atan2(b, h);
  c.sin_alpha = b / c.R;
  c.cos_alpha = h / c.R;
  c.columns_mass = group.count * group.mass;
  c.structure_mass = bare ? 0.0 : structure.masses.sum();
  c.deck_mass = structure.base_mass + c.structure_mass;
  c.inertia = 4.0 / 3.0 * c.columns_mass * c.R * c.R + 4.0 * c.R * c.R * c.deck_mass;
  c.lever = c.R * (c.columns_mass + 2.0 * c.deck_mass);
  c.height_mass = bare ? 0.0 : structure.masses.dot(structure.heights);
  c.axes.resize(group.count);
  for (int k = 0; k < group.count; ++k)
    c.axes[k] = group.count == 1 ? 0.0 : -0.5 * group.spacing + group.spacing * k / (group.count - 1);
  return c;
}

Eigen::Index elastic_size(const Columns& c) { return nodes(c); }

double frame_gamma(const Columns& c) { return c.deck_mass / c.columns_mass; }

double frame_p2(const Columns& c) {
  const double gamma = frame_gamma(c);
  return 3.0 * c.g / (4.0 * c.R) * (1.0 + 2.0 * gamma) / (1.0 + 3.0 * gamma);
}

double frame_restitution(const Columns& c) {
  const double gamma = frame_gamma(c);
  return (1.0 - 1.5 * c.sin_alpha * c.sin_alpha + 3.0 * gamma * (1.0 - 2.0 * c.sin_alpha * c.sin_alpha)) /
         (1.0 + 3.0 * gamma);
}

BeamMotion beam_motion(const Columns& c, Pivot pivot, const Tilt& tilt) {
  const int s = sign(pivot);
  const Angle p = phi_of(c, pivot, tilt);
  const double R2 = 2.0 * c.R;
  // dx = 2R s (sin alpha - sin phi), dy = 2R (cos phi - cos alpha), dphi/dtheta = -s
  return {R2 * s * (c.sin_alpha - p.sin), R2 * (p.cos - c.cos_alpha), R2 * p.cos, R2 * s * p.sin,
          R2 * s * p.sin,                 -R2 * p.cos};
}

Stretch beam_device_stretch(const Columns& c, double ground_x, double ground_y, double beam_x, double beam_y,
                            double free_length, Pivot p, const Tilt& tilt) {
  const int s = sign(p);
  const BeamMotion m = beam_motion(c, p, tilt);
  const double rx = beam_x - ground_x, ry = beam_y - ground_y;
  const double L = free_length > 0 ? free_length : std::hypot(rx, ry);
  const double x = rx + m.dx, y = ry + m.dy, length = std::hypot(x, y);
  if (length == 0) return {-L, 0.0};  // anchors that meet: no direction, no lever
  // de/dtheta = n . d(dx, dy)/dtheta; de/d|theta| = s de/dtheta
  return {length - L, s * (x * m.jx + y * m.jy) / length};
}

DeckLoad beam_device_load(const Columns& c, double ground_x, double ground_y, double beam_x, double beam_y, Phase phase,
                          const Tilt& tilt, double force) {
  const BeamMotion m = phase.is_rocking() ? beam_motion(c, *phase.pivot(), tilt) : BeamMotion{};
  const double x = beam_x - ground_x + m.dx, y = beam_y - ground_y + m.dy, length = std::hypot(x, y);
  if (length == 0) return {};
  // -F n on the deck at (beam_x, beam_y - 2h) from O
  const double fx = -force * x / length, fy = -force * y / length;
  return {fx, fy, beam_x * fy - (beam_y - 2.0 * c.group.half_height) * fx};
}

void full_contact_acceleration(const Columns& c, double a_g, Eigen::Ref<const Eigen::VectorXd> u,
                               Eigen::Ref<const Eigen::VectorXd> u_dot, Eigen::Ref<Eigen::VectorXd> rates) {
  const Eigen::Index n = nodes(c);
  if (n == 0) return;
  rates.head(n) = u_dot;
  double* acc = rates.data() + n;
  with_static_size(n, [&](auto size) { elastic_force<decltype(size)::value>(c, a_g, u.data(), u_dot.data(), acc, n); });
  for (Eigen::Index i = 0; i < n; ++i) acc[i] *= c.inverse_masses[i];  // M u'' = -M1 a_g - K u - C u'
}

double rocking_acceleration(const Columns& c, Pivot pivot, GroundAcceleration a, double device_moment, const Coordinates& q,
                            Eigen::Ref<Eigen::VectorXd> rates) {
  const int s = sign(pivot);
  const Angle p = phi_of(c, pivot, q.tilt);
  const double ge = c.g + a.v;
  // rhs_theta = -R (n m_c + 2 m_d) (s (g + a_v) sin phi + a_g cos phi) - s D
  const double rhs_theta = -c.lever * (s * ge * p.sin + a.h * p.cos) - s * device_moment;
  const Eigen::Index n = nodes(c);
  if (n == 0) return rhs_theta / c.inertia;
  // The beam's horizontal Jacobian ax = 2R cos phi and bias 2 s R sin phi theta'^2:
  // M u'' + ax M1 theta'' = f,  ax 1'M u'' + J theta'' = rhs_theta, with
  // f = -M1 (a_g + bias) - K u - C u'; M diagonal, so
  // theta'' = (rhs_theta - ax 1'f) / (J - ax^2 m_s),  u'' = M^-1 f - ax 1 theta''.
  const double ax = 2.0 * c.R * p.cos;
  const double bias = 2.0 * s * c.R * p.sin * q.theta_dot * q.theta_dot;
  double theta_ddot = 0;
  with_static_size(n, [&](auto size) {
    theta_ddot = rocking_rates<decltype(size)::value>(c, a.h + bias, rhs_theta, ax, q.u.data(), q.u_dot.data(),
                                                      rates.data(), rates.data() + n, n);
  });
  return theta_ddot;
}

double uplift_guard(const Columns& c, Pivot p, GroundAcceleration a, double held_moment,
                    Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot) {
  const int s = sign(p);
  // The rocking equations' numerator at theta = theta' = 0 (phi = alpha,
  // R sin alpha = b, R cos alpha = h), times s.
  const double b = c.group.half_width, h = c.group.half_height;
  const double rhs_theta = -(c.columns_mass + 2.0 * c.deck_mass) * (s * (c.g + a.v) * b + a.h * h) - s * held_moment;
  // 1'f = -m_s a_g - 1'(K u + C u') for a flexible deck; a rigid deck's masses
  // ride on theta (their inertia and load are in J and rhs_theta).
  const double shear = c.flexible ? -c.structure_mass * a.h - c.shear_K.dot(u) - c.shear_C.dot(u_dot) : 0.0;
  return s * (rhs_theta - 2.0 * h * shear);
}

ColumnsImpact impact(const Columns& c, Pivot p, double theta_dot, Eigen::Ref<Eigen::VectorXd> u_dot, double restitution,
                     double min_rate) {
  const double R2 = c.R * c.R, b = c.group.half_width, h = c.group.half_height;
  const double cos2 = 1.0 - 2.0 * c.sin_alpha * c.sin_alpha;
  const double m0 = c.structure.base_mass, ms = c.structure_mass;
  ColumnsImpact out;
  if (restitution < 0) {
    // Momentum conjugate to the post-impact (u, theta) conserved (docs/columns.md):
    // (J - 4h^2 m_s) theta'+ = [(4/3) n m_c R^2 (1 - 1.5 sin^2 alpha) + 4 R^2 m0 cos 2alpha - 4 b^2 m_s] theta'-
    // for a flexible deck (u'+ + 2h theta'+ = u'- + 2h theta'-); a rigid deck
    // moves with theta, so m_s joins m0: 16's r.
    const double columns = 4.0 / 3.0 * c.columns_mass * R2;
    const double num = columns * (1.0 - 1.5 * c.sin_alpha * c.sin_alpha) + 4.0 * R2 * m0 * cos2 +
                       (c.flexible ? -4.0 * b * b * ms : 4.0 * R2 * ms * cos2);
    const double den = columns + 4.0 * R2 * m0 + (c.flexible ? 4.0 * b * b * ms : 4.0 * R2 * ms);
    out.ratio = num / den;
  } else {
    out.ratio = restitution;
  }
  const bool rocks = out.ratio > 0 && std::abs(theta_dot) > min_rate;
  if (rocks) {
    out.after = Phase::rocking(opposite(p));
    out.theta_dot = out.ratio * theta_dot;
    // theta'+ = ratio theta'-; a flexible deck keeps its nodes' horizontal momentum
    if (c.flexible && restitution < 0) u_dot.array() += 2.0 * h * (theta_dot - out.theta_dot);
  } else {
    out.after = Phase::full_contact();
    out.theta_dot = 0;
    // the beam stops: u'+ = u'- + 2h theta'- (the nodes' horizontal momentum)
    if (c.flexible && restitution < 0) u_dot.array() += 2.0 * h * theta_dot;
  }
  return out;
}

ColumnsEnergy mechanical_energy(const Columns& c, Phase phase, const Coordinates& q) {
  ColumnsEnergy e;
  const Eigen::Index n = nodes(c);
  if (n > 0) {
    e.kinetic = 0.5 * q.u_dot.dot(c.structure.masses.cwiseProduct(q.u_dot));
    e.elastic = 0.5 * quadratic(c.matrices.K, q.u);
  }
  if (phase.is_rocking()) {
    const Angle p = phi_of(c, *phase.pivot(), q.tilt);
    const double w = q.theta_dot;
    // T = 1/2 J theta'^2 + 2R cos phi theta' 1'M u' + 1/2 u'M u'
    e.kinetic += 0.5 * c.inertia * w * w;
    if (n > 0) e.kinetic += 2.0 * c.R * p.cos * w * c.structure.masses.dot(q.u_dot);
    // g R (n m_c + 2 m_d) (cos phi - cos alpha): the columns' centres and the deck
    e.gravity = c.g * c.lever * (p.cos - c.cos_alpha);
  }
  return e;
}

double ground_input_power(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q) {
  const int s = phase.sign();
  const Eigen::Index n = nodes(c);
  double P = n > 0 ? -a.h * c.structure.masses.dot(q.u_dot) : 0.0;
  if (s != 0) {
    const Angle p = phi_of(c, *phase.pivot(), q.tilt);
    P -= c.lever * q.theta_dot * (a.h * p.cos + a.v * s * p.sin);
  }
  return P;
}

double viscous_power(const Columns& c, Eigen::Ref<const Eigen::VectorXd> u_dot) {
  return nodes(c) > 0 ? quadratic(c.matrices.C, u_dot) : 0.0;
}

TopContact top_contact_forces(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q, double theta_ddot,
                              Eigen::Ref<const Eigen::VectorXd> u_ddot, std::span<double> normal,
                              const DeckLoad& load) {
  // The deck's accelerations in the ground's frame: the beam's (0 in full
  // contact), plus u'' for the nodes; the contact forces balance m (acc + (a_g, g + a_v)).
  double ax = 0, ay = 0;
  if (phase.is_rocking()) {
    const BeamMotion m = beam_motion(c, *phase.pivot(), q.tilt);
    const double w2 = q.theta_dot * q.theta_dot;
    ax = m.jx * theta_ddot + m.kx * w2;
    ay = m.jy * theta_ddot + m.ky * w2;
  }
  const double fy = ay + c.g + a.v, fx = ax + a.h;
  TopContact out;
  // The contacts carry what the deck's motion needs less what the load supplies.
  out.normal = c.deck_mass * fy - load.fy;
  out.shear = c.deck_mass * fx - load.fx;
  out.moment = -load.moment;
  const Eigen::Index n = c.structure.heights.size();
  const bool flexible = nodes(c) > 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double m = c.structure.masses[i];
    const double ui = flexible ? q.u[i] : 0.0, ui_dd = flexible ? u_ddot[i] : 0.0;
    out.shear += m * ui_dd;
    // about O (the beam's underside centre), counterclockwise: x F_y - y F_x
    out.moment += m * (ui * fy - c.structure.heights[i] * (fx + ui_dd));
  }
  split_over_columns(c, phase, out, normal);
  return out;
}

TopContact top_contact_forces_now(const Columns& c, Phase phase, GroundAcceleration a, const Coordinates& q,
                                  double device_moment, std::span<double> normal, const DeckLoad& load) {
  const int s = phase.sign();
  // The nodes enter through 1'M u'', H'M u'' and 1'M u. With f = -M1 acc -
  // (K u + C u') (acc = a_g, or a_g + the beam's bias while rocking),
  // M u'' = f - jac M1 theta'' gives 1'M u'' = 1'f - jac m_s theta'' and
  // H'M u'' = H'f - jac H'M1 theta'' (rocking_acceleration's equations).
  const Eigen::Index n = nodes(c);
  double Mu = 0, shear = 0, moment = 0;  // 1'M u, 1'(K u + C u'), H'(K u + C u')
  if (n > 0) {
    Mu = c.structure.masses.dot(q.u);
    shear = c.shear_K.dot(q.u) + c.shear_C.dot(q.u_dot);
    moment = c.moment_K.dot(q.u) + c.moment_C.dot(q.u_dot);
  }
  double ax = 0, ay = 0, Mu_dd = 0, HMu_dd = 0;
  if (s != 0) {
    const Pivot pivot = *phase.pivot();
    const Angle p = phi_of(c, pivot, q.tilt);
    const double w2 = q.theta_dot * q.theta_dot;
    const double rhs_theta = -c.lever * (s * (c.g + a.v) * p.sin + a.h * p.cos) - s * device_moment;
    double theta_ddot = 0;
    if (n == 0) {
      theta_ddot = rhs_theta / c.inertia;
    } else {
      const double jac = 2.0 * c.R * p.cos, acc = a.h + 2.0 * s * c.R * p.sin * w2;
      const double f = -acc * c.structure_mass - shear, Hf = -acc * c.height_mass - moment;
      theta_ddot = (rhs_theta - jac * f) / (c.inertia - jac * jac * c.structure_mass);
      Mu_dd = f - jac * c.structure_mass * theta_ddot;
      HMu_dd = Hf - jac * c.height_mass * theta_ddot;
    }
    const BeamMotion m = beam_motion(c, pivot, q.tilt);
    ax = m.jx * theta_ddot + m.kx * w2;
    ay = m.jy * theta_ddot + m.ky * w2;
  } else if (n > 0) {
    Mu_dd = -a.h * c.structure_mass - shear;
    HMu_dd = -a.h * c.height_mass - moment;
  }
  const double fy = ay + c.g + a.v, fx = ax + a.h;
  TopContact out;
  out.normal = c.deck_mass * fy - load.fy;
  out.shear = c.deck_mass * fx + Mu_dd - load.fx;
  // about O, counterclockwise: sum m (u fy - H (fx + u''))
  out.moment = -load.moment + fy * Mu - fx * c.height_mass - HMu_dd;
  split_over_columns(c, phase, out, normal);
  return out;
}

}  // namespace rocking
