// Exact steps of a linear system with a piecewise-linear input, z' = A z + b a(t)
// (the full-contact phase, Eq. 1, under a record). With A = V diag(lambda) V^-1,
// w = V^-1 z and beta = V^-1 b, over a step from t0 with a(t0 + tau) = a0 + a' tau,
// each w_j solves w' = lambda w + beta (a0 + a' tau) exactly:
//   w(tau) = e^(x) w0 + beta [(e^x - 1) a0 / lambda + (e^x - 1 - x) a' / lambda^2],  x = lambda tau
// (the first-order-hold discretisation; for one mode, the piecewise-exact
// method of Nigam & Jennings, BSSA 59, 1969). For small x the differences
// e^x - 1 - x lose digits, but only absolute round-off of size
// eps |beta a'| / |lambda|^2, far below the state's own size.
// Steps of the usual length (a record's sample interval, or an equal part of
// it) reuse real matrices at the step's guard samples,
// z_k = Phi_k z0 + G0_k a0 + G1_k a', so such a step costs a few small
// matrix-vector products; other lengths use the eigen form. A system beyond
// the unrolled sizes whose A splits into independent blocks (a structure in
// its fixed-base modes: one block (q_i, q_i') per mode) is solved block by
// block, so that a sample costs the sum of the blocks' squares, not the
// square of their sum.
// Quadratures (LinearSystem::quadratures), W' = z' Q z + a(t) c' z, are
// integrated in the same eigen form: with w_j = E_j alpha_j + p_j + q_j tau
// (E_j = e^(lambda_j tau), the particular solution p + q tau of the ramp,
// alpha = w0 - p) and z = V w, z' Q z = w' G w with G = V^T Q V, so the
// integral is a sum of integrals of e^(mu s) and s e^(mu s) (mu = lambda_j,
// or lambda_j + lambda_k) and of polynomials, each in closed form:
//   int_0^tau e^(mu s) ds = tau phi1(mu tau),  phi1(x) = (e^x - 1) / x,
//   int_0^tau s e^(mu s) ds = tau^2 phi2(mu tau),  phi2(x) = ((x - 1) e^x + 1) / x^2,
// by their series for |x| <= 1/2. Over the usual step length the integral is
// a quadratic form in (z0, a0, a'), cached as its matrix.
module;
#include <rocking/eigen.hpp>
#include <rocking/static_size.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <string>
#include <vector>
module rocking.integrator;

