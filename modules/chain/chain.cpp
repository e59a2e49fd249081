module;
#include <rocking/eigen.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>
module rocking.chain;

namespace rocking {

namespace {

// cos and sin of a rotation, for the closed form of a rigid top
// (rigid_top), which runs at every step, and the anchors' positions (the
// outputs' top drift at every sample). A joint's or a face's angle is
// small in every motion short of overturning: there (|x| <= 1/16) the Taylor
// series to x^10 for the cosine and x^9 for the sine is exact to round-off
// (the first term left out, x^12/12! or x^11/11!, is below 1e-19 of the
// value), at a fraction of the library's cost; larger angles take the
// library's. The generic path (kinematics) keeps the library's, which the
// one-joint structure's equations share: a difference in the last bit there
// grows over a long run's impacts.
struct CosSin {
  double c = 1, s = 0;
};
CosSin cos_sin(double x) {
  if (std::abs(x) <= 0.0625) {
    const double x2 = x * x;
    const double s = x * (1.0 - x2 * (1.0 / 6) * (1.0 - x2 * (1.0 / 20) * (1.0 - x2 * (1.0 / 42) * (1.0 - x2 * (1.0 / 72)))));
    const double c =
        1.0 - x2 * 0.5 * (1.0 - x2 * (1.0 / 12) * (1.0 - x2 * (1.0 / 30) * (1.0 - x2 * (1.0 / 56) * (1.0 - x2 * (1.0 / 90)))));
    return {c, s};
  }
  return {std::cos(x), std::sin(x)};
}

// The columns, of the first ncol, in which a frame's Jacobian may be
// nonzero: a frame turns and moves with the joints and the faces below it
// only (segment j's slab frame with theta_0..theta_j, the top u and phi of
// each segment below j and, augmented, d_0..d_j), so that the loops over a
// Jacobian's columns skip the others, where every term is an exact zero. A
// bit set, or every column (`all`: with per_point, whose point Jacobians
// read every column, or beyond 64 columns).
struct Columns {
  std::uint64_t bits = 0;
  bool all = false;
  void add(int k, int ncol) {
    if (!all && k >= 0 && k < ncol) bits |= std::uint64_t{1} << k;
  }
  bool has(int k) const { return all || (k >= 0 && k < 64 && ((bits >> k) & 1U) != 0); }
};

// f(k) for each column k of s (of the first ncol).
template <class F>
void each_column(const Columns& s, int ncol, F f) {
  if (s.all) {
    for (int k = 0; k < ncol; ++k) f(k);
    return;
  }
  for (std::uint64_t m = s.bits; m != 0; m &= m - 1) f(std::countr_zero(m));
}

// A frame: origin O, angle psi (clockwise, as theta), their rates, and the
// bias acceleration of O (its acceleration at q'' = 0). Its Jacobian lives in
// three rows of ChainWorkspace::frames: dOx/dq, dOy/dq, dpsi/dq, nonzero in
// the columns `cols` only (the rows' other entries are not kept up to date
// unless cols is every column).
struct Frame {
  double ox = 0, oy = 0, psi = 0, c = 1, s = 0;
  double vx = 0, vy = 0, omega = 0, bx = 0, by = 0;
  int row = 0;  // first of its three Jacobian rows
  Columns cols;
};

// A point of frame f at local (x, z), local rate (x', 0), whose x is
// coordinate ucol (-1: none), into Jacobian rows out, out + 1 of jac, with its
// position, velocity and bias acceleration:
//   p = O + R r, R r = (x c + z s, -x s + z c),
//   p' = O' + w perp(R r) + R r',  perp(a, b) = (b, -a),
//   bias = O_bias - w^2 R r + 2 w perp(R r').
struct Point {
  double x, y, vx, vy, bx, by;
};
using Rows = ChainWorkspace::Rows;

Point point_of(const Frame& f, const Rows& fj, double x, double z, double x_dot, int ucol, int ncol, Rows& jac,
               int out) {
  const double rx = x * f.c + z * f.s, ry = -x * f.s + z * f.c;
  const double px = ry, py = -rx;  // perp(R r)
  for (int k = 0; k < ncol; ++k) {
    const double dpsi = fj(f.row + 2, k);
    jac(out, k) = fj(f.row, k) + px * dpsi;
    jac(out + 1, k) = fj(f.row + 1, k) + py * dpsi;
  }
  if (ucol >= 0 && ucol < ncol) {
    jac(out, ucol) += f.c;
    jac(out + 1, ucol) -= f.s;
  }
  const double w = f.omega;
  const double rdx = x_dot * f.c, rdy = -x_dot * f.s;  // R r'
  return {f.ox + rx,
          f.oy + ry,
          f.vx + w * px + rdx,
          f.vy + w * py + rdy,
          f.bx - w * w * rx + 2.0 * w * rdy,
          f.by - w * w * ry - 2.0 * w * rdx};
}

// The frame at local (x, z) of frame f (local rate (x', 0), x being
// coordinate ucol, -1: none), turned by dpsi (rate dpsi_dot, coordinate col,
// -1: none): point_of's point as a frame, its Jacobian into rows row..row+2
// of fj in one pass.
Frame frame_from(const Frame& f, Rows& fj, double x, double z, double x_dot, int ucol, int ncol, int row, double dpsi,
                 double dpsi_dot, int col) {
  const double rx = x * f.c + z * f.s, ry = -x * f.s + z * f.c;
  const double px = ry, py = -rx;  // perp(R r)
  const double* fx = &fj(f.row, 0);
  const double* fy = &fj(f.row + 1, 0);
  const double* fp = &fj(f.row + 2, 0);
  double* gx = &fj(row, 0);
  double* gy = &fj(row + 1, 0);
  double* gp = &fj(row + 2, 0);
  each_column(f.cols, ncol, [&](int k) {
    gx[k] = fx[k] + px * fp[k];
    gy[k] = fy[k] + py * fp[k];
    gp[k] = fp[k];
  });
  // f's Jacobian is zero on ucol and col (a segment's own u, a joint above
  // f): there g's is the new terms alone.
  if (ucol >= 0 && ucol < ncol) {
    gx[ucol] = f.c;
    gy[ucol] = -f.s;
    gp[ucol] = 0.0;
  }
  if (col >= 0 && col < ncol) {
    gx[col] = gy[col] = 0.0;
    gp[col] = 1.0;
  }
  const double w = f.omega;
  const double rdx = x_dot * f.c, rdy = -x_dot * f.s;  // R r'
  Frame g;
  g.row = row;
  g.cols = f.cols;
  g.cols.add(ucol, ncol);
  g.cols.add(col, ncol);
  g.ox = f.ox + rx;
  g.oy = f.oy + ry;
  g.vx = f.vx + w * px + rdx;
  g.vy = f.vy + w * py + rdy;
  g.bx = f.bx - w * w * rx + 2.0 * w * rdy;
  g.by = f.by - w * w * ry - 2.0 * w * rdx;
  g.psi = f.psi + dpsi;
  if (dpsi == 0.0) {  // cos(psi + 0) = cos(psi) exactly
    g.c = f.c;
    g.s = f.s;
  } else {
    g.c = std::cos(g.psi);
    g.s = std::sin(g.psi);
  }
  g.omega = f.omega + dpsi_dot;
  return g;
}

bool closed(const Phase& p) { return !p.is_rocking(); }

int pivot_sign(const Phase& p) { return p.sign(); }

// Whether segment j enters the equations lumped (its slab frame, its
// Chain::segment_* and, when flexible, its nodes' sums in w.slabs) rather
// than point by point.
bool lumped(const ChainWorkspace& w) { return !w.per_point; }

// Columns of w.slabs: the slab frame's O x, y, cos, sin of psi, O', psi',
// O's bias (0-8), then a flexible segment's sums over its nodes (zero when
// rigid): U = sum m u, U' = sum m u', sum m u^2, sum m u u', sum m z u'.
constexpr int slab_U = 9, slab_U_dot = 10, slab_uu = 11, slab_uu_dot = 12, slab_zu_dot = 13, slab_columns = 14;

// Row of w.frames where segment j's slab frame Jacobian starts.
int slab_row(int j) { return 6 + 3 * j; }

// Whether the frames' Jacobians are kept on every column (Columns::all).
bool every_column(const Chain& c, const ChainWorkspace& w) { return w.per_point || c.augmented > 64; }

// The columns of segment j's slab frame, as kinematics builds them: each
// joint i <= j (theta_i and, augmented, d_i) and each face below j (the top
// node's u and phi of segment i - 1).
Columns frame_columns(const Chain& c, int j, int ncol, const ChainWorkspace& w) {
  Columns s;
  s.all = every_column(c, w);
  for (int i = 0; i <= j && !s.all; ++i) {
    if (i > 0) {
      const int eb = c.elastic_offset[i - 1];
      if (eb >= 0) s.add(eb + static_cast<int>(c.data.segments[i - 1].heights.size()) - 1, ncol);
      s.add(c.rotation_index[i - 1], ncol);
    }
    s.add(i, ncol);
    if (ncol > c.size) {
      s.add(c.size + 2 * i, ncol);
      s.add(c.size + 2 * i + 1, ncol);
    }
  }
  return s;
}

// Kinematics of every segment's slab frame (w.slabs, its Jacobian in
// w.frames from slab_row(j)), of every mass point of a segment not lumped
// (rows 2i, 2i+1 of w.jac; position, velocity and bias in w.points) and of
// the tendons' anchors (after the points), for
// the first ncol coordinates (size, or augmented with each joint's relative
// translation (d_x, d_y) in its face's frame, about the joint's reference
// point: the active corner, or the centre of a closed joint, where theta_j
// then turns).
void kinematics(const Chain& c, ChainPhases phases, Eigen::Ref<const Eigen::VectorXd> q,
                Eigen::Ref<const Eigen::VectorXd> q_dot, int ncol, ChainWorkspace& w) {
  const ChainData& d = c.data;
  Rows& fj = w.frames;  // rows 0-2 face, 3-5 pivot, then the slab frames
  Rows& jac = w.jac;
  const int anchor_row = 2 * c.points;
  const int tendons = static_cast<int>(d.tendons.size());
  auto place_anchor = [&](const ChainAnchor& a, int slot, const Frame* seg, int j) {
    const int row = anchor_row + 2 * slot;
    if (a.segment < 0) {
      for (int k = 0; k < ncol; ++k) jac(row, k) = jac(row + 1, k) = 0.0;
      w.anchors.row(slot) << a.x, a.z, 0.0, 0.0;
      return;
    }
    if (a.segment != j) return;
    double x = a.x, z = a.z, xd = 0;
    int ucol = -1;
    if (a.node >= 0) {
      z = c.local_heights[j][a.node];
      if (c.elastic_offset[j] >= 0) {
        ucol = c.elastic_offset[j] + a.node;
        x += q[ucol];
        xd = q_dot[ucol];
      }
    }
    const Point p = point_of(*seg, fj, x, z, xd, ucol, ncol, jac, row);
    w.anchors.row(slot) << p.x, p.y, p.vx, p.vy;
  };
  for (int t = 0; t < tendons; ++t)
    if (d.tendons[t].from.segment < 0) place_anchor(d.tendons[t].from, 2 * t, nullptr, -1);

  Frame face;  // the ground
  face.row = 0;
  face.cols.all = every_column(c, w);
  if (face.cols.all)
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < ncol; ++k) fj(r, k) = 0.0;
  Frame seg;
  int pt = 0;
  for (int j = 0; j < c.joints; ++j) {
    const ChainSegment& sg = d.segments[j];
    const int eo = c.elastic_offset[j];
    if (j > 0) {  // the face: segment j-1's top node, turning with its phi
      const ChainSegment& below = d.segments[j - 1];
      const int n = static_cast<int>(below.heights.size());
      const int eb = c.elastic_offset[j - 1];
      const int ucol = eb >= 0 ? eb + n - 1 : -1;
      const int pcol = c.rotation_index[j - 1];
      face = frame_from(seg, fj, ucol >= 0 ? q[ucol] : 0.0, c.local_heights[j - 1][n - 1], ucol >= 0 ? q_dot[ucol] : 0.0,
                        ucol, ncol, 0, pcol >= 0 ? q[pcol] : 0.0, pcol >= 0 ? q_dot[pcol] : 0.0, pcol);
    }
    // the reference point: the active corner (s B, 0), or the centre; the
    // pivot frame there turns by theta_j
    const double cx = closed(phases[j]) ? 0.0 : pivot_sign(phases[j]) * sg.half_width;
    const double th = closed(phases[j]) ? 0.0 : q[j], th_dot = closed(phases[j]) ? 0.0 : q_dot[j];
    Frame pivot = frame_from(face, fj, cx, 0.0, 0.0, -1, ncol, 3, th, th_dot, j);
    if (ncol > c.size) {  // relative translation of the slab on the face (zero in the face's Jacobian)
      const int dx = c.size + 2 * j;
      fj(3, dx) = face.c;
      fj(4, dx) = -face.s;
      fj(5, dx) = 0.0;
      fj(3, dx + 1) = face.s;
      fj(4, dx + 1) = face.c;
      fj(5, dx + 1) = 0.0;
      pivot.cols.add(dx, ncol);
      pivot.cols.add(dx + 1, ncol);
    }
    seg = frame_from(pivot, fj, -cx, 0.0, 0.0, -1, ncol, slab_row(j), 0.0, 0.0, -1);
    double* slab = &w.slabs(j, 0);  // row-major, as w.slabs is declared
    slab[0] = seg.ox, slab[1] = seg.oy, slab[2] = seg.c, slab[3] = seg.s, slab[4] = seg.vx, slab[5] = seg.vy;
    slab[6] = seg.omega, slab[7] = seg.bx, slab[8] = seg.by;
    const Eigen::VectorXd& z = c.local_heights[j];
    if (lumped(w)) {
      if (eo >= 0) {  // a flexible segment's sums over its nodes
        double U = 0, Ud = 0, uu = 0, uud = 0, zud = 0;
        for (int i = 0; i < z.size(); ++i) {
          const double m = c.masses[pt + 1 + i], u = q[eo + i], ud = q_dot[eo + i];
          U += m * u;
          Ud += m * ud;
          uu += m * u * u;
          uud += m * u * ud;
          zud += m * z[i] * ud;
        }
        slab[slab_U] = U, slab[slab_U_dot] = Ud, slab[slab_uu] = uu, slab[slab_uu_dot] = uud, slab[slab_zu_dot] = zud;
      }
      pt += 1 + static_cast<int>(z.size());
    } else {  // its mass points: the slab, then the nodes
      const Point slab = point_of(seg, fj, 0.0, 0.0, 0.0, -1, ncol, jac, 2 * pt);
      w.points.row(pt) << slab.x, slab.y, slab.vx, slab.vy, slab.bx, slab.by;
      ++pt;
    }
    for (int i = 0; i < z.size() && !lumped(w); ++i, ++pt) {
      const int ucol = eo >= 0 ? eo + i : -1;
      const Point p = point_of(seg, fj, ucol >= 0 ? q[ucol] : 0.0, z[i], ucol >= 0 ? q_dot[ucol] : 0.0, ucol, ncol, jac,
                               2 * pt);
      w.points.row(pt) << p.x, p.y, p.vx, p.vy, p.bx, p.by;
    }
    for (int t = 0; t < tendons; ++t) {
      place_anchor(d.tendons[t].from, 2 * t, &seg, j);
      place_anchor(d.tendons[t].to, 2 * t + 1, &seg, j);
    }
    (void)sg;
  }
}

// Mass of each point, in kinematics' order.
double point_mass(const Chain& c, int i) { return c.masses[i]; }

// Tendon t's elongation, force and the force's generalised force row
// accumulated into Q (after kinematics).
struct TendonState {
  double e, e_dot, force;
};
TendonState tendon_state(const Chain& c, int t, int ncol, ChainWorkspace& w, Eigen::VectorXd* Q) {
  const ChainTendon& td = c.data.tendons[t];
  const int a = 2 * c.points + 4 * t;  // rows of from, then to
  const double dx = w.anchors(2 * t + 1, 0) - w.anchors(2 * t, 0), dy = w.anchors(2 * t + 1, 1) - w.anchors(2 * t, 1);
  const double L = std::hypot(dx, dy), nx = dx / L, ny = dy / L;
  const double e = L - c.rest_length[t];
  const double e_dot = nx * (w.anchors(2 * t + 1, 2) - w.anchors(2 * t, 2)) + ny * (w.anchors(2 * t + 1, 3) - w.anchors(2 * t, 3));
  const double F = std::max(0.0, td.prestress + td.stiffness * e);
  if (Q && F != 0.0)
    for (int k = 0; k < ncol; ++k)  // -F de/dq, de/dq = n'(J_to - J_from)
      (*Q)[k] -= F * (nx * (w.jac(a + 2, k) - w.jac(a, k)) + ny * (w.jac(a + 3, k) - w.jac(a + 1, k)));
  return {e, e_dot, F};
}

// The entries of M that the solve, the reactions and the corner
// accelerations read: with per_point, the whole of M; else the columns of the
// free coordinates (every row: M_ff and M_cf) and, for each closed joint j of
// the augmented system, its block on (theta_j, d_y) (M_jj, M_dy,j, M_dy,dy).
// add(l, k) adds the contribution to M(l, k) of one rank-few term.
template <class Add>
void for_each_wanted(const Chain& c, ChainPhases phases, int ncol, const ChainWorkspace& w, Add add) {
  if (w.per_point) {
    for (int k = 0; k < ncol; ++k)
      for (int l = k; l < ncol; ++l) add(l, k);
    return;
  }
  for (int k : w.free)
    for (int l = 0; l < ncol; ++l) add(l, k);
  if (ncol <= c.size) return;
  for (int j = 0; j < c.joints; ++j) {
    if (!closed(phases[j])) continue;
    const int dy = c.size + 2 * j + 1;
    add(j, j);
    add(dy, j);
    add(dy, dy);
  }
}

// for_each_wanted's entries in the rows and columns of cols alone (every
// other entry of a term whose factors vanish outside cols is zero).
template <class Add>
void for_each_wanted_in(const Chain& c, ChainPhases phases, int ncol, const ChainWorkspace& w, const Columns& cols,
                        Add add) {
  if (cols.all) {
    for_each_wanted(c, phases, ncol, w, add);
    return;
  }
  for (int k : w.free)
    if (cols.has(k)) each_column(cols, ncol, [&](int l) { add(l, k); });
  if (ncol <= c.size) return;
  for (int j = 0; j < c.joints; ++j) {
    if (!closed(phases[j])) continue;
    const int dy = c.size + 2 * j + 1;
    if (cols.has(j)) add(j, j);
    if (cols.has(j) && cols.has(dy)) add(dy, j);
    if (cols.has(dy)) add(dy, dy);
  }
}

// A segment's share of M and Q from its slab frame (docs/chain.md). Its
// points sit at r_i = (u_i, z_i) in the frame (u = 0 when rigid) and move with
// J_i = J_O + perp(R r_i) J_psi + R e_x e_(u_i)', so
//   sum m_i J_i'J_i = [J_O; J_psi]' A [J_O; J_psi] + the u columns' terms,
// A = [m 0 P_x; 0 m P_y; P_x P_y I], P = sum m_i perp(R r_i) = R (S, -U),
// S = sum m z, U = sum m u, I = sum m (z^2 + u^2); u_i's column adds
// m_i (cos J_O,x - sin J_O,y + z_i J_psi) to every row and m_i to its own
// (R e_x . R e_x = 1, perp(R r_i) . R e_x = z_i). Their forces
// f_i = m_i (bias_i + a), bias_i = O_bias - psi'^2 R r_i + 2 psi' perp(R r_i'),
// sum to F = m (O_bias + a) - psi'^2 R (U, S) + 2 psi' perp(R (U', 0)) in
// translation and P.(O_bias + a) + 2 psi' sum m u u' in rotation, and on u_i
// to m_i ((cos, -sin).(O_bias + a) - psi'^2 u_i).
void lumped_segment(const Chain& c, ChainPhases phases, int j, int first, double ah, double gv, int ncol,
                    Eigen::Ref<const Eigen::VectorXd> q, ChainWorkspace& w) {
  const double* slab = &w.slabs(j, 0);
  const double m = c.segment_mass[j], S = c.segment_moment[j];
  const double U = slab[slab_U], Ud = slab[slab_U_dot];
  const double I = c.segment_inertia[j] + slab[slab_uu];
  const double cs = slab[2], sn = slab[3], om = slab[6];
  const double Px = S * cs - U * sn, Py = -S * sn - U * cs;
  const double RUx = U * cs + S * sn, RUy = -U * sn + S * cs;  // R (U, S)
  const double ax = slab[7] + ah, ay = slab[8] + gv;
  const double Fx = m * ax - om * om * RUx - 2.0 * om * Ud * sn, Fy = m * ay - om * om * RUy - 2.0 * om * Ud * cs;
  const double T = Px * ax + Py * ay + 2.0 * om * slab[slab_uu_dot];
  const int r = slab_row(j);
  const double* jx = &w.frames(r, 0);
  const double* jy = &w.frames(r + 1, 0);
  const double* jp = &w.frames(r + 2, 0);
  double* gx = &w.lumped(0, 0);  // A [J_O; J_psi], one column per coordinate
  double* gy = &w.lumped(1, 0);
  double* gp = &w.lumped(2, 0);
  Eigen::VectorXd& Q = w.force;
  Columns cols = frame_columns(c, j, ncol, w);
  each_column(cols, ncol, [&](int k) {
    Q[k] -= jx[k] * Fx + jy[k] * Fy + jp[k] * T;
    gx[k] = m * jx[k] + Px * jp[k];
    gy[k] = m * jy[k] + Py * jp[k];
    gp[k] = Px * jx[k] + Py * jy[k] + I * jp[k];
  });
  Eigen::MatrixXd& M = w.mass;
  const int eo = c.elastic_offset[j];
  if (eo < 0) {
    for_each_wanted_in(c, phases, ncol, w, cols,
                       [&](int l, int k) { M(l, k) += jx[l] * gx[k] + jy[l] * gy[k] + jp[l] * gp[k]; });
    return;
  }
  const int nodes = static_cast<int>(c.local_heights[j].size());
  // The frame's Jacobian (and so A's columns) is 0 on the segment's own u
  // columns, which its terms below touch too.
  for (int i = 0; i < nodes && eo + i < ncol; ++i) {
    if (!cols.all) gx[eo + i] = gy[eo + i] = gp[eo + i] = 0.0;
    cols.add(eo + i, ncol);
  }
  const double* mass = c.masses.data() + first + 1;
  const double* z = c.local_heights[j].data();
  for (int i = 0; i < nodes && eo + i < ncol; ++i)
    Q[eo + i] -= mass[i] * (cs * ax - sn * ay - om * om * q[eo + i]);
  for_each_wanted_in(c, phases, ncol, w, cols, [&](int l, int k) {
    double v = jx[l] * gx[k] + jy[l] * gy[k] + jp[l] * gp[k];
    const int il = l - eo, ik = k - eo;
    if (il >= 0 && il < nodes) v += mass[il] * (cs * jx[k] - sn * jy[k] + z[il] * jp[k]);
    if (ik >= 0 && ik < nodes) v += mass[ik] * (cs * jx[l] - sn * jy[l] + z[ik] * jp[l]);
    if (il >= 0 && il < nodes && il == ik) v += mass[il];
    M(l, k) += v;
  });
}

// M (the entries for_each_wanted names) and Q on the first ncol coordinates (after kinematics).
void assemble_equations(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                        Eigen::Ref<const Eigen::VectorXd> q_dot, int ncol, ChainWorkspace& w) {
  Eigen::MatrixXd& M = w.mass;
  Eigen::VectorXd& Q = w.force;
  for (int k = 0; k < ncol; ++k) Q[k] = 0.0;
  for_each_wanted(c, phases, ncol, w, [&](int l, int k) { M(l, k) = 0.0; });
  const double gv = c.data.g + a.v;
  for (int j = 0, first = 0; j < c.joints; ++j) {
    const int count = 1 + static_cast<int>(c.local_heights[j].size());
    if (lumped(w)) {
      lumped_segment(c, phases, j, first, a.h, gv, ncol, q, w);
      first += count;
      continue;
    }
    for (int i = first; i < first + count; ++i) {
      const double m = point_mass(c, i);
      if (m == 0.0) continue;
      const double fx = m * (w.points(i, 4) + a.h), fy = m * (w.points(i, 5) + gv);
      const double* jx = &w.jac(2 * i, 0);
      const double* jy = &w.jac(2 * i + 1, 0);
      for (int k = 0; k < ncol; ++k) Q[k] -= jx[k] * fx + jy[k] * fy;
      for_each_wanted(c, phases, ncol, w, [&](int l, int k) { M(l, k) += m * (jx[k] * jx[l] + jy[k] * jy[l]); });
    }
    first += count;
  }
  if (w.per_point)
    for (int k = 0; k < ncol; ++k)
      for (int l = k + 1; l < ncol; ++l) M(k, l) = M(l, k);
  for (int j = 0; j < c.joints; ++j) {  // - K x - C x'
    const int o = c.elastic_offset[j];
    if (o < 0) continue;
    const Eigen::MatrixXd &K = c.K[j], &C = c.C[j];
    const int n = static_cast<int>(K.rows());
    for (int l = 0; l < n; ++l) {
      const double x = q[o + l], v = q_dot[o + l];
      for (int k = 0; k < n; ++k) Q[o + k] -= K(k, l) * x + C(k, l) * v;
    }
  }
  for (int t = 0; t < static_cast<int>(c.data.tendons.size()); ++t) tendon_state(c, t, ncol, w, &Q);
  for (int k = 0; k < std::min(ncol, c.size); ++k) Q[k] += w.applied[k];
}

// The free coordinates (open joints' theta, every elastic one) and, when
// augmented, the fixed ones (closed joints' theta, every d).
void partition(const Chain& c, ChainPhases phases, bool augmented, ChainWorkspace& w) {
  int closed_joints = 0;
  for (int j = 0; j < c.joints; ++j) closed_joints += closed(phases[j]) ? 1 : 0;
  w.free.resize(static_cast<std::size_t>(c.size - closed_joints));  // within make_workspace's reserve
  w.fixed.resize(static_cast<std::size_t>(closed_joints + (augmented ? c.augmented - c.size : 0)));
  int* f = w.free.data();
  int* x = w.fixed.data();
  for (int j = 0; j < c.joints; ++j) *(closed(phases[j]) ? x++ : f++) = j;
  for (int k = c.joints; k < c.size; ++k) *f++ = k;
  if (augmented)
    for (int k = c.size; k < c.augmented; ++k) *x++ = k;
}

// x = M_ff^-1 x in place, with M_ff's Cholesky factor in w.reduced (solve_free).
void solve_factored(const ChainWorkspace& w, Eigen::VectorXd& x) {
  const int n = static_cast<int>(w.free.size());
  const Eigen::MatrixXd& L = w.reduced;
  for (int i = 0; i < n; ++i) {
    double v = x[i];
    for (int p = 0; p < i; ++p) v -= L(i, p) * x[p];
    x[i] = v / L(i, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    double v = x[i];
    for (int p = i + 1; p < n; ++p) v -= L(p, i) * x[p];
    x[i] = v / L(i, i);
  }
}

// x = M_ff^-1 x and y = M_ff^-1 y in place, in one pass (solve_factored's
// operations on each: two independent chains of dependent steps interleaved).
void solve_factored(const ChainWorkspace& w, double* x, double* y) {
  const int n = static_cast<int>(w.free.size());
  const Eigen::MatrixXd& L = w.reduced;
  for (int i = 0; i < n; ++i) {
    double v = x[i], u = y[i];
    for (int p = 0; p < i; ++p) {
      v -= L(i, p) * x[p];
      u -= L(i, p) * y[p];
    }
    x[i] = v / L(i, i);
    y[i] = u / L(i, i);
  }
  for (int i = n - 1; i >= 0; --i) {
    double v = x[i], u = y[i];
    for (int p = i + 1; p < n; ++p) {
      v -= L(p, i) * x[p];
      u -= L(p, i) * y[p];
    }
    x[i] = v / L(i, i);
    y[i] = u / L(i, i);
  }
}

// Solve M_ff x = rhs (rhs in w.rhs, result in w.solution) by Cholesky in w.reduced.
void solve_free(ChainWorkspace& w) {
  const int n = static_cast<int>(w.free.size());
  Eigen::MatrixXd& L = w.reduced;
  for (int b = 0; b < n; ++b)
    for (int a = b; a < n; ++a) L(a, b) = w.mass(w.free[a], w.free[b]);
  for (int k = 0; k < n; ++k) {
    double d = L(k, k);
    for (int p = 0; p < k; ++p) d -= L(k, p) * L(k, p);
    if (!(d > 0.0)) throw std::runtime_error("chain: mass matrix not positive definite");
    d = std::sqrt(d);
    L(k, k) = d;
    for (int i = k + 1; i < n; ++i) {
      double v = L(i, k);
      for (int p = 0; p < k; ++p) v -= L(i, p) * L(k, p);
      L(i, k) = v / d;
    }
  }
  for (int i = 0; i < n; ++i) w.solution[i] = w.rhs[i];
  solve_factored(w, w.solution);
}

// sum m v over the mass points (after kinematics): a lumped segment's is
// m O' + psi' P + R (U', 0) (P as in lumped_segment).
Eigen::Vector2d momentum(const Chain& c, const ChainWorkspace& w) {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int j = 0, first = 0; j < c.joints; ++j) {
    const int count = 1 + static_cast<int>(c.local_heights[j].size());
    if (lumped(w)) {
      const double S = c.segment_moment[j], m = c.segment_mass[j], om = w.slabs(j, 6);
      const double U = w.slabs(j, slab_U), Ud = w.slabs(j, slab_U_dot), cs = w.slabs(j, 2), sn = w.slabs(j, 3);
      p.x() += m * w.slabs(j, 4) + om * (S * cs - U * sn) + Ud * cs;
      p.y() += m * w.slabs(j, 5) - om * (S * sn + U * cs) - Ud * sn;
    } else {
      for (int i = first; i < first + count; ++i) {
        p.x() += point_mass(c, i) * w.points(i, 2);
        p.y() += point_mass(c, i) * w.points(i, 3);
      }
    }
    first += count;
  }
  return p;
}

// The ground's power and the viscous damping's (after kinematics).
ChainPower power_of(const Chain& c, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q_dot, const ChainWorkspace& w) {
  ChainPower p;
  const Eigen::Vector2d mv = momentum(c, w);
  p.ground = -(a.h * mv.x() + a.v * mv.y());
  for (int j = 0; j < c.joints; ++j) {  // x'C x', with no temporary
    const int o = c.elastic_offset[j];
    if (o < 0) continue;
    const Eigen::MatrixXd& C = c.C[j];
    for (Eigen::Index l = 0; l < C.cols(); ++l)
      for (Eigen::Index k = 0; k < C.rows(); ++k) p.damping += q_dot[o + k] * C(k, l) * q_dot[o + l];
  }
  return p;
}

void check_sizes(const Chain& c, ChainPhases phases, Eigen::Ref<const Eigen::VectorXd> q,
                 Eigen::Ref<const Eigen::VectorXd> q_dot, Eigen::Ref<Eigen::VectorXd> q_ddot) {
  if (static_cast<int>(phases.size()) != c.joints || q.size() != c.size || q_dot.size() != c.size || q_ddot.size() != c.size)
    throw std::invalid_argument("chain: one phase per joint and one q, q', q'' per coordinate");
}

// docs/chain.md "A rigid top on a closed chain": every joint but the top one
// (J) closed, the top segment rigid, rocking about s or closed, every
// segment below its face rigid but the one it stands on (b = J - 1), no
// tendon. Every segment below the top then has its slab frame fixed in the
// ground's (each stands closed on the ground or on a rigid segment whose
// frame is fixed); a flexible b's nodes move by u alone, so the free
// coordinates are theta_J when the top rocks and, when b is flexible, its u
// and phi; M is the nodes' masses on u_1..u_(n-1) (no other term touches
// them) and a dense block on (theta_J, u_n, phi), the top's
// [J_O; J_psi]' A [J_O; J_psi] with m_n on u_n. A closed top turns with the
// face about its centre: the same kinematics with the corner at the centre
// (s B = 0) and no theta_J. Whether the workspace and the phases take it.
bool rigid_top_applies(const Chain& c, ChainPhases phases, const ChainWorkspace& w) {
  if (!w.rigid_top || w.per_point || !c.data.tendons.empty() || c.joints < 2) return false;
  const int J = c.joints - 1;
  if (c.elastic_offset[J] >= 0) return false;
  for (int j = 0; j < J; ++j)
    if (!closed(phases[j])) return false;
  for (int j = 0; j + 1 < J; ++j)
    if (c.elastic_offset[j] >= 0) return false;
  return true;
}

// The closed form: q'' (and the power) always; with `out`, every joint's
// reaction, and with `corners`, every closed joint's corner accelerations.
void rigid_top(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
               Eigen::Ref<const Eigen::VectorXd> q_dot, Eigen::Ref<Eigen::VectorXd> q_ddot, ChainWorkspace& w,
               ChainPower* power, std::span<JointReaction> out, std::span<CornerAcceleration> corners) {
  const ChainData& d = c.data;
  const int J = c.joints - 1, b = J - 1;
  const double gv = d.g + a.v;
  // The fixed frames' heights O_k.y (x = 0, psi = 0), summed up the chain as
  // kinematics sums them; the first mass point of b.
  double* height = w.column.data();
  int first_b = 0;
  height[0] = 0.0;
  for (int k = 0; k < b; ++k) {
    const Eigen::Index top = c.local_heights[k].size() - 1;
    height[k + 1] = height[k] + c.local_heights[k][top];
    first_b += 1 + static_cast<int>(c.local_heights[k].size());
  }
  const int eo = c.elastic_offset[b];
  const bool flex = eo >= 0, rocks = !closed(phases[J]);
  const int nb = static_cast<int>(c.local_heights[b].size());
  const int ucol = flex ? eo + nb - 1 : -1, pcol = flex ? c.rotation_index[b] : -1;
  const double u = flex ? q[ucol] : 0.0, ud = flex ? q_dot[ucol] : 0.0;
  const double phi = flex ? q[pcol] : 0.0, phid = flex ? q_dot[pcol] : 0.0;
  // The face of joint J: b's top node, turning with phi.
  const double fx = u, fy = height[b] + c.local_heights[b][nb - 1];
  const CosSin face = flex ? cos_sin(phi) : CosSin{};
  const double cF = face.c, sF = face.s;
  // The top: its slab frame about the corner (s B, 0) of the face (the
  // centre, s B = 0, when closed).
  const double sB = rocks ? pivot_sign(phases[J]) * d.segments[J].half_width : 0.0;
  const double th = rocks ? q[J] : 0.0, psi = phi + th, om = phid + (rocks ? q_dot[J] : 0.0);
  const CosSin top = rocks ? cos_sin(psi) : face;
  const double cJ = top.c, sJ = top.s;
  const double RFx = sB * cF, RFy = -sB * sF;  // R(psi_F) (s B, 0)
  const double RJx = sB * cJ, RJy = -sB * sJ;  // R(psi) (s B, 0)
  const double Ox = fx + RFx - RJx, Oy = fy + RFy - RJy;
  const double vx = ud + phid * RFy - om * RJy, vy = -phid * RFx + om * RJx;
  const double bx = -phid * phid * RFx + om * om * RJx, by = -phid * phid * RFy + om * om * RJy;
  // Its frame's Jacobian on the free ones of (theta_J, u_n, phi), in that
  // order: J_O = -perp(R c), (1, 0), perp(R_F c) - perp(R c); J_psi = 1, 0, 1.
  int nf = 0, col[3], iu = -1;
  double jx[3], jy[3], jp[3];
  auto add = [&](int k, double x, double y, double p) { col[nf] = k, jx[nf] = x, jy[nf] = y, jp[nf] = p, ++nf; };
  if (rocks) add(J, -RJy, RJx, 1.0);
  if (flex) {
    iu = nf;
    add(ucol, 1.0, 0.0, 0.0);
    add(pcol, RFy - RJy, -RFx + RJx, 1.0);
  }
  const double m = c.segment_mass[J], S = c.segment_moment[J], I = c.segment_inertia[J];
  const double Px = S * cJ, Py = -S * sJ;  // P = sum m perp(R r) = R (S, 0)
  const double ax = bx + a.h, ay = by + gv;
  const double Fx = m * ax - om * om * S * sJ, Fy = m * ay - om * om * S * cJ;  // R (0, S) = S (sin, cos)
  const double T = Px * ax + Py * ay;
  double Mb[3][3], Qb[3] = {0.0, 0.0, 0.0};
  for (int k = 0; k < nf; ++k) {
    const double gx = m * jx[k] + Px * jp[k], gy = m * jy[k] + Py * jp[k], gp = Px * jx[k] + Py * jy[k] + I * jp[k];
    for (int l = k; l < nf; ++l) Mb[l][k] = jx[l] * gx + jy[l] * gy + jp[l] * gp;
    Qb[k] = -(jx[k] * Fx + jy[k] * Fy + jp[k] * T);
  }
  if (rocks) Qb[0] += w.applied[J];
  // b's coordinates: the nodes' forces -m a_h (their frame still), - K x - C x'.
  double* Qe = w.rhs.data();
  const double* mass = c.masses.data() + first_b + 1;
  if (flex) {
    for (int i = 0; i <= nb; ++i) Qe[i] = i < nb ? -mass[i] * a.h : 0.0;
    const Eigen::MatrixXd &K = c.K[b], &C = c.C[b];
    for (int l = 0; l <= nb; ++l) {
      const double x = q[eo + l], v = q_dot[eo + l];
      for (int k = 0; k <= nb; ++k) Qe[k] -= K(k, l) * x + C(k, l) * v;
    }
    for (int i = 0; i <= nb; ++i) Qe[i] += w.applied[eo + i];
    Mb[iu][iu] += mass[nb - 1];
    Qb[iu] += Qe[nb - 1];
    Qb[iu + 1] += Qe[nb];
  }
  // The block's inverse by its adjugate (one division on the path, where a
  // Cholesky factor's solves take nine), after the leading minors' check
  // that it is positive definite; then q''.
  double Mi[3][3];
  auto not_definite = [] { throw std::runtime_error("chain: mass matrix not positive definite"); };
  if (nf == 1) {
    if (!(Mb[0][0] > 0.0)) not_definite();
    Mi[0][0] = 1.0 / Mb[0][0];
  } else if (nf == 2) {
    const double a0 = Mb[0][0], a1 = Mb[1][0], d1 = Mb[1][1], det = a0 * d1 - a1 * a1;
    if (!(a0 > 0.0) || !(det > 0.0)) not_definite();
    const double r = 1.0 / det;
    Mi[0][0] = d1 * r, Mi[0][1] = Mi[1][0] = -a1 * r, Mi[1][1] = a0 * r;
  } else if (nf == 3) {
    const double a0 = Mb[0][0], a1 = Mb[1][0], a2 = Mb[2][0], d1 = Mb[1][1], e1 = Mb[2][1], f2 = Mb[2][2];
    const double A00 = d1 * f2 - e1 * e1, A01 = a2 * e1 - a1 * f2, A02 = a1 * e1 - a2 * d1;
    const double A11 = a0 * f2 - a2 * a2, A12 = a1 * a2 - a0 * e1, A22 = a0 * d1 - a1 * a1;
    const double det = a0 * A00 + a1 * A01 + a2 * A02;
    if (!(a0 > 0.0) || !(A22 > 0.0) || !(det > 0.0)) not_definite();
    const double r = 1.0 / det;
    Mi[0][0] = A00 * r, Mi[0][1] = Mi[1][0] = A01 * r, Mi[0][2] = Mi[2][0] = A02 * r;
    Mi[1][1] = A11 * r, Mi[1][2] = Mi[2][1] = A12 * r, Mi[2][2] = A22 * r;
  }
  auto solve = [&](double* x) {
    double y[3];
    for (int i = 0; i < nf; ++i) {
      y[i] = 0.0;
      for (int k = 0; k < nf; ++k) y[i] += Mi[i][k] * x[k];
    }
    for (int i = 0; i < nf; ++i) x[i] = y[i];
  };
  double acc[3] = {Qb[0], Qb[1], Qb[2]};
  solve(acc);
  q_ddot.setZero();
  for (int k = 0; k < nf; ++k) q_ddot[col[k]] = acc[k];
  if (flex)
    for (int i = 0; i + 1 < nb; ++i) q_ddot[eo + i] = Qe[i] / mass[i];
  if (power) {  // momentum: b's nodes' sum m u', the top's m O' + psi' P
    double Ud = 0;
    for (int i = 0; flex && i < nb; ++i) Ud += mass[i] * q_dot[eo + i];
    const double px = Ud + (m * vx + om * Px), py = m * vy + om * Py;
    power->ground = -(a.h * px + a.v * py);
    power->damping = 0.0;
    if (flex) {
      const Eigen::MatrixXd& C = c.C[b];
      for (int l = 0; l <= nb; ++l)
        for (int k = 0; k <= nb; ++k) power->damping += q_dot[eo + k] * C(k, l) * q_dot[eo + l];
    }
  }
  if (out.empty()) return;

  // Reactions: the force sum m (a_i + (a_h, g + a_v)) on each part above a
  // joint and its moment about the joint's centre (docs/chain.md).
  double psi_dd = 0, Ax = bx, Ay = by;  // psi'', O''
  for (int k = 0; k < nf; ++k) {
    psi_dd += jp[k] * acc[k];
    Ax += jx[k] * acc[k];
    Ay += jy[k] * acc[k];
  }
  const double ex = Ax + a.h, ey = Ay + gv;
  double Sx = m * ex + psi_dd * Px - om * om * S * sJ, Sy = m * ey + psi_dd * Py - om * om * S * cJ;
  double Mo = Px * ex + Py * ey + I * psi_dd;  // about the top's O (the face's centre when closed)
  out[J].V = cF * Sx - sF * Sy;
  out[J].N = sF * Sx + cF * Sy;
  out[J].M = rocks ? 0.0 : w.applied[J] - Mo;
  // The top's share of b = M_f,t about a corner C (for the corners):
  // J_O'perp(W) + J_psi L with W = m (O - C) + R (0, S), L = R (0, S).(O - C) + I.
  auto top_share = [&](double cx, double cy, double* bt) {
    const double Wtx = m * (Ox - cx) + S * sJ, Wty = m * (Oy - cy) + S * cJ;
    const double Lt = S * sJ * (Ox - cx) + S * cJ * (Oy - cy) + I;
    for (int l = 0; l < nf; ++l) bt[l] = jx[l] * Wty - jy[l] * Wtx + jp[l] * Lt;
  };
  auto set_corner = [&](int k, Pivot p, double den) {
    const double inertia = 1.0 / den;
    (p == Pivot::left ? corners[k].left : corners[k].right) = (sign(p) * out[k].M - d.segments[k].half_width * out[k].N) * inertia;
    (p == Pivot::left ? corners[k].left_gain : corners[k].right_gain) = -inertia;
  };
  if (!corners.empty()) {
    corners[J] = {};
    if (!rocks)  // the top alone about a corner of its face, C = O + R_F (s B_J, 0)
      for (Pivot p : pivots) {
        const double sBJ = sign(p) * d.segments[J].half_width;
        const double cx = Ox + sBJ * cF, cy = Oy - sBJ * sF, rx = Ox - cx, ry = Oy - cy;
        const double tMt = m * (rx * rx + ry * ry) + 2.0 * S * (sJ * rx + cJ * ry) + I;
        double bt[3], y[3], bMb = 0;
        top_share(cx, cy, bt);
        for (int l = 0; l < nf; ++l) y[l] = bt[l];
        solve(y);
        for (int l = 0; l < nf; ++l) bMb += bt[l] * y[l];
        set_corner(J, p, tMt - bMb);
      }
  }
  // The part above, for the corners: mass, first and second moments about (Xx, Xy).
  double mt = m, Wx = S * sJ, Wy = S * cJ, It = I, Xx = Ox, Xy = Oy;
  for (int k = b; k >= 0; --k) {
    const double ox = 0.0, oy = height[k];
    // move the sums to O_k
    const double rx = Xx - ox, ry = Xy - oy;
    Mo += ry * Sx - rx * Sy;
    It += 2.0 * (rx * Wx + ry * Wy) + mt * (rx * rx + ry * ry);
    Wx += mt * rx;
    Wy += mt * ry;
    Xx = ox, Xy = oy;
    // segment k's own, about O_k
    const double mk = c.segment_mass[k], Sk = c.segment_moment[k];
    double Fk = mk * a.h, Tk = Sk * a.h, Uk = 0, uu = 0;
    if (k == b && flex)
      for (int i = 0; i < nb; ++i) {
        const double ui = q[eo + i], ai = q_ddot[eo + i];
        Fk += mass[i] * ai;
        Tk += mass[i] * (c.local_heights[b][i] * ai - gv * ui);
        Uk += mass[i] * ui;
        uu += mass[i] * ui * ui;
      }
    Sx += Fk;
    Sy += mk * gv;
    Mo += Tk;
    mt += mk;
    Wx += Uk;
    Wy += Sk;
    It += c.segment_inertia[k] + uu;
    out[k].V = Sx;
    out[k].N = Sy;
    out[k].M = w.applied[k] - Mo;
    if (corners.empty()) continue;
    for (Pivot p : pivots) {
      const double sBk = sign(p) * d.segments[k].half_width;  // the corner C = O_k + (s B_k, 0)
      const double tMt = It - 2.0 * sBk * Wx + mt * sBk * sBk;
      const double cx = ox + sBk, cy = oy;
      double bt[3], y[3], bMb = 0;
      top_share(cx, cy, bt);
      if (flex) {
        for (int i = 0; i < nb; ++i) {
          const double bi = mass[i] * (height[b] + c.local_heights[b][i] - cy);
          if (i + 1 < nb)
            bMb += bi * bi / mass[i];
          else
            bt[iu] += bi;
        }
      }
      for (int l = 0; l < nf; ++l) y[l] = bt[l];
      solve(y);
      for (int l = 0; l < nf; ++l) bMb += bt[l] * y[l];
      set_corner(k, p, tMt - bMb);
    }
  }
}

void accelerate(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                Eigen::Ref<const Eigen::VectorXd> q_dot, Eigen::Ref<Eigen::VectorXd> q_ddot, bool augmented,
                ChainWorkspace& w, ChainPower* power = nullptr) {
  check_sizes(c, phases, q, q_dot, q_ddot);
  if (!augmented && rigid_top_applies(c, phases, w)) {
    rigid_top(c, phases, a, q, q_dot, q_ddot, w, power, {}, {});
    return;
  }
  partition(c, phases, augmented, w);
  // Without the augmentation only the free coordinates' columns are read (M_ff,
  // Q_f): the Jacobians stop at the last free one (free is increasing, and
  // every elastic coordinate is free, so no -K x - C x' term falls beyond).
  const int ncol = augmented ? c.augmented : (w.free.empty() ? 0 : w.free.back() + 1);
  if (w.free.empty() && !augmented) {
    // No free coordinate: every joint closed on rigid segments (an elastic
    // coordinate is always free), so nothing moves: q'' = 0, no power.
    q_ddot.setZero();
    if (power) *power = ChainPower{};
    return;
  }
  kinematics(c, phases, q, q_dot, ncol, w);
  if (power) *power = power_of(c, a, q_dot, w);
  assemble_equations(c, phases, a, q, q_dot, ncol, w);
  for (std::size_t i = 0; i < w.free.size(); ++i) w.rhs[i] = w.force[w.free[i]];
  solve_free(w);
  q_ddot.setZero();
  for (std::size_t i = 0; i < w.free.size(); ++i) q_ddot[w.free[i]] = w.solution[i];
}

void fail(const std::string& field, const std::string& what) { throw std::invalid_argument(field + ": " + what); }

// Stiffness of a segment's beam clamped to its slab (local heights z), on
// (u_1..u_n) and, with keep_top, the top node's rotation (the others condensed).
Eigen::MatrixXd segment_stiffness(const Eigen::VectorXd& z, const Eigen::VectorXd& EI, bool keep_top) {
  const int n = static_cast<int>(z.size());
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2 * n, 2 * n);  // u_1..u_n, phi_1..phi_n
  for (int e = 0; e < n; ++e) {
    const double below = e == 0 ? 0.0 : z[e - 1];
    const Eigen::Matrix4d ke = element_stiffness(EI[e], z[e] - below);
    const int dof[4] = {e - 1, n + e - 1, e, n + e};
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        if (e > 0 || (a >= 2 && b >= 2)) k(dof[a], dof[b]) += ke(a, b);
  }
  const int kept = n + (keep_top ? 1 : 0);
  std::vector<int> keep, cond;
  for (int i = 0; i < 2 * n; ++i) ((i < n || (keep_top && i == 2 * n - 1)) ? keep : cond).push_back(i);
  Eigen::MatrixXd kk(kept, kept), kc(kept, static_cast<int>(cond.size())), cc(cond.size(), cond.size());
  for (int a = 0; a < kept; ++a)
    for (int b = 0; b < kept; ++b) kk(a, b) = k(keep[a], keep[b]);
  for (int a = 0; a < kept; ++a)
    for (std::size_t b = 0; b < cond.size(); ++b) kc(a, b) = k(keep[a], cond[b]);
  for (std::size_t a = 0; a < cond.size(); ++a)
    for (std::size_t b = 0; b < cond.size(); ++b) cc(a, b) = k(cond[a], cond[b]);
  Eigen::MatrixXd out = cond.empty() ? kk : Eigen::MatrixXd(kk - kc * cc.llt().solve(kc.transpose()));
  return 0.5 * (out + out.transpose());
}

}  // namespace

