// rocking.simulation:chain_stiff, a partition: the stiff part of a chain's
// equations (MODEL.md 15) for the Rosenbrock-W steps (rocking.integrator's
// LinearSolve), docs/chain.md "Stiff steps". A flexible segment's elastic
// forces are what make the chain stiff: its top node's rotation phi, which a
// segment standing on it turns, has little inertia once that segment rocks
// (turning the face while the part above keeps its angle moves only the
// corner), so its mode is fast. T, standing in for the Jacobian of the
// current phases, is the chain's linear elastic part about rest:
//   q' = v,  M v' = -K x - C v   on the free coordinates (the rocking joints'
// theta and every elastic one), zero on every other component of the state
// (a closed joint's theta and theta', the devices' states, the works),
// with M the mass matrix at rest in those phases (rocking.chain's
// chain_mass_at_rest) and K, C the flexible segments' stiffness and Rayleigh
// damping. Gravity and the velocity terms are left out (a W-method keeps its
// order with any T; they are slow). (I - g T) x = b then reads
//   (M + g C + g^2 K) x_v = M b_v - g K b_q,  x_q = b_q + g x_v
// on the free coordinates and x = b elsewhere: one Cholesky factorisation
// per phases and g, which a step's four stages share (written out: the
// matrices are a few rows, and the solve allocates nothing).
module;
#include <rocking/eigen.hpp>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>
export module rocking.simulation:chain_stiff;
import rocking.chain;

export namespace rocking {

class ChainStiff {
 public:
  explicit ChainStiff(const Chain& c) : c_(&c), n_(c.size) {}

  // x = (I - g T)^-1 b for the phases' T; b and x hold the chain driver's
  // state: q, q', then components T leaves alone.
  void solve(std::span<const Phase> phases, double g, Eigen::Ref<const Eigen::VectorXd> b,
             Eigen::Ref<Eigen::VectorXd> x) {
    x = b;
    const Part& p = part(phases);
    const int nf = static_cast<int>(p.free.size());
    if (&p != last_ || g != last_g_) {
      factorise(p, g);
      last_ = &p;
      last_g_ = g;
    }
    double* r = rhs_.data();
    for (int i = 0; i < nf; ++i) {  // M b_v - g K b_q
      double v = 0;
      for (int k = 0; k < nf; ++k)
        v += p.M(i, k) * b[n_ + p.free[static_cast<std::size_t>(k)]] - g * p.K(i, k) * b[p.free[static_cast<std::size_t>(k)]];
      r[i] = v;
    }
    for (int i = 0; i < nf; ++i) {  // L L' x_v = r
      double v = r[i];
      for (int k = 0; k < i; ++k) v -= L_(i, k) * r[k];
      r[i] = v / L_(i, i);
    }
    for (int i = nf - 1; i >= 0; --i) {
      double v = r[i];
      for (int k = i + 1; k < nf; ++k) v -= L_(k, i) * r[k];
      r[i] = v / L_(i, i);
    }
    for (int i = 0; i < nf; ++i) {
      const int k = p.free[static_cast<std::size_t>(i)];
      x[n_ + k] = r[i];
      x[k] = b[k] + g * r[i];
    }
  }

 private:
  struct Part {
    std::vector<int> free;
    Eigen::MatrixXd M, K, C;  // on the free coordinates
  };

  // The phases as a number: one base-3 digit per joint, its pivot's sign + 1.
  static std::uint64_t key(std::span<const Phase> phases) {
    std::uint64_t k = 0;
    for (const Phase& p : phases) k = 3 * k + static_cast<std::uint64_t>(p.sign() + 1);
    return k;
  }

  const Part& part(std::span<const Phase> phases) {
    const std::uint64_t k = key(phases);
    if (last_ != nullptr && k == last_key_) return *last_;
    last_key_ = k;
    auto it = parts_.find(k);
    if (it == parts_.end()) it = parts_.emplace(k, build(phases)).first;
    last_ = nullptr;  // refactorise for the new phases
    return it->second;
  }

  // L, the Cholesky factor of M + g C + g^2 K (symmetric positive definite:
  // M is, K and C are semi-definite), in L_'s lower triangle.
  void factorise(const Part& p, double g) {
    const int nf = static_cast<int>(p.free.size());
    for (int j = 0; j < nf; ++j)
      for (int i = j; i < nf; ++i) L_(i, j) = p.M(i, j) + g * p.C(i, j) + g * g * p.K(i, j);
    for (int k = 0; k < nf; ++k) {
      double d = L_(k, k);
      for (int q = 0; q < k; ++q) d -= L_(k, q) * L_(k, q);
      d = std::sqrt(d);
      L_(k, k) = d;
      for (int i = k + 1; i < nf; ++i) {
        double v = L_(i, k);
        for (int q = 0; q < k; ++q) v -= L_(i, q) * L_(k, q);
        L_(i, k) = v / d;
      }
    }
  }

  Part build(std::span<const Phase> phases) const {
    const Chain& c = *c_;
    Part p;
    for (int j = 0; j < c.joints; ++j)
      if (phases[static_cast<std::size_t>(j)].is_rocking()) p.free.push_back(j);
    for (int k = c.joints; k < c.size; ++k) p.free.push_back(k);
    const Eigen::MatrixXd M = chain_mass_at_rest(c, phases);
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n_, n_), C = Eigen::MatrixXd::Zero(n_, n_);
    for (int j = 0; j < c.joints; ++j) {
      const int o = c.elastic_offset[static_cast<std::size_t>(j)];
      if (o < 0) continue;
      const Eigen::Index m = c.K[static_cast<std::size_t>(j)].rows();
      K.block(o, o, m, m) = c.K[static_cast<std::size_t>(j)];
      C.block(o, o, m, m) = c.C[static_cast<std::size_t>(j)];
    }
    const auto nf = static_cast<Eigen::Index>(p.free.size());
    p.M.resize(nf, nf);
    p.K.resize(nf, nf);
    p.C.resize(nf, nf);
    for (Eigen::Index a = 0; a < nf; ++a)
      for (Eigen::Index b = 0; b < nf; ++b) {
        const int fa = p.free[static_cast<std::size_t>(a)], fb = p.free[static_cast<std::size_t>(b)];
        p.M(a, b) = M(fa, fb);
        p.K(a, b) = K(fa, fb);
        p.C(a, b) = C(fa, fb);
      }
    return p;
  }

  const Chain* c_;
  int n_;
  std::unordered_map<std::uint64_t, Part> parts_;
  const Part* last_ = nullptr;
  std::uint64_t last_key_ = 0;
  double last_g_ = 0;
  Eigen::MatrixXd L_ = Eigen::MatrixXd::Zero(n_, n_);
  Eigen::VectorXd rhs_ = Eigen::VectorXd::Zero(n_);
};

}  // namespace rocking