namespace rocking::ode {

namespace {

using Complex = std::complex<double>;
// Guard samples inside each step (incl. its end): with a sample spacing at
// most 16 (steps are cut to fit); see guard_samples.
constexpr int max_samples_per_step = 16;

// The independent blocks of z' = A z + b a(t): the connected components of
// A's pattern (i and j joined when A(i, j) or A(j, i) is nonzero), each as
// its indices in increasing order. A structure in nodal coordinates is one
// block; in its fixed-base modes, one block of (q_i, q_i') per mode.
std::vector<std::vector<Eigen::Index>> independent_blocks(const Eigen::MatrixXd& A) {
  // (A stands for the pattern of every coupling: the system's matrix and the
  // quadratures' Q.)
  const auto m = static_cast<std::size_t>(A.rows());
  std::vector<std::size_t> root(m);  // union-find with path halving
  for (std::size_t i = 0; i < m; ++i) root[i] = i;
  auto find = [&](std::size_t i) {
    while (root[i] != i) i = root[i] = root[root[i]];
    return i;
  };
  for (std::size_t j = 0; j < m; ++j)
    for (std::size_t i = 0; i < m; ++i)
      if (A(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) != 0.0) root[find(i)] = find(j);
  std::vector<std::vector<Eigen::Index>> blocks;
  std::vector<std::size_t> block_of(m, m);  // m: none yet
  for (std::size_t i = 0; i < m; ++i) {
    std::size_t& b = block_of[find(i)];
    if (b == m) {
      b = blocks.size();
      blocks.emplace_back();
    }
    blocks[b].push_back(static_cast<Eigen::Index>(i));
  }
  return blocks;
}

// (e^x - 1) / x and ((x - 1) e^x + 1) / x^2, given e^x; their series
// sum x^n / (n + 1)! and sum x^n / (n! (n + 2)) near 0.
// (Magnitudes compared squared, and u / x as u conj(x) / |x|^2: no hypot,
// no library division, in the inner loop of the quadratures.)
Complex over(Complex u, Complex x) { return u * std::conj(x) / std::norm(x); }

Complex phi1(Complex x, Complex ex) {
  if (std::norm(x) > 0.25) return over(ex - 1.0, x);
  Complex term = 1.0, sum = 1.0;
  for (int n = 1; n < 40 && std::norm(term) > 1e-36 * std::norm(sum); ++n) {
    term *= x / static_cast<double>(n + 1);
    sum += term;
  }
  return sum;
}

Complex phi2(Complex x, Complex ex) {
  if (std::norm(x) > 0.25) return over((x - 1.0) * ex + 1.0, x * x);
  Complex power = 1.0, sum = 0.5;
  for (int n = 1; n < 40; ++n) {
    power *= x / static_cast<double>(n);
    const Complex term = power / static_cast<double>(n + 2);
    sum += term;
    if (std::norm(term) <= 1e-36 * std::norm(sum)) break;
  }
  return sum;
}

// The exact solution of one block, z' = A z + b a(t), over a step from z0
// with a(t0 + tau) = a0 + slope tau: in the eigen form at any tau, and from
// cached real matrices at the guard samples of the usual step length.
class BlockSolution {
  struct Quad;

 public:
  BlockSolution(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
    const Eigen::Index m = A.rows();
    Eigen::EigenSolver<Eigen::MatrixXd> es(A);
    if (es.info() != Eigen::Success)
      throw IntegrationError(IntegrationError::Kind::backend, 0, "no eigendecomposition of the linear system");
    lambda_ = es.eigenvalues();
    V_ = es.eigenvectors();
    const Eigen::FullPivLU<Eigen::MatrixXcd> lu(V_);
    const double smallest = lambda_.cwiseAbs().minCoeff(), largest = lambda_.cwiseAbs().maxCoeff();
    if (!lu.isInvertible() || !(smallest > 1e-12 * largest))
      throw IntegrationError(IntegrationError::Kind::backend, 0, "the linear system is singular or defective");
    V_inv_ = lu.inverse();
    beta_ = V_inv_ * b.cast<Complex>();
    inv_lambda_ = lambda_.cwiseInverse();
    choose_modes();
    z0_.setZero(m);
    w0_.setZero(m);
  }

  Eigen::Index size() const { return z0_.size(); }

  // A quadrature's terms on this block (its part of Q and c; either may be empty).
  void add_quadrature(const Eigen::MatrixXd& Q, const Eigen::VectorXd& c) {
    Quad q;
    if (Q.size() > 0 && !Q.isZero(0)) q.G = V_.transpose() * Q.cast<Complex>() * V_;
    if (c.size() > 0 && !c.isZero(0)) q.h = V_.transpose() * c.cast<Complex>();
    quads_.push_back(std::move(q));
  }

  // Per mode over [0, tau]: E = e^(lambda tau), J0 = int e^(lambda s) ds and
  // J1 = int s e^(lambda s) ds; and of a pair of modes, int e^((lambda_j + lambda_k) s) ds.
  struct ModeIntegrals {
    Eigen::VectorXcd E, J0, J1;
  };
  ModeIntegrals mode_integrals(double tau) const {
    const Eigen::Index m = z0_.size();
    ModeIntegrals t{Eigen::VectorXcd(m), Eigen::VectorXcd(m), Eigen::VectorXcd(m)};
    for (Eigen::Index j = 0; j < m; ++j) {
      const Complex x = lambda_[j] * tau;
      t.E[j] = std::exp(x);
      t.J0[j] = tau * phi1(x, t.E[j]);
      t.J1[j] = tau * tau * phi2(x, t.E[j]);
    }
    return t;
  }
  Complex pair_integral(const ModeIntegrals& t, Eigen::Index j, Eigen::Index k, double tau) const {
    return tau * phi1((lambda_[j] + lambda_[k]) * tau, t.E[j] * t.E[k]);
  }

