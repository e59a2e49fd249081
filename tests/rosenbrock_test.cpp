// The Rosenbrock-W integrator (rocking.integrator, rosenbrock.cpp) and the
// stiff part it solves with in a rocking run (rocking.contact, StiffPart):
// order 3 whatever T is (the W property), dense output of order 2 (of order
// 3 without a stiff part, exact on the cubic an uplift from rest starts
// with, so that the guards see no impact in its first steps), events
// against closed forms, agreement with CVODE on a stiff problem at a small
// fraction of an explicit method's steps; T equal to the Jacobian of the
// equations of motion at rest, and its solve exact.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "close.hpp"
#include <optional>
#include <gsl/gsl_sf_ellint.h>
#include <cmath>
#include <initializer_list>
#include <memory>
#include <utility>
#include <numbers>
#include <string>
#include <vector>
#include "dense_order.hpp"
#include "records.hpp"
import rocking.simulation;
import rocking.scene;
import rocking.errors;
import rocking.records;

using namespace rocking;
using namespace rocking::ode;
using Vec = Eigen::VectorXd;
using CRef = Eigen::Ref<const Eigen::VectorXd>;
using Ref = Eigen::Ref<Eigen::VectorXd>;

namespace {

Vec vec(std::initializer_list<double> v) {
  Vec out(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) out[i++] = x;
  return out;
}

// The solve of (I - g T) x = b for a small dense T (the tests' own, by LU).
LinearSolve dense_solve(Eigen::MatrixXd T) {
  return [T](double g, CRef b, Ref x) {
    const Eigen::MatrixXd W = Eigen::MatrixXd::Identity(T.rows(), T.cols()) - g * T;
    x = W.partialPivLu().solve(b);
  };
}

// A forced pendulum, y'' = -sin y + cos(2t): non-autonomous and nonlinear.
void pendulum(double t, CRef y, Ref f) {
  f[0] = y[1];
  f[1] = -std::sin(y[0]) + std::cos(2 * t);
}

// y(1) with steps of exactly h (tolerances loose enough never to reject).
Vec fixed_steps(double h, const LinearSolve& solve) {
  auto w = make_rosenbrock_w(2, pendulum, solve, {.rtol = 1.0, .atol = 1.0, .max_step = h, .initial_step = h});
  w->reset(0.0, vec({0.3, 0.0}), {});
  advance(*w, 1.0);
  return w->state();
}

}  // namespace

TEST_CASE("rosw is 3rd order with the exact Jacobian, with none and with a wrong one (a W-method)") {
  auto reference = make_rosenbrock_w(2, pendulum, {}, {.rtol = 1e-13, .atol = 1e-13});
  reference->reset(0.0, vec({0.3, 0.0}), {});
  advance(*reference, 1.0);
  const Vec exact = reference->state();
  Eigen::MatrixXd J(2, 2), wrong(2, 2);
  J << 0, 1, -std::cos(0.3), 0;  // the Jacobian at the start
  wrong << 1, 0, 2, -3;          // nothing like it
  for (const auto& [what, solve] : {std::pair{"exact", dense_solve(J)}, std::pair{"none", LinearSolve{}},
                                    std::pair{"wrong", dense_solve(wrong)}}) {
    CAPTURE(what);
    const double e1 = (fixed_steps(0.02, solve) - exact).norm(), e2 = (fixed_steps(0.01, solve) - exact).norm();
    CHECK(std::log2(e1 / e2) == close_to(3.0, 0.1));
  }
}

TEST_CASE("rosw's dense output is 2nd order: its error inside one step shrinks as h^3") {
  Eigen::MatrixXd T(2, 2);
  T << 0, 1, -1, 0;
  const double order = dense_order::measured(
      [&](double h) {
        return make_rosenbrock_w(2, dense_order::oscillator, dense_solve(T),
                                 {.rtol = 1.0, .atol = 1.0, .max_step = h, .initial_step = h});
      },
      0.01);
  CHECK(order == close_to(2.0, 0.1));
}