ChainData split_structure(const Structure& s, std::span<const ChainJointSpec> joints) {
  check(s);
  const int N = static_cast<int>(s.heights.size());
  std::vector<int> cuts{0};
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const std::string field = "joint[" + std::to_string(k + 1) + "]";
    if (joints[k].node < 1 || joints[k].node > N - 1)
      fail(field + ".node", "must be a node of the structure, 1.." + std::to_string(N - 1));
    if (joints[k].node <= cuts.back()) fail(field + ".node", "joints must go up the structure in order");
    cuts.push_back(joints[k].node);
  }
  cuts.push_back(N);
  ChainData d;
  d.g = gravity;
  if (!s.rigid) d.rayleigh = assemble(s).rayleigh;
  for (std::size_t j = 0; j + 1 < cuts.size(); ++j) {
    ChainSegment sg;
    const int lo = cuts[j], hi = cuts[j + 1];  // nodes lo+1..hi
    sg.base_height = lo == 0 ? 0.0 : s.heights[lo - 1];
    sg.half_width = j == 0 ? s.half_width : joints[j - 1].half_width;
    sg.base_mass = j == 0 ? s.base_mass : joints[j - 1].base_mass;
    sg.heights = s.heights.segment(lo, hi - lo);
    sg.masses = s.masses.segment(lo, hi - lo);
    sg.rigid = s.rigid || (j > 0 && joints[j - 1].rigid);
    if (!sg.rigid) sg.EI = s.EI_scale * s.EI.segment(lo, hi - lo);
    d.segments.push_back(sg);
  }
  return d;
}