  // Each quadrature's integral over [0, tau] of the current step, in closed
  // form, added to sums[i].
  void add_integrals(double tau, double* sums) const {
    bool any_G = false, any = false;
    for (const Quad& q : quads_) {
      any_G = any_G || q.G.size() > 0;
      any = any || q.G.size() > 0 || q.h.size() > 0;
    }
    if (!any) return;
    const Eigen::Index m = z0_.size();
    Eigen::VectorXcd alpha(m), p(m), r(m);
    const Eigen::VectorXcd w0 = V_inv_ * z0_.cast<Complex>();
    for (Eigen::Index j = 0; j < m; ++j) {
      r[j] = -beta_[j] * slope_ * inv_lambda_[j];       // q_j
      p[j] = (r[j] - beta_[j] * a0_) * inv_lambda_[j];  // p_j
      alpha[j] = w0[j] - p[j];
    }
    const ModeIntegrals t = mode_integrals(tau);
    const Eigen::VectorXcd &J0 = t.J0, &J1 = t.J1;
    // alpha_j alpha_k int e^((lambda_j + lambda_k) s) ds, symmetric: its upper triangle
    Eigen::MatrixXcd pairs;
    if (any_G) {
      pairs.resize(m, m);
      for (Eigen::Index k = 0; k < m; ++k)
        for (Eigen::Index j = 0; j <= k; ++j)
          pairs(j, k) = alpha[j] * alpha[k] * pair_integral(t, j, k, tau);
    }
    for (std::size_t i = 0; i < quads_.size(); ++i) {
      const Quad& q = quads_[i];
      Complex sum = 0.0;
      if (q.G.size() > 0) {
        for (Eigen::Index k = 0; k < m; ++k) {
          for (Eigen::Index j = 0; j < k; ++j) sum += 2.0 * q.G(j, k) * pairs(j, k);
          sum += q.G(k, k) * pairs(k, k);
        }
        const Eigen::VectorXcd Gp = q.G * p, Gr = q.G * r;
        for (Eigen::Index j = 0; j < m; ++j) sum += 2.0 * alpha[j] * (J0[j] * Gp[j] + J1[j] * Gr[j]);
        sum += tau * (p.transpose() * Gp)(0) + tau * tau * (p.transpose() * Gr)(0) +
               tau * tau * tau / 3.0 * (r.transpose() * Gr)(0);
      }
      if (q.h.size() > 0)
        for (Eigen::Index j = 0; j < m; ++j)
          sum += q.h[j] * (alpha[j] * (a0_ * J0[j] + slope_ * J1[j]) + a0_ * p[j] * tau +
                           (a0_ * r[j] + slope_ * p[j]) * tau * tau / 2.0 + slope_ * r[j] * tau * tau * tau / 3.0);
      sums[i] += sum.real();
    }
  }