TEST_CASE("rosw without a stiff part: its dense output is 3rd order, and exact on theta = t^3 / 6 from rest, where no impact is seen") {
  const double order = dense_order::measured(
      [&](double h) {
        return make_rosenbrock_w(2, dense_order::oscillator, {}, {.rtol = 1.0, .atol = 1.0, .max_step = h, .initial_step = h});
      },
      0.01);
  CHECK(order == close_to(3.0, 0.1));

  // theta'' = t from theta = theta' = 0: a rocking angle just after an uplift from rest (its acceleration grows
  // from 0 with the ground's). The steps grow from 1e-6 by the controller's factor 5, each several times the
  // time since the start; the dense output is the cubic itself to round-off, and theta falling through 0 (an
  // impact's guard) is never seen.
  auto w = make_rosenbrock_w(2, [](double t, CRef y, Ref f) { f[0] = y[1]; f[1] = t; }, {}, {.rtol = 1e-4, .atol = 1e-7});
  w->reset(0.0, vec({0.0, 0.0}), {[](double, CRef y, Ref out) { out[0] = y[0]; }, {Direction::falling}});
  Vec y(2);
  int steps = 0;
  while (w->time() < 1.0) {
    const StepReport r = w->step(1.0);
    REQUIRE(r.reason != Stop::event);
    ++steps;
    const double t0 = w->previous_time(), t1 = w->time();
    for (double s : {0.1, 0.25, 0.5, 0.75, 0.9}) {
      const double t = t0 + s * (t1 - t0);
      w->dense(t, y);
      CHECK(y[0] == close_to(t * t * t / 6, 1e-9));
      CHECK(y[1] == close_to(t * t / 2, 1e-9));
    }
  }
  CHECK(steps > 5);
}

TEST_CASE("rosw locates events against closed forms: a falling ball, a pendulum's quarter period") {
  constexpr double g = 9.81;
  auto ball = make_rosenbrock_w(2, [](double, CRef y, Ref f) { f[0] = y[1]; f[1] = -g; }, {},
                                {.rtol = 1e-10, .atol = 1e-10});
  ball->reset(0.0, vec({2.0, 0.0}), {[](double, CRef y, Ref out) { out[0] = y[0]; }, {Direction::falling}});
  const StepReport hit = advance(*ball, 10.0);
  REQUIRE(hit.reason == Stop::event);
  CHECK(hit.t == within(std::sqrt(2 * 2.0 / g), 1e-10));

  // From rest at 1 rad, theta'' = -sin theta reaches 0 after K(sin(1/2)).
  const double quarter = gsl_sf_ellint_Kcomp(std::sin(0.5), GSL_PREC_DOUBLE);
  auto swing = make_rosenbrock_w(2, [](double, CRef y, Ref f) { f[0] = y[1]; f[1] = -std::sin(y[0]); }, {},
                                 {.rtol = 1e-12, .atol = 1e-12});
  swing->reset(0.0, vec({1.0, 0.0}), {[](double, CRef y, Ref out) { out[0] = y[0]; }, {Direction::falling}});
  const StepReport zero = advance(*swing, 10.0);
  REQUIRE(zero.reason == Stop::event);
  CHECK(zero.t == within(quarter, 1e-9));
}