Chain make_chain(const ChainData& d) {
  Chain c;
  c.data = d;
  if (d.segments.empty()) fail("segments", "a chain needs at least one segment");
  if (!(d.g > 0)) fail("g", "must be > 0");
  c.joints = static_cast<int>(d.segments.size());
  int next = c.joints;
  for (int j = 0; j < c.joints; ++j) {
    const ChainSegment& s = d.segments[j];
    const std::string f = "segments[" + std::to_string(j) + "]";
    const Eigen::Index n = s.heights.size();
    if (n < 1) fail(f + ".heights", "a segment needs at least one node");
    if (s.masses.size() != n) fail(f + ".masses", "one mass per node");
    if (!(s.half_width > 0) || !std::isfinite(s.half_width)) fail(f + ".half_width", "must be > 0");
    if (!(s.base_mass >= 0) || !std::isfinite(s.base_mass)) fail(f + ".base_mass", "must be >= 0");
    const double h0 = j == 0 ? 0.0 : d.segments[j - 1].heights[d.segments[j - 1].heights.size() - 1];
    if (s.base_height != h0) fail(f + ".base_height", "must be the top node's height of the segment below (0 for the first)");
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!(s.heights[i] > (i == 0 ? s.base_height : s.heights[i - 1])) || !std::isfinite(s.heights[i]))
        fail(f + ".heights", "must increase from above the slab");
      if (!(s.rigid ? s.masses[i] >= 0 : s.masses[i] > 0) || !std::isfinite(s.masses[i]))
        fail(f + ".masses", s.rigid ? "must be >= 0" : "must be > 0 (a flexible node)");
    }
    if (s.base_mass + s.masses.sum() <= 0) fail(f, "has no mass");
    if (!s.rigid && j > 0 && !d.segments[j - 1].rigid)
      fail(f + ".rigid", "a flexible segment on a flexible one is not supported (the face's rotation would have no inertia)");
    c.local_heights.push_back(s.heights.array() - s.base_height);
    const bool below_joint = j + 1 < c.joints;
    if (s.rigid) {
      c.elastic_offset.push_back(-1);
      c.rotation_index.push_back(-1);
      c.K.emplace_back();
      c.C.emplace_back();
    } else {
      if (s.EI.size() != n) fail(f + ".EI", "one E*I per element");
      for (Eigen::Index i = 0; i < n; ++i)
        if (!(s.EI[i] > 0) || !std::isfinite(s.EI[i])) fail(f + ".EI", "must be > 0");
      c.elastic_offset.push_back(next);
      next += static_cast<int>(n);
      c.rotation_index.push_back(below_joint ? next++ : -1);
      c.K.push_back(segment_stiffness(c.local_heights.back(), s.EI, below_joint));
      Eigen::VectorXd m = Eigen::VectorXd::Zero(c.K.back().rows());
      m.head(n) = s.masses;
      c.C.push_back(d.rayleigh.a0 * Eigen::MatrixXd(m.asDiagonal()) + d.rayleigh.a1 * c.K.back());
    }
    c.points += 1 + static_cast<int>(n);
    c.rest_height.push_back(s.base_height);
    for (Eigen::Index i = 0; i < n; ++i) c.rest_height.push_back(s.heights[i]);
  }
  c.masses.resize(c.points);
  for (int j = 0, i = 0; j < c.joints; ++j) {
    const ChainSegment& s = d.segments[j];
    double m = s.base_mass, S = 0, I = 0;
    c.masses[i++] = s.base_mass;
    for (Eigen::Index k = 0; k < s.masses.size(); ++k) {
      c.masses[i++] = s.masses[k];
      const double z = c.local_heights[j][k];
      m += s.masses[k];
      S += s.masses[k] * z;
      I += s.masses[k] * z * z;
    }
    c.segment_mass.push_back(m);
    c.segment_moment.push_back(S);
    c.segment_inertia.push_back(I);
  }
  c.size = next;
  c.augmented = next + 2 * c.joints;
  for (std::size_t t = 0; t < d.tendons.size(); ++t) {
    const std::string f = "tendons[" + std::to_string(t) + "]";
    for (const ChainAnchor* a : {&d.tendons[t].from, &d.tendons[t].to}) {
      const std::string g = f + (a == &d.tendons[t].from ? ".from" : ".to");
      if (a->segment < -1 || a->segment >= c.joints) fail(g + ".segment", "no such segment (-1 is the ground)");
      if (a->node >= 0 && (a->segment < 0 || a->node >= d.segments[a->segment].heights.size()))
        fail(g + ".node", "no such node on that segment");
    }
    if (d.tendons[t].from.segment >= d.tendons[t].to.segment)
      fail(f + ".to.segment", "must be above the segment of .from");
    if (!(d.tendons[t].stiffness >= 0) || !(d.tendons[t].prestress >= 0)) fail(f, "stiffness and prestress must be >= 0");
  }
  // rest lengths: the anchors' distance with every coordinate zero
  ChainWorkspace w = make_workspace(c);
  const std::vector<Phase> rest(c.joints);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(c.size);
  for (std::size_t t = 0; t < d.tendons.size(); ++t) {
    const Eigen::Vector2d a = anchor_position(c, rest, d.tendons[t].from, zero, w);
    const Eigen::Vector2d b = anchor_position(c, rest, d.tendons[t].to, zero, w);
    const double L = d.tendons[t].free_length > 0 ? d.tendons[t].free_length : (b - a).norm();
    if (!(L > 0)) fail("tendons[" + std::to_string(t) + "]", "its anchors coincide");
    c.rest_length.push_back(L);
  }
  return c;
}