  // Quadrature q's integral over a step of length tau as the symmetric matrix
  // N of a quadratic form in xi = (z0, a0, a'): add_integrals' terms with
  // alpha, p and q (r here) written as linear maps of xi,
  //   w0 = V^-1 z0,  p = -beta (a0 / lambda + a' / lambda^2),  r = -beta a' / lambda,  alpha = w0 - p.
  Eigen::MatrixXd quadratic_form(const Quad& q, double tau) const {
    const Eigen::Index m = z0_.size(), K = m + 2;
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(K, K);
    if (q.G.size() == 0 && q.h.size() == 0) return N;
    Eigen::MatrixXcd Ap = Eigen::MatrixXcd::Zero(m, K), Ar = Eigen::MatrixXcd::Zero(m, K), Aa(m, K);
    for (Eigen::Index j = 0; j < m; ++j) {
      Ap(j, m) = -beta_[j] * inv_lambda_[j];
      Ap(j, m + 1) = -beta_[j] * inv_lambda_[j] * inv_lambda_[j];
      Ar(j, m + 1) = -beta_[j] * inv_lambda_[j];
    }
    const ModeIntegrals t = mode_integrals(tau);
    const Eigen::VectorXcd &J0 = t.J0, &J1 = t.J1;
    Aa.leftCols(m) = V_inv_;
    Aa.rightCols(2).setZero();
    Aa -= Ap;
    Eigen::MatrixXcd B = Eigen::MatrixXcd::Zero(K, K);  // N = Re(B + B^T) / 2
    if (q.G.size() > 0) {
      Eigen::MatrixXcd GP(m, m);  // G o P, P_jk = tau phi1((lambda_j + lambda_k) tau)
      for (Eigen::Index k = 0; k < m; ++k)
        for (Eigen::Index j = 0; j < m; ++j)
          GP(j, k) = q.G(j, k) * pair_integral(t, j, k, tau);
      B += Aa.transpose() * GP * Aa;
      B += 2.0 * Aa.transpose() * (J0.asDiagonal() * (q.G * Ap) + J1.asDiagonal() * (q.G * Ar));
      B += tau * Ap.transpose() * q.G * Ap + tau * tau * Ap.transpose() * q.G * Ar +
           tau * tau * tau / 3.0 * Ar.transpose() * q.G * Ar;
    }
    if (q.h.size() > 0) {
      const Eigen::VectorXcd on_a0 = Aa.transpose() * q.h.cwiseProduct(J0) + tau * Ap.transpose() * q.h +
                                     tau * tau / 2.0 * Ar.transpose() * q.h;
      const Eigen::VectorXcd on_slope = Aa.transpose() * q.h.cwiseProduct(J1) +
                                        tau * tau / 2.0 * Ap.transpose() * q.h +
                                        tau * tau * tau / 3.0 * Ar.transpose() * q.h;
      B.col(m) += on_a0;
      B.col(m + 1) += on_slope;
    }
    N = 0.5 * (B + B.transpose()).real();
    return N;
  }

  // Quadrature i's integral over the cached step: xi' N xi, xi = (z0, a0, a').
  double cached_integral(std::size_t i) const {
    const Eigen::MatrixXd& N = quads_[i].N;
    const Eigen::Index m = z0_.size();
    double sum = 0;
    for (Eigen::Index k = 0; k < m + 2; ++k) {
      const double xk = k < m ? z0_[k] : k == m ? a0_ : slope_;
      double column = 0;
      for (Eigen::Index j = 0; j < m; ++j) column += N(j, k) * z0_[j];
      column += N(m, k) * a0_ + N(m + 1, k) * slope_;
      sum += column * xk;
    }
    return sum;
  }
  // A new step from the block's components `at` of z, under a0 + slope tau.
  void start(const double* z, const std::vector<Eigen::Index>& at, double a0, double slope) {
    for (std::size_t i = 0; i < at.size(); ++i) z0_[static_cast<Eigen::Index>(i)] = z[at[i]];
    a0_ = a0;
    slope_ = slope;
    have_w0_ = false;
  }