TEST_CASE("rosw agrees with CVODE on a stiff problem in a small fraction of rk45's steps") {
  // y' = A y + 0.1 sin(y) + forcing, A = Q diag(-1, -1e3, -1e6) Q' (Q a
  // rotation): the stiff mode bounds an explicit step near 3e-6, while the
  // solution varies on the scale of 1.
  Eigen::Matrix3d Q = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d A = Q * Eigen::Vector3d(-1, -1e3, -1e6).asDiagonal() * Q.transpose();
  const Rhs f = [A](double t, CRef y, Ref dy) {
    dy = A * y + 0.1 * y.array().sin().matrix() + Eigen::Vector3d(std::sin(t), 1.0, std::cos(3 * t));
  };
  const Vec y0 = vec({1.0, -1.0, 0.5});
  const double t_end = 5.0;
  auto run = [&](std::unique_ptr<Integrator> it) {
    it->reset(0.0, y0, {});
    advance(*it, t_end);
    return std::pair{Vec(it->state()), it->stats().steps};
  };
  const auto [reference, cvode_steps] = run(make_cvode(3, f, {.rtol = 1e-11, .atol = 1e-13}));
  const auto [rosw, rosw_steps] = run(make_rosenbrock_w(3, f, dense_solve(A), {.rtol = 1e-7, .atol = 1e-9}));
  const auto [rk, rk_steps] = run(make_rk45(3, f, {.rtol = 1e-7, .atol = 1e-9}));
  CAPTURE(cvode_steps);
  CHECK((rosw - reference).norm() < 1e-5 * reference.norm());
  CHECK((rk - reference).norm() < 1e-5 * reference.norm());
  CHECK(rosw_steps * 50 < rk_steps);
}

namespace {

// A flexible rocking structure of three nodes with no devices.
ContactModel three_nodes() {
  Structure s;
  s.heights = vec({4.0, 8.0, 12.0});
  s.masses = vec({2e4, 2e4, 1.5e4});
  s.EI = vec({4e10, 4e10, 4e10});
  s.damping_ratio = 0.05;
  s.half_width = 2.0;
  s.base_mass = 3e4;
  return make_contact_model(s, Contact{}, {}, false);
}

}  // namespace

TEST_CASE("StiffPart: T is the Jacobian of the modal equations of motion at rest, and its solve is exact") {
  // Without gravity the rest of the equations vanishes at rest with all its
  // derivatives in u and u' (gravity's are the non-stiff terms T leaves out).
  ContactModel m = in_modal_coordinates(three_nodes());
  m.body.g = 0;
  const Layout& l = m.layout;
  StiffPart stiff(m);
  for (Phase phase : {Phase::full_contact(), Phase::rocking(Pivot::right), Phase::rocking(Pivot::left)}) {
    CAPTURE(phase_name(phase));
    Discrete d;
    Vec y = Vec::Zero(l.size);
    if (const std::optional<Pivot> p = phase.pivot()) begin_rocking(m, d, *p, y);
    // The Jacobian's columns of u and u' by central differences of the rhs.
    Eigen::MatrixXd T = Eigen::MatrixXd::Zero(l.size, l.size);
    Vec fp(l.size), fm(l.size);
    for (Eigen::Index j = l.u.start; j < l.u.start + 2 * l.n; ++j) {
      const double h = 1e-7;
      Vec yp = y, ym = y;
      yp[j] += h;
      ym[j] -= h;
      phase_rhs(m, d, 0.0, yp, fp);
      phase_rhs(m, d, 0.0, ym, fm);
      T.col(j) = (fp - fm) / (2 * h);
    }
    // T's rows are those of u, u' and (rocking) theta': leave out the rest.
    if (l.theta.present()) T.row(l.theta.start).setZero();
    const double g = 3e-3;
    Vec b = Vec::LinSpaced(l.size, -1.0, 2.0), x(l.size);
    stiff.solve(phase, g, b, x);
    const Vec residual = (Eigen::MatrixXd::Identity(l.size, l.size) - g * T) * x - b;
    CHECK(residual.norm() < 1e-6 * b.norm());
    // The same g again (the cached factors) and another g.
    stiff.solve(phase, g, b, x);
    CHECK(((Eigen::MatrixXd::Identity(l.size, l.size) - g * T) * x - b).norm() < 1e-6 * b.norm());
    stiff.solve(phase, 0.5, b, x);
    CHECK(((Eigen::MatrixXd::Identity(l.size, l.size) - 0.5 * T) * x - b).norm() < 1e-6 * b.norm());
  }
}