ChainWorkspace make_workspace(const Chain& c) {
  ChainWorkspace w;
  const int anchors = 2 * static_cast<int>(c.data.tendons.size());
  w.jac = Rows::Zero(2 * (c.points + anchors), c.augmented);
  w.points = Eigen::MatrixXd::Zero(c.points, 6);
  w.anchors = Eigen::MatrixXd::Zero(anchors, 4);
  w.frames = Rows::Zero(6 + 3 * c.joints, c.augmented);
  w.slabs = Rows::Zero(c.joints, slab_columns);
  w.lumped = Rows::Zero(3, c.augmented);
  w.column = Eigen::VectorXd::Zero(c.augmented);
  w.coupling = Eigen::VectorXd::Zero(c.augmented);
  w.mass = Eigen::MatrixXd::Zero(c.augmented, c.augmented);
  w.force = Eigen::VectorXd::Zero(c.augmented);
  w.applied = Eigen::VectorXd::Zero(c.size);
  w.reduced = Eigen::MatrixXd::Zero(c.augmented, c.augmented);
  w.rhs = Eigen::VectorXd::Zero(c.augmented);
  w.solution = Eigen::VectorXd::Zero(c.augmented);
  w.free.reserve(c.augmented);
  w.fixed.reserve(c.augmented);
  return w;
}