  // z at sample k of the cached step, unrolled for the block's size
  // (static_size.hpp), in a local array that aliases nothing.
  template <int S>
  void cached_sample(int k, double* z) const {
    const long m = static_or<S>(z0_.size());
    const double* P = phi_[k].data();  // column-major
    const double *g0 = g0_[k].data(), *g1 = g1_[k].data(), *z0 = z0_.data();
    double local[S > 0 ? S : 1];
    double* r = S > 0 ? local : z;
    for (long i = 0; i < m; ++i) r[i] = g0[i] * a0_ + g1[i] * slope_;
    for (long j = 0; j < m; ++j) {
      const double zj = z0[j];
      for (long i = 0; i < m; ++i) r[i] += P[j * m + i] * zj;
    }
    if (S > 0)
      for (long i = 0; i < m; ++i) z[i] = r[i];
  }

  // z(t0 + tau) from the eigen form, in real arithmetic over the chosen modes.
  void state_at(double tau, Eigen::Ref<Eigen::VectorXd> z) {
    if (!have_w0_) {
      // (dot() would conjugate V^-1's row)
      for (const Mode& q : modes_) w0_[q.j] = (V_inv_.row(q.j).transpose().array() * z0_.array()).sum();
      have_w0_ = true;
    }
    z.setZero();
    for (const Mode& q : modes_) {
      Complex e, f0, f1;
      response_terms(q.j, tau, e, f0, f1);
      const Complex w = q.weight * (e * w0_[q.j] + f0 * a0_ + f1 * slope_);
      z += Vr_.col(q.j) * w.real() - Vi_.col(q.j) * w.imag();
    }
  }

  // The real matrices of `count` samples of a step of length h, and each
  // quadrature's over the whole step (its quadratic form in (z0, a0, a')).
  void build_cache(double h, int count) {
    const Eigen::Index m = z0_.size();
    for (Quad& q : quads_) q.N = quadratic_form(q, h);
    Eigen::VectorXcd e(m), f0(m), f1(m);
    for (int k = 0; k < count; ++k) {
      const double tau = h * (k + 1) / count;
      for (Eigen::Index j = 0; j < m; ++j) response_terms(j, tau, e[j], f0[j], f1[j]);
      phi_[k] = (V_ * e.asDiagonal() * V_inv_).real();
      g0_[k] = (V_ * f0).real();
      g1_[k] = (V_ * f1).real();
    }
  }

 private:
  // The modes state_at sums: a real eigenvalue with weight 1, and one of each
  // conjugate pair (Im > 0) with weight 2, since z and the input are real and
  // the partner's term is the conjugate (Re(v w) + Re(conj(v w)) = 2 Re(v w)).
  void choose_modes() {
    long above = 0, below = 0;
    for (Eigen::Index j = 0; j < lambda_.size(); ++j) {
      above += lambda_[j].imag() > 0;
      below += lambda_[j].imag() < 0;
    }
    const bool paired = above == below;  // else (never seen) sum every mode
    modes_.clear();
    for (Eigen::Index j = 0; j < lambda_.size(); ++j) {
      const double im = lambda_[j].imag();
      if (!paired) modes_.push_back({j, 1.0});
      else if (im > 0) modes_.push_back({j, 2.0});
      else if (im == 0) modes_.push_back({j, 1.0});
    }
    Vr_ = V_.real();
    Vi_ = V_.imag();
  }

  // Mode j over tau: e^x, beta (e^x - 1) / lambda, beta (e^x - 1 - x) / lambda^2.
  void response_terms(Eigen::Index j, double tau, Complex& e, Complex& f0, Complex& f1) const {
    const Complex x = lambda_[j] * tau;
    e = std::exp(x);
    f0 = beta_[j] * (e - 1.0) * inv_lambda_[j];
    f1 = beta_[j] * (e - 1.0 - x) * inv_lambda_[j] * inv_lambda_[j];
  }