TEST_CASE("StiffPart refuses a flexible model in nodal coordinates, and solves nothing for a rigid block") {
  const ContactModel nodal = three_nodes();
  CHECK_THROWS_AS(StiffPart{nodal}, InputError);
  Structure s;
  s.heights = vec({4.0, 8.0});
  s.masses = vec({2e4, 2e4});
  s.half_width = 2.0;
  s.base_mass = 3e4;
  s.rigid = true;
  const ContactModel block = make_contact_model(s, Contact{}, {}, false);
  StiffPart stiff(block);
  const Vec b = Vec::LinSpaced(block.layout.size, -1.0, 2.0);
  Vec x(block.layout.size);
  stiff.solve(Phase::rocking(Pivot::right), 0.1, b, x);
  CHECK(x == b);
}

namespace {

ContactModel tower(int n, bool energy) {
  return make_contact_model(load_scene(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/towers/tower_" +
                                       std::to_string(n) + ".toml"),
                            energy);
}

}  // namespace

TEST_CASE("auto keeps rk45 for the chimney and the 8-node tower, and takes rosw where the highest modes would bind rk45") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion elcentro = read_record(*dir + "/elcentro_1940_ns.at2");
  const ContactModel chimney = make_contact_model(load_scene(std::string(ROCKING_SOURCE_DIR) +
                                                             "/data/scenes/christchurch_chimney.toml"), false);
  CHECK(choose_backend(chimney, elcentro, Backend::automatic) == Backend::rk45);
  // rk45's stability limit: pace / 9 for 8 nodes (rk45 the cheaper), pace / 180 for 16 (rosw)
  CHECK(choose_backend(tower(8, false), elcentro, Backend::automatic) == Backend::rk45);
  CHECK(choose_backend(tower(16, false), elcentro, Backend::automatic) == Backend::rosw);
  CHECK(choose_backend(tower(16, false), elcentro, Backend::cvode) == Backend::cvode);  // a choice is kept
  const RunResult r = simulate(chimney, elcentro, RunOptions{});
  CHECK(r.integrator == "rk45");
}

TEST_CASE("a 16-node tower under El Centro: rosw at the default tolerance matches rk45 at 1e-8 to 1e-3 in its peaks") {
  // The acceptance of issue 20 for the smallest tower where rk45's steps are
  // bound by stability: peaks of delta_t, delta_e, theta and the base moment.
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion elcentro = read_record(*dir + "/elcentro_1940_ns.at2");
  const ContactModel model = tower(16, false);
  RunOptions reference;
  reference.backend = Backend::rk45;
  reference.tolerances = {.rtol = 1e-8, .atol = 1e-11};
  const RunResult ref = simulate(model, elcentro, reference);
  RunOptions fast;
  fast.backend = Backend::rosw;
  const RunResult r = simulate(model, elcentro, fast);
  REQUIRE(ref.outcome == Outcome::completed);
  REQUIRE(r.outcome == Outcome::completed);
  CHECK(r.integrator == "rosw");
  for (Quantity q : {Quantity::delta_t, Quantity::delta_e, Quantity::theta, Quantity::base_moment}) {
    CAPTURE(info(q).name);
    CHECK(r.peak(q) == close_to(ref.peak(q), 1e-3));
  }
}

TEST_CASE("rosw closes the energy balance of a tower under El Centro as rk45 does") {
  const auto dir = records_dir();
  if (!dir) return;
  const GroundMotion elcentro = read_record(*dir + "/elcentro_1940_ns.at2");
  const ContactModel model = tower(8, true);
  for (double rtol : {1e-6, 1e-8}) {
    CAPTURE(rtol);
    RunOptions o;
    o.backend = Backend::rosw;
    o.tolerances = {.rtol = rtol, .atol = rtol * 1e-3};
    const RunResult r = simulate(model, elcentro, o);
    REQUIRE(r.outcome == Outcome::completed);
    CHECK(std::abs(r.energy.residual()) < 100 * rtol * r.energy.ground);
  }
}