ChainAtRest chain_at_rest(const Chain& c) {
  const int J = c.joints, n = c.size, ne = n - J;
  ChainAtRest out{Eigen::MatrixXd::Zero(ne, ne), Eigen::MatrixXd::Zero(ne, ne), Eigen::MatrixXd::Zero(ne, ne),
                  Eigen::VectorXd::Zero(ne)};
  if (ne == 0) return out;
  ChainWorkspace w = make_workspace(c);
  w.per_point = true;  // every mass point's own Jacobian and bias
  const std::vector<Phase> closed(J);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  kinematics(c, closed, zero, zero, n, w);
  for (int i = 0; i < c.points; ++i)
    for (int k = 0; k < ne; ++k) out.f[k] -= point_mass(c, i) * w.jac(2 * i, J + k);
  out.M = chain_mass_at_rest(c, closed).bottomRightCorner(ne, ne);
  // Gravity's Hessian g sum m_i d2y_i/dq2 =: G: at rest with rates v the
  // points' vertical bias accelerations are v'(d2y_i/dq2)v, so g sum m_i
  // bias_y,i(v) = v'G v, and G(k, l) follows by polarisation from
  // v = e_k, e_l and e_k + e_l (exact: a quadratic form).
  auto weighted_bias = [&](int k, int l) {
    Eigen::VectorXd v = zero;
    v[J + k] += 1.0;
    v[J + l] += 1.0;
    kinematics(c, closed, zero, v, 0, w);
    double sum = 0;
    for (int i = 0; i < c.points; ++i) sum += point_mass(c, i) * w.points(i, 5);
    return c.data.g * sum;
  };
  Eigen::VectorXd diagonal(ne);
  for (int k = 0; k < ne; ++k) diagonal[k] = 0.25 * weighted_bias(k, k);  // v = 2 e_k
  for (int k = 0; k < ne; ++k) {
    out.K(k, k) += diagonal[k];
    for (int l = k + 1; l < ne; ++l) {
      const double G = 0.5 * (weighted_bias(k, l) - diagonal[k] - diagonal[l]);
      out.K(k, l) += G;
      out.K(l, k) += G;
    }
  }
  for (int j = 0; j < J; ++j) {
    const int o = c.elastic_offset[j];
    if (o < 0) continue;
    const Eigen::Index m = c.K[j].rows();
    out.K.block(o - J, o - J, m, m) += c.K[j];
    out.C.block(o - J, o - J, m, m) += c.C[j];
  }
  return out;
}