  struct Mode {
    Eigen::Index j;
    double weight;
  };
  Eigen::VectorXcd lambda_, inv_lambda_, beta_, w0_;
  Eigen::MatrixXcd V_, V_inv_;
  Eigen::MatrixXd Vr_, Vi_;  // V's real and imaginary parts
  std::vector<Mode> modes_;
  Eigen::VectorXd z0_;
  struct Quad {
    Eigen::MatrixXcd G;  // V^T Q V
    Eigen::VectorXcd h;  // V^T c
    Eigen::MatrixXd N;   // over the cached step, in (z0, a0, a')
  };
  std::vector<Quad> quads_;
  Eigen::MatrixXd phi_[max_samples_per_step];
  Eigen::VectorXd g0_[max_samples_per_step], g1_[max_samples_per_step];
  double a0_ = 0, slope_ = 0;
  bool have_w0_ = false;
};

class ExactLinear final : public Integrator {
 public:
  ExactLinear(LinearSystem sys, Options o) : sys_(std::move(sys)), opt_(o) {
    const Eigen::Index m = sys_.A.rows();
    if (sys_.A.cols() != m || sys_.b.size() != m || sys_.first < 0 || sys_.first + m > sys_.size || !sys_.forcing)
      throw IntegrationError(IntegrationError::Kind::backend, 0, "inconsistent linear system");
    // Within the unrolled sizes one product per sample costs less than a
    // few tiny ones: such a system is stepped whole.
    for (const LinearSystem::Quadrature& q : sys_.quadratures)
      if ((q.Q.size() > 0 && (q.Q.rows() != m || q.Q.cols() != m)) || (q.c.size() > 0 && q.c.size() != m) ||
          q.at < 0 || q.at >= sys_.size || (q.at >= sys_.first && q.at < sys_.first + m))
        throw IntegrationError(IntegrationError::Kind::backend, 0, "inconsistent quadrature of the linear system");
    std::vector<std::vector<Eigen::Index>> blocks(1);
    if (m > max_static_size) {
      Eigen::MatrixXd pattern = sys_.A.cwiseAbs();
      for (const LinearSystem::Quadrature& q : sys_.quadratures)
        if (q.Q.size() > 0) pattern += q.Q.cwiseAbs();
      blocks = independent_blocks(pattern);
    } else {
      for (Eigen::Index i = 0; i < m; ++i) blocks.front().push_back(i);
    }
    for (std::vector<Eigen::Index>& at : blocks) {
      BlockSolution solution(sys_.A(at, at), sys_.b(at));
      for (const LinearSystem::Quadrature& q : sys_.quadratures)
        solution.add_quadrature(q.Q.size() > 0 ? Eigen::MatrixXd(q.Q(at, at)) : Eigen::MatrixXd(),
                                q.c.size() > 0 ? Eigen::VectorXd(q.c(at)) : Eigen::VectorXd());
      blocks_.push_back({std::move(at), std::move(solution)});
    }
    quad_start_.setZero(static_cast<Eigen::Index>(sys_.quadratures.size()));
    quad_sums_.assign(sys_.quadratures.size(), 0.0);
    whole_ = blocks_.size() == 1;
    y_.setZero(sys_.size);
    scratch_.setZero(m);
    for (auto& s : samples_) s.setZero(sys_.size);
  }

  void reset(double t, const Eigen::VectorXd& y, Guards guards) override {
    t_ = t_prev_ = t;
    y_ = y;
    h_ = 0;
    samples_valid_ = false;
    for (auto& s : samples_) s = y;  // outside the system the state is constant
    scanner_.reset(std::move(guards), t, y_);
  }

  void set_breakpoints(NextBreakpoint next) override { breakpoints_.set(std::move(next)); }

  StepReport step(double t_limit) override {
    if (t_ >= t_limit) return {Stop::limit, t_};
    if (stats_.steps >= opt_.max_steps)
      throw IntegrationError(IntegrationError::Kind::max_steps, t_, std::to_string(opt_.max_steps) + " steps");
    const auto [bound, bp_ahead] = step_bound(breakpoints_, t_, t_limit);
    // Equal steps up to the bound, none longer than max_step or than
    // max_samples_per_step sample spacings.
    const double span = bound - t_;
    const bool spaced = std::isfinite(opt_.sample_spacing);
    const double longest = std::min(opt_.max_step, spaced ? max_samples_per_step * opt_.sample_spacing
                                                          : std::numeric_limits<double>::infinity());
    const double pieces = std::isfinite(longest) ? std::max(1.0, std::ceil(span / longest - 1e-9)) : 1.0;
    const bool lands = pieces == 1.0;
    const double t_new = lands ? bound : t_ + span / pieces;
    count_ = guard_samples(t_new - t_, opt_.sample_spacing, 1, max_samples_per_step);
    advance_to(t_new);
    if (!y_.allFinite()) throw IntegrationError(IntegrationError::Kind::non_finite_state, t_, "");
    if (GuardScanner::Crossing c{}; scanner_.scan(*this, count_, c)) {
      dense(c.t, y_);
      add_quadratures(c.t - t_prev_, false);
      t_ = c.t;
      samples_valid_ = false;  // the step now ends at the event
      scanner_.restart_at(c, y_);
      ++stats_.events;
      return c.report();
    }
    if (lands) return {bp_ahead ? Stop::breakpoint : Stop::limit, t_};
    return {Stop::step, t_};
  }

  double time() const override { return t_; }
  const Eigen::VectorXd& state() const override { return y_; }
  double previous_time() const override { return t_prev_; }

  void dense(double t, Eigen::Ref<Eigen::VectorXd> y) override {
    y = y_;
    if (h_ == 0) return;  // no step since the reset: the state is all there is
    for (Block& b : blocks_) at_time(b, t - t_prev_, y);
    for (std::size_t i = 0; i < sys_.quadratures.size(); ++i)
      y[sys_.quadratures[i].at] = quad_start_[static_cast<Eigen::Index>(i)];
  }

  const Eigen::VectorXd& sample(int k, int count) override {
    if (!samples_valid_ || count != count_) return Integrator::sample(k, count);
    return samples_[k - 1];
  }
  int sample_count() const override { return count_; }

  Stats stats() const override {
    Stats out = stats_;
    out.guards = scanner_.evaluations();
    return out;
  }
  std::string name() const override { return "exact"; }

 private:
  struct Block {
    std::vector<Eigen::Index> at;  // its components of the system
    BlockSolution solution;
  };

  // One exact step from (t_, y_) to t_new; keeps what dense() and sample() need.
  void advance_to(double t_new) {
    t_prev_ = t_;
    h_ = t_new - t_;
    // a(t) at the step's start is the last step's end value when it ends there
    const double a0 = t_prev_ == forcing_time_ ? forcing_value_ : sys_.forcing(t_prev_);
    forcing_time_ = t_new;
    forcing_value_ = sys_.forcing(t_new);
    const double slope = (forcing_value_ - a0) / h_;
    for (Block& b : blocks_) b.solution.start(y_.data() + sys_.first, b.at, a0, slope);
    for (std::size_t i = 0; i < sys_.quadratures.size(); ++i) {
      const Eigen::Index at = sys_.quadratures[i].at;
      quad_start_[static_cast<Eigen::Index>(i)] = y_[at];
      for (int k = 0; k < count_; ++k) samples_[k][at] = y_[at];
    }
    const bool cached = std::abs(h_ - cached_h_) <= 1e-10 * cached_h_ && count_ == cached_count_;
    if (cached) {
      // The usual step: within 1e-10 of the cached length (consecutive sample
      // times differ by round-off), a shift far below the state's accuracy.
      for (Block& b : blocks_)
        with_static_size(b.solution.size(), [&](auto size) {
          for (int k = 0; k < count_; ++k) {
            if (whole_) {
              b.solution.cached_sample<decltype(size)::value>(k, samples_[k].data() + sys_.first);
            } else {
              b.solution.cached_sample<decltype(size)::value>(k, scratch_.data());
              double* out = samples_[k].data() + sys_.first;
              for (std::size_t i = 0; i < b.at.size(); ++i) out[b.at[i]] = scratch_[static_cast<Eigen::Index>(i)];
            }
          }
        });
    } else {
      // A length that recurs is cached: three steps in a row. The equal parts
      // of the span from an event to the next sample (at most two) do not
      // displace the usual length.
      if (std::abs(h_ - candidate_h_) <= 1e-10 * candidate_h_) {
        if (++candidate_repeats_ >= 3) {
          for (Block& b : blocks_) b.solution.build_cache(h_, count_);
          cached_h_ = h_;
          cached_count_ = count_;
        }
      } else {
        candidate_h_ = h_;
        candidate_repeats_ = 1;
      }
      for (int k = 0; k < count_; ++k)
        for (Block& b : blocks_) at_time(b, h_ * (k + 1) / count_, samples_[k]);
    }
    samples_valid_ = true;
    t_ = t_new;
    y_.segment(sys_.first, sys_.A.rows()) = samples_[count_ - 1].segment(sys_.first, sys_.A.rows());
    add_quadratures(h_, cached);
    ++stats_.steps;
  }