Eigen::MatrixXd chain_mass_at_rest(const Chain& c, ChainPhases phases) {
  const int n = c.size;
  ChainWorkspace w = make_workspace(c);
  w.per_point = true;  // every mass point's own Jacobian
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  kinematics(c, phases, zero, zero, n, w);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < c.points; ++i) {
    const double m = point_mass(c, i);
    for (int k = 0; k < n; ++k)
      for (int l = 0; l < n; ++l)
        M(k, l) += m * (w.jac(2 * i, k) * w.jac(2 * i, l) + w.jac(2 * i + 1, k) * w.jac(2 * i + 1, l));
  }
  return M;
}

void chain_acceleration(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                        Eigen::Ref<const Eigen::VectorXd> q_dot, Eigen::Ref<Eigen::VectorXd> q_ddot, ChainWorkspace& w,
                        ChainPower* power) {
  accelerate(c, phases, a, q, q_dot, q_ddot, false, w, power);
}

void chain_reactions(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                     Eigen::Ref<const Eigen::VectorXd> q_dot, std::span<JointReaction> out,
                     Eigen::Ref<Eigen::VectorXd> q_ddot, ChainWorkspace& w, std::span<CornerAcceleration> corners) {
  check_sizes(c, phases, q, q_dot, q_ddot);
  if (rigid_top_applies(c, phases, w)) {
    rigid_top(c, phases, a, q, q_dot, q_ddot, w, nullptr, out, corners);
    return;
  }
  accelerate(c, phases, a, q, q_dot, q_ddot, true, w);
  // lambda_c = M_cf q_f'' - Q_c: the generalised force of constraint c
  auto lambda = [&](int col) {
    double v = -w.force[col];
    for (std::size_t i = 0; i < w.free.size(); ++i) v += w.mass(col, w.free[i]) * w.solution[i];
    return v;
  };
  for (int j = 0; j < c.joints; ++j) {
    out[j].V = lambda(c.size + 2 * j);
    out[j].N = lambda(c.size + 2 * j + 1);
    out[j].M = closed(phases[j]) ? -lambda(j) : 0.0;  // the face's moment on the part above is -M
  }
  if (corners.empty()) return;
  // Closed joint j rocking about s at theta_j = theta_j' = 0: its rotation
  // about the corner (s B, 0) moves everything as the rotation about its
  // centre (coordinate j) with the centre lifted s B per radian (coordinate
  // d_y), t = e_j + s B e_dy, while the free coordinates f and the bias are
  // the closed system's. With b = M_ft, the Schur complement gives
  //   theta_j'' = (t'Q - b'M_ff^-1 Q_f) / (t'M t - b'M_ff^-1 b),
  // M_ff^-1 Q_f being the free q'' just solved.
  const int nf = static_cast<int>(w.free.size());
  for (int j = 0; j < c.joints; ++j) {
    corners[j] = {};
    if (!closed(phases[j])) continue;
    const int dy = c.size + 2 * j + 1;
    Eigen::VectorXd &b0 = w.column, &b1 = w.coupling;  // M_fj, M_f,dy
    for (int i = 0; i < nf; ++i) {
      b0[i] = w.mass(j, w.free[i]);
      b1[i] = w.mass(dy, w.free[i]);
    }
    double b0x = 0, b1x = 0;  // M_jf x_f, M_dy,f x_f
    for (int i = 0; i < nf; ++i) {
      b0x += b0[i] * w.solution[i];
      b1x += b1[i] * w.solution[i];
    }
    // b'M_ff^-1 b for b = b0 + s B b1, from b0'M_ff^-1 b0, b0'M_ff^-1 b1, b1'M_ff^-1 b1
    double b0y0 = 0, b0y1 = 0, b1y1 = 0;
    // M_ff^-1 b0 and M_ff^-1 b1, the latter in w.lumped's first row (scratch
    // of the assembly, done by now)
    double* z = w.rhs.data();
    double* z1 = &w.lumped(0, 0);
    for (int i = 0; i < nf; ++i) {
      z[i] = b0[i];
      z1[i] = b1[i];
    }
    solve_factored(w, z, z1);
    for (int i = 0; i < nf; ++i) {
      b0y0 += b0[i] * z[i];
      b0y1 += b1[i] * z[i];
    }
    for (int i = 0; i < nf; ++i) b1y1 += b1[i] * z1[i];
    const double B = c.data.segments[j].half_width;
    for (Pivot p : pivots) {
      const double sB = sign(p) * B;
      const double num = w.force[j] + sB * w.force[dy] - (b0x + sB * b1x);
      const double den = w.mass(j, j) + 2.0 * sB * w.mass(dy, j) + sB * sB * w.mass(dy, dy) -
                         (b0y0 + 2.0 * sB * b0y1 + sB * sB * b1y1);
      (p == Pivot::left ? corners[j].left : corners[j].right) = sign(p) * num / den;
      (p == Pivot::left ? corners[j].left_gain : corners[j].right_gain) = -1.0 / den;
    }
  }
}