  // The quadratures at tau into the step: their values at its start plus the
  // integrals over [0, tau] (from the cached forms over a usual step).
  void add_quadratures(double tau, bool cached) {
    const std::size_t count = sys_.quadratures.size();
    if (count == 0) return;
    for (std::size_t i = 0; i < count; ++i) quad_sums_[i] = quad_start_[static_cast<Eigen::Index>(i)];
    for (const Block& b : blocks_) {
      if (!cached) b.solution.add_integrals(tau, quad_sums_.data());
      else
        for (std::size_t i = 0; i < count; ++i) quad_sums_[i] += b.solution.cached_integral(i);
    }
    for (std::size_t i = 0; i < count; ++i) y_[sys_.quadratures[i].at] = quad_sums_[i];
  }

  // Block b's components of y at tau into the step, from the eigen form.
  void at_time(Block& b, double tau, Eigen::Ref<Eigen::VectorXd> y) {
    if (whole_) {
      b.solution.state_at(tau, y.segment(sys_.first, sys_.A.rows()));
      return;
    }
    auto z = scratch_.head(b.solution.size());
    b.solution.state_at(tau, z);
    for (std::size_t i = 0; i < b.at.size(); ++i) y[sys_.first + b.at[i]] = z[static_cast<Eigen::Index>(i)];
  }

  LinearSystem sys_;
  Options opt_;
  GuardScanner scanner_;
  std::vector<Block> blocks_;
  bool whole_ = true;          // one block: its values are the system's, in place
  Eigen::VectorXd y_, scratch_;
  Eigen::VectorXd quad_start_;  // the quadratures at the step's start
  std::vector<double> quad_sums_;
  // The state at the step's guard samples (only the system's part changes in a step).
  std::array<Eigen::VectorXd, max_samples_per_step> samples_;
  int count_ = guard_samples(0, std::numeric_limits<double>::infinity(), 1, max_samples_per_step),
      cached_count_ = 0;  // samples of the last step, of the cached length (all blocks alike)
  double cached_h_ = std::numeric_limits<double>::quiet_NaN(), candidate_h_ = std::numeric_limits<double>::quiet_NaN();
  int candidate_repeats_ = 0;
  double t_ = 0, t_prev_ = 0, h_ = 0;
  double forcing_time_ = std::numeric_limits<double>::quiet_NaN(), forcing_value_ = 0;  // a(t) at the last step's end
  bool samples_valid_ = false;
  Breakpoints breakpoints_;
  Stats stats_;
};

}  // namespace

std::unique_ptr<Integrator> make_exact_linear(LinearSystem system, Options options) {
  return std::make_unique<ExactLinear>(std::move(system), options);
}

}  // namespace rocking::ode