bool chain_rigid_top(const Chain& c, ChainPhases phases, const ChainWorkspace& w) {
  return static_cast<int>(phases.size()) == c.joints && rigid_top_applies(c, phases, w);
}

double uplift_guard(const Chain& c, int joint, Pivot s, const JointReaction& r) {
  return sign(s) * r.M - r.N * c.data.segments[joint].half_width;
}

double friction_demand(const JointReaction& r) {
  return r.N > 0 ? std::abs(r.V) / r.N : std::numeric_limits<double>::infinity();
}

double corner_acceleration(const Chain& c, ChainPhases phases, int joint, Pivot s, GroundAcceleration a,
                           Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w) {
  std::vector<Phase> trial(phases.begin(), phases.end());
  trial[joint] = Phase::rocking(s);
  Eigen::VectorXd q0 = q, v0 = q_dot, acc(c.size);
  q0[joint] = 0.0;
  v0[joint] = 0.0;
  accelerate(c, trial, a, q0, v0, acc, false, w);
  return sign(s) * acc[joint];
}

namespace {

// The velocities of the mass points before an impact (with the kinematics
// before) and the scale of the impulses, sum m |v-|: what every candidate
// outcome of one impact shares.
struct BeforeImpact {
  Eigen::MatrixXd v;
  double momentum = 0;
};
BeforeImpact before_impact(const Chain& c, ChainPhases before, Eigen::Ref<const Eigen::VectorXd> q,
                           Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w) {
  kinematics(c, before, q, q_dot, c.size, w);
  BeforeImpact out{w.points.middleCols(2, 2), 0.0};
  for (int i = 0; i < c.points; ++i) out.momentum += point_mass(c, i) * out.v.row(i).norm();
  return out;
}

ImpactCandidate impact_with(const Chain& c, ChainPhases before, int joint, ChainPhases after,
                            Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot,
                            const BeforeImpact& b, ChainWorkspace& w);

}  // namespace

ImpactCandidate impact_into(const Chain& c, ChainPhases before, int joint, ChainPhases after,
                            Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot) {
  if (static_cast<int>(before.size()) != c.joints || static_cast<int>(after.size()) != c.joints || q.size() != c.size ||
      q_dot.size() != c.size || joint < 0 || joint >= c.joints || !before[joint].is_rocking())
    throw std::invalid_argument("chain impact: one phase per joint, and the impacting joint rocking");
  ChainWorkspace w = make_workspace(c);
  w.per_point = true;  // the momenta below are summed point by point
  return impact_with(c, before, joint, after, q, q_dot, before_impact(c, before, q, q_dot, w), w);
}

namespace {

ImpactCandidate impact_with(const Chain& c, ChainPhases before, int joint, ChainPhases after,
                            Eigen::Ref<const Eigen::VectorXd> q, Eigen::Ref<const Eigen::VectorXd> q_dot,
                            const BeforeImpact& b, ChainWorkspace& w) {
  const Eigen::MatrixXd& v_before = b.v;
  const double momentum = b.momentum;
  // p_k = sum m v- . dp/dq_k with the kinematics after (augmented)
  partition(c, after, true, w);
  kinematics(c, after, q, q_dot, c.augmented, w);
  assemble_equations(c, after, GroundAcceleration{}, q, q_dot, c.augmented, w);
  Eigen::VectorXd p = Eigen::VectorXd::Zero(c.augmented);
  for (int i = 0; i < c.points; ++i) {
    const double m = point_mass(c, i);
    for (int k = 0; k < c.augmented; ++k)
      p[k] += m * (w.jac(2 * i, k) * v_before(i, 0) + w.jac(2 * i + 1, k) * v_before(i, 1));
  }
  for (std::size_t i = 0; i < w.free.size(); ++i) w.rhs[i] = p[w.free[i]];
  solve_free(w);
  ImpactCandidate out;
  out.phases.assign(after.begin(), after.end());
  out.q_dot = Eigen::VectorXd::Zero(c.size);
  for (std::size_t i = 0; i < w.free.size(); ++i) out.q_dot[w.free[i]] = w.solution[i];
  auto impulse = [&](int col) {  // p+_c - p-_c, p+ = M_cf q_f'+
    double v = -p[col];
    for (std::size_t i = 0; i < w.free.size(); ++i) v += w.mass(col, w.free[i]) * w.solution[i];
    return v;
  };
  out.impulse.resize(c.joints);
  out.refused.assign(static_cast<std::size_t>(c.joints), ImpactCandidate::Refusal::none);
  const double tol = 1e-10 * momentum;
  for (int j = 0; j < c.joints; ++j) {
    JointReaction& r = out.impulse[j];
    r.V = impulse(c.size + 2 * j);
    r.N = impulse(c.size + 2 * j + 1);
    r.M = closed(after[j]) ? -impulse(j) : 0.0;
    const double B = c.data.segments[j].half_width;
    if (j == 0 && c.data.base_held) continue;  // a fixed base takes any impulse
    const bool opened = !closed(after[j]) && (j == joint || closed(before[j]));
    using enum ImpactCandidate::Refusal;
    ImpactCandidate::Refusal refused = none;
    if (r.N < -tol) refused = tensile;
    else if (closed(after[j]) && std::abs(r.M) > B * r.N + B * tol) refused = past_corner;
    else if (opened && after[j].sign() * out.q_dot[j] < -1e-12 * std::abs(q_dot[joint])) refused = shutting;
    out.refused[static_cast<std::size_t>(j)] = refused;
  }
  return out;
}

}  // namespace

std::string refusal_words(ImpactCandidate::Refusal r, int joint) {
  switch (r) {
    case ImpactCandidate::Refusal::none: return "joint " + std::to_string(joint) + " admissible";
    case ImpactCandidate::Refusal::tensile: return "a tensile impulse at joint " + std::to_string(joint);
    case ImpactCandidate::Refusal::past_corner: return "the resultant past a corner of joint " + std::to_string(joint);
    case ImpactCandidate::Refusal::shutting: return "joint " + std::to_string(joint) + " opened but moving shut";
  }
  return "?";
}

ImpactOutcome chain_impact(const Chain& c, ChainPhases before, int joint, Eigen::Ref<const Eigen::VectorXd> q,
                           Eigen::Ref<const Eigen::VectorXd> q_dot, double restitution) {
  ImpactOutcome out;
  if (joint < 0 || joint >= c.joints || static_cast<int>(before.size()) != c.joints || !before[joint].is_rocking())
    throw std::invalid_argument("chain impact: one phase per joint, and the impacting joint rocking");
  const Pivot s = *before[joint].pivot();
  if (restitution >= 0) {  // theta_j'+ = r theta_j'-, the rest continuous
    out.status = ImpactStatus::unique;
    out.phases.assign(before.begin(), before.end());
    out.phases[joint] = Phase::rocking(opposite(s));
    out.q_dot = q_dot;
    out.q_dot[joint] = restitution * q_dot[joint];
    return out;
  }
  // Joint j continues about -s or closes; every other closed joint stays
  // closed or opens about either corner (impact-induced uplift); the joints
  // already rocking keep their pivots (theta != 0 there). Every combination
  // is examined, and the admissible ones (impact_into's `consistent()`)
  // counted, up to max_impact_outcomes of them.
  std::vector<int> others;  // the closed joints that may open
  for (int k = 0; k < c.joints; ++k)
    if (k != joint && closed(before[k]) && !(k == 0 && c.data.base_held)) others.push_back(k);
  out.may_open = static_cast<int>(others.size());
  std::size_t combinations = 2;
  for (std::size_t i = 0; i < others.size(); ++i) {
    if (combinations * 3 > max_impact_outcomes) {
      out.status = ImpactStatus::beyond_search;
      return out;
    }
    combinations *= 3;
  }
  std::vector<std::size_t> good;
  std::vector<Phase> after(before.begin(), before.end());
  ChainWorkspace w = make_workspace(c);
  w.per_point = true;  // the momenta are summed point by point
  const BeforeImpact b = before_impact(c, before, q, q_dot, w);
  for (std::size_t code = 0; code < combinations; ++code) {
    std::size_t digits = code;
    after[joint] = digits % 2 == 0 ? Phase::rocking(opposite(s)) : Phase::full_contact();
    digits /= 2;
    for (int k : others) {
      const std::size_t d = digits % 3;
      digits /= 3;
      after[k] = d == 0 ? Phase::full_contact() : Phase::rocking(d == 1 ? Pivot::right : Pivot::left);
    }
    out.candidates.push_back(impact_with(c, before, joint, after, q, q_dot, b, w));
    if (out.candidates.back().consistent()) good.push_back(out.candidates.size() - 1);
  }
  if (good.size() == 1) {
    out.status = ImpactStatus::unique;
    out.phases = out.candidates[good[0]].phases;
    out.q_dot = out.candidates[good[0]].q_dot;
    for (int k = 0; k < c.joints; ++k)
      if (k != joint && closed(before[k]) && !closed(out.phases[k])) out.uplifted.push_back(k);
  } else {
    out.status = good.empty() ? ImpactStatus::none : ImpactStatus::non_unique;
  }
  return out;
}

ChainEnergy chain_energy(const Chain& c, ChainPhases phases, Eigen::Ref<const Eigen::VectorXd> q,
                         Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w) {
  kinematics(c, phases, q, q_dot, 0, w);
  ChainEnergy e;
  for (int j = 0, first = 0; j < c.joints; ++j) {
    const int count = 1 + static_cast<int>(c.local_heights[j].size());
    if (lumped(w)) {
      // v_i = O' + psi' perp(R r_i) + R r_i', |perp(R r_i)|^2 = |r_i|^2,
      // perp(R r_i).R r_i' = z_i u_i'; y_i - y_rest,i = O_y - h + z_i (cos psi
      // - 1) - u_i sin psi, cos psi - 1 = -sin^2 psi / (1 + cos psi)
      const double m = c.segment_mass[j], S = c.segment_moment[j], om = w.slabs(j, 6);
      const double cs = w.slabs(j, 2), sn = w.slabs(j, 3), vx = w.slabs(j, 4), vy = w.slabs(j, 5);
      const double U = w.slabs(j, slab_U), Ud = w.slabs(j, slab_U_dot);
      double udot2 = 0;  // sum m u'^2
      if (const int eo = c.elastic_offset[j]; eo >= 0)
        for (Eigen::Index i = 0; i < c.local_heights[j].size(); ++i)
          udot2 += c.masses[first + 1 + i] * q_dot[eo + i] * q_dot[eo + i];
      e.kinetic += 0.5 * m * (vx * vx + vy * vy) + om * (vx * (S * cs - U * sn) - vy * (S * sn + U * cs)) +
                   Ud * (vx * cs - vy * sn) + 0.5 * om * om * (c.segment_inertia[j] + w.slabs(j, slab_uu)) +
                   om * w.slabs(j, slab_zu_dot) + 0.5 * udot2;
      e.gravity += c.data.g * (m * (w.slabs(j, 1) - c.data.segments[j].base_height) - S * sn * sn / (1.0 + cs) - U * sn);
    } else {
      for (int i = first; i < first + count; ++i) {
        const double m = point_mass(c, i);
        e.kinetic += 0.5 * m * (w.points(i, 2) * w.points(i, 2) + w.points(i, 3) * w.points(i, 3));
        e.gravity += m * c.data.g * (w.points(i, 1) - c.rest_height[i]);
      }
    }
    first += count;
  }
  for (int j = 0; j < c.joints; ++j) {
    const int o = c.elastic_offset[j];
    if (o < 0) continue;
    const int n = static_cast<int>(c.K[j].rows());
    e.elastic += 0.5 * q.segment(o, n).dot(c.K[j] * q.segment(o, n));
  }
  for (int t = 0; t < static_cast<int>(c.data.tendons.size()); ++t) {
    const ChainTendon& td = c.data.tendons[t];
    const TendonState st = tendon_state(c, t, c.size, w, nullptr);
    // int_0^e max(0, P0 + k e) de
    const double slack = td.stiffness > 0 ? -td.prestress / td.stiffness : -std::numeric_limits<double>::infinity();
    const double x = std::max(st.e, slack);
    e.tendons += td.prestress * x + 0.5 * td.stiffness * x * x;
  }
  return e;
}

ChainPower chain_power(const Chain& c, ChainPhases phases, GroundAcceleration a, Eigen::Ref<const Eigen::VectorXd> q,
                       Eigen::Ref<const Eigen::VectorXd> q_dot, ChainWorkspace& w) {
  kinematics(c, phases, q, q_dot, 0, w);
  return power_of(c, a, q_dot, w);
}

double tendon_elongation(const Chain& c, ChainPhases phases, int k, Eigen::Ref<const Eigen::VectorXd> q,
                         ChainWorkspace& w) {
  kinematics(c, phases, q, q, 0, w);  // positions only: the velocities (here q) do not enter e
  return tendon_state(c, k, 0, w, nullptr).e;
}

Eigen::Vector2d anchor_position(const Chain& c, ChainPhases phases, const ChainAnchor& p,
                                Eigen::Ref<const Eigen::VectorXd> q, ChainWorkspace&) {
  if (p.segment < 0) return {p.x, p.z};
  // kinematics' frames, positions only (the same arithmetic): the face,
  // the pivot and the slab frame of each segment up to the anchor's.
  struct Place {
    double ox = 0, oy = 0, psi = 0, c = 1, s = 0;
  };
  const auto from = [](const Place& f, double x, double z, double dpsi) {
    Place g{f.ox + (x * f.c + z * f.s), f.oy + (-x * f.s + z * f.c), f.psi + dpsi, f.c, f.s};
    if (dpsi != 0.0) {  // cos(psi + 0) = cos(psi) exactly
      const CosSin r = cos_sin(g.psi);
      g.c = r.c;
      g.s = r.s;
    }
    return g;
  };
  Place face, seg;  // the ground
  for (int j = 0; j <= p.segment; ++j) {
    if (j > 0) {  // segment j-1's top node, turning with its phi
      const int n = static_cast<int>(c.data.segments[j - 1].heights.size());
      const int eb = c.elastic_offset[j - 1], pcol = c.rotation_index[j - 1];
      face = from(seg, eb >= 0 ? q[eb + n - 1] : 0.0, c.local_heights[j - 1][n - 1], pcol >= 0 ? q[pcol] : 0.0);
    }
    const double cx = closed(phases[j]) ? 0.0 : pivot_sign(phases[j]) * c.data.segments[j].half_width;
    const Place pivot = from(face, cx, 0.0, closed(phases[j]) ? 0.0 : q[j]);
    seg = from(pivot, -cx, 0.0, 0.0);
  }
  double x = p.x, z = p.z;
  if (p.node >= 0) {
    z = c.local_heights[p.segment][p.node];
    if (c.elastic_offset[p.segment] >= 0) x += q[c.elastic_offset[p.segment] + p.node];
  }
  return {seg.ox + (x * seg.c + z * seg.s), seg.oy + (-x * seg.s + z * seg.c)};
}

}  // namespace rocking
