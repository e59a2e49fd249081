// rocking.devices (MODEL.md 11): each kinematics against its closed form and
// the paper's damper; each law alone under a prescribed elongation history
// against its closed form; the limits (a law that exerts nothing, a Bouc-Wen
// device with eps = 1 that is an elastic spring); laws made by name from
// their parameters, with one-line errors.
#include <doctest/doctest.h>
#include "close.hpp"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>
import rocking.devices;
import rocking.hysteresis;
import rocking.errors;

using namespace rocking;

namespace {

std::optional<double> none(std::string_view) { return std::nullopt; }

// z of a rate law along e(t) = e_of(t), by classical RK4 with n steps on [0, T].
double integrate_z(const DeviceLaw& law, double (*e_of)(double), double (*v_of)(double), double T, int n) {
  double z = 0;
  const double h = T / n;
  for (int i = 0; i < n; ++i) {
    const double t = i * h;
    auto f = [&](double tt, double zz) { return law_rate(law, e_of(tt), v_of(tt), zz); };
    const double k1 = f(t, z), k2 = f(t + h / 2, z + h / 2 * k1), k3 = f(t + h / 2, z + h / 2 * k2),
                 k4 = f(t + h, z + h * k3);
    z += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return z;
}

}  // namespace

namespace {
// A registered law as its example device (each parameter at its example value).
DeviceLaw example_law(const LawInfo& info) {
  return make_law(info.name, [&](std::string_view key) -> std::optional<double> {
    for (const LawParameter& p : info.parameters)
      if (p.key == key) return p.example;
    return std::nullopt;
  });
}
}  // namespace

TEST_CASE("chord kinematics at the far edge is the paper's damper, bit for bit") {
  const double B = 0.9;
  for (const Pivot p : pivots)
    for (double th : {1e-6, 0.003, 0.02, 0.3}) {
      const int s = sign(p);
      const Tilt tilt(s * th);
      const Stretch st = stretch({-s * B, Kinematics::chord, 0}, B, p, tilt);
      CHECK(lever_arm({-s * B, Kinematics::chord, 0}, B, p) == 2 * B);
      CHECK(st.e == damper_elongation(B, tilt));
      // e' = de/d|th| s th' is the damper's rate.
      CHECK(st.de_dtheta * s * 0.7 == close_to(damper_rate(B, tilt, 0.7, p), 1e-15));
      // The device at the pivot does not stretch.
      CHECK(stretch({s * B, Kinematics::chord, 0}, B, p, tilt).e == 0);
    }
}

TEST_CASE("vertical kinematics: the closed form, its derivative, and its limits") {
  const double B = 1.5, L = 6.0;
  const DeviceGeometry centre{0, Kinematics::vertical, L};
  for (double th : {0.001, 0.01, 0.05, 0.2}) {
    const double l = B;  // a central anchor: l = B about either pivot
    const Stretch st = stretch(centre, B, Pivot::right, Tilt(th));
    CHECK(st.e == close_to(std::hypot(L + l * std::sin(th), l * (1 - std::cos(th))) - L, 1e-13));
    // de/d|th| against a central difference of e.
    const double h = 1e-6;
    const double fd = (stretch(centre, B, Pivot::right, Tilt(th + h)).e - stretch(centre, B, Pivot::right, Tilt(th - h)).e) / (2 * h);
    CHECK(st.de_dtheta == close_to(fd, 1e-7));
    // Rocking the other way mirrors it.
    CHECK(stretch(centre, B, Pivot::left, Tilt(-th)).e == close_to(st.e, 1e-15));
  }
  // At theta = 0 the lever arm is the rate of elongation; a very long tendon
  // follows the anchor's rise, l sin|th|.
  CHECK(stretch(centre, B, Pivot::right, Tilt(0.0)).de_dtheta == close_to(B, 1e-12));
  const Stretch long_tendon = stretch({0, Kinematics::vertical, 1e7}, B, Pivot::right, Tilt(0.1));
  CHECK(long_tendon.e == close_to(B * std::sin(0.1), 1e-6));
}

TEST_CASE("elastic law: F = P0 + k e in tension only, storing the work done on it") {
  const DeviceLaw tendon = ElasticLaw{2.0e5, 3.0e6};
  CHECK(law_states(tendon) == 0);
  CHECK(law_force_at_rest(tendon, 0) == 2.0e5);
  CHECK(law_stiffness(tendon) == 3.0e6);
  // Along e = 0 .. 0.05 the work int F de (trapezoids, exact for a linear F) is the stored energy.
  double work = 0;
  const int n = 1000;
  for (int i = 0; i < n; ++i) {
    const double e0 = 0.05 * i / n, e1 = 0.05 * (i + 1) / n;
    work += 0.5 * (law_force(tendon, e0, 0, 0) + law_force(tendon, e1, 0, 0)) * (e1 - e0);
  }
  CHECK(work == close_to(law_stored_energy(tendon, 0.05, 0), 1e-12));
  CHECK(law_force(tendon, 0.05, 0, 0) == close_to(2.0e5 + 3.0e6 * 0.05, 1e-12));
  // Tension only: a compressed spring without prestress pushes nothing.
  CHECK(law_force(ElasticLaw{0, 1e6}, -0.01, 0, 0) == 0);
}

TEST_CASE("viscous law: F = c sign(e') |e'|^a, linear for a = 1") {
  const DeviceLaw linear = ViscousLaw{4.0e5, 1.0}, fluid = ViscousLaw{4.0e5, 0.3};
  for (double v : {-0.8, -0.01, 0.0, 0.02, 0.5}) {
    CHECK(law_force(linear, 0.1, v, 0) == close_to(4.0e5 * v, 1e-12));
    CHECK(law_force(fluid, 0.1, v, 0) == close_to(std::copysign(4.0e5 * std::pow(std::abs(v), 0.3), v), 1e-12));
  }
  CHECK(law_force_at_rest(fluid, 0) == 0);
  CHECK(law_stored_energy(fluid, 0.3, 0) == 0);
}

TEST_CASE("friction law: F = F_s tanh(e'/v_r), Coulomb friction once sliding, dissipating F_s per unit of slip") {
  const double F_s = 2.0e5, v_r = 1e-3;
  const DeviceLaw friction = FrictionLaw{F_s, v_r};
  for (double v : {-0.5, -1e-3, 0.0, 2e-4, 0.3})
    CHECK(law_force(friction, 0.05, v, 0) == close_to(F_s * std::tanh(v / v_r), 1e-15));
  CHECK(law_force(friction, 0.0, 0.2, 0) == close_to(F_s, 1e-12));  // sliding: the slip force
  CHECK(law_force(friction, 0.0, -0.2, 0) == close_to(-F_s, 1e-12));
  // A prescribed slide e(t) = V t to e = 0.1 m at V = 0.1 m/s >> v_r: the work
  // done on it is F_s e to 1e-9 (midpoint rule, 1000 steps), all dissipated.
  const double V = 0.1;
  double work = 0;
  for (int i = 0; i < 1000; ++i) work += law_force(friction, V * (i + 0.5) * 1e-3, V, 0) * V * 1e-3;
  CHECK(work == close_to(F_s * 0.1, 1e-9));
  CHECK(law_stored_energy(friction, 0.1, 0) == 0);
  CHECK(law_force_at_rest(friction, 0) == 0);
  CHECK(law_states(friction) == 0);
  const DeviceLaw by_name = make_law("friction", [F_s](std::string_view k) -> std::optional<double> {
    return k == "F_s" ? std::optional<double>(F_s) : std::nullopt;
  });
  CHECK(std::get<FrictionLaw>(by_name).v_r == 1e-3);  // the default regularising velocity
}

TEST_CASE("Bouc-Wen law: monotonic loading follows z = 1 - exp(-e / d_y), and it is the paper's damper") {
  // alpha = beta = 1/2, n = 1, loading from rest: d_y dz/de = 1 - z, so z = 1 - exp(-e / d_y).
  const DeviceLaw law = BoucWenLaw::make({1.2e6, 0.05, 0.004, 0.5, 0.5, 1.0});
  CHECK(law_states(law) == 1);
  auto e_of = [](double t) { return 0.01 * t; };
  auto v_of = [](double) { return 0.01; };
  for (double T : {0.2, 1.0, 3.0}) {
    const double z = integrate_z(law, e_of, v_of, T, 20000);
    CHECK(z == close_to(1 - std::exp(-0.01 * T / 0.004), 1e-10));
  }
  // The same numbers as rocking.hysteresis's damper.
  Damper d;
  d.stiffness = 1.2e6;
  d.post_yield_ratio = 0.05;
  d.alpha = d.beta = 0.5;
  d.n = 1;
  CHECK(law_force(law, 0.01, 0.3, 0.4) == damper_force(d, 0.004, 0.01, 0.4));
  CHECK(law_rate(law, 0.01, 0.3, 0.4) == bouc_wen_rate(d, 0.004, 0.3, 0.4));
  CHECK(law_force_at_rest(law, 0.4) == damper_force(d, 0.004, 0.0, 0.4));
}

TEST_CASE("limits: laws that exert nothing, and Bouc-Wen with eps = 1 is the elastic spring") {
  for (double e : {0.0, 0.01, 0.2})
    for (double v : {-1.0, 0.0, 0.3}) {
      CHECK(law_force(ViscousLaw{0, 1}, e, v, 0) == 0);
      CHECK(law_force(ViscousLaw{0, 0.3}, e, v, 0) == 0);
      CHECK(law_force(ElasticLaw{0, 0}, e, v, 0) == 0);
      const DeviceLaw linear = BoucWenLaw::make({2e6, 1.0, 0.003, 0.5, 0.5, 1.0});
      CHECK(law_force(linear, e, v, 0.7) == close_to(law_force(ElasticLaw{0, 2e6}, e, v, 0), 1e-12));
    }
}

TEST_CASE("laws by name from their parameters, with one-line errors naming the key") {
  const auto values = [](std::string_view key) -> std::optional<double> {
    if (key == "P0") return 1e5;
    if (key == "k") return 2e6;
    return std::nullopt;
  };
  const DeviceLaw tendon = make_law("elastic", values);
  REQUIRE(std::holds_alternative<ElasticLaw>(tendon));
  CHECK(std::get<ElasticLaw>(tendon).P0 == 1e5);
  const DeviceLaw dashpot = make_law("viscous", none);
  CHECK(std::get<ViscousLaw>(dashpot).a == 1);  // the default exponent
  // An unknown law is refused naming every registered law, in registry order.
  std::string names;
  for (const LawInfo& l : device_laws()) names += (names.empty() ? "" : ", ") + l.name;
  CHECK(names.starts_with("bouc-wen, elastic, viscous, friction"));
  CHECK_THROWS_WITH_AS(make_law("spring", none), ("device law 'spring': unknown (laws: " + names + ")").c_str(),
                       InputError);
  CHECK_THROWS_WITH_AS(make_law("viscous", [](std::string_view k) -> std::optional<double> {
                         return k == "a" ? std::optional<double>(0.0) : std::nullopt;
                       }),
                       "viscous law: a = 0: must be > 0 and <= 3 [-]", InputError);
  CHECK_THROWS_WITH_AS(make_law("bouc-wen", [](std::string_view k) -> std::optional<double> {
                         if (k == "k") return 1e7;
                         if (k == "d_y") return 0.02;
                         if (k == "alpha" || k == "beta") return 0.0;
                         return std::nullopt;
                       }),
                       "bouc-wen law: beta: alpha + beta must be positive (bounded hysteresis)", InputError);
  CHECK_THROWS_AS(make_law("bouc-wen", none), InputError);  // k and d_y have no default
}

TEST_CASE("every registered law: its stiffness at rest is the slope of its force from rest, as the modal analysis takes it") {
  // The laws from the registry (device_laws), each as its example device.
  // Loaded from rest by a tiny elongation delta at zero rate (the internal
  // state carried along the path, z' per unit e'), the force grows by
  // law_stiffness x delta: the rocking stiffness of MODEL.md 8 and 11.
  for (const LawInfo& info : device_laws()) {
    CAPTURE(info.name);
    const DeviceLaw law = example_law(info);
    const double delta = 1e-9;
    const int steps = 1000;
    double z = 0;
    for (int i = 0; i < steps; ++i) {  // midpoint rule along e = 0 .. delta
      const double e = (i + 0.5) * delta / steps;
      if (law_states(law) > 0) z += law_rate(law, e, 1.0, z) * delta / steps;
    }
    const double slope = (law_force(law, delta, 0.0, z) - law_force(law, 0.0, 0.0, 0.0)) / delta;
    CHECK(slope == close_to(law_stiffness(law), 1e-6));
    CHECK(law_force(law, 0.0, 0.0, 0.0) == close_to(law_force_at_rest(law, 0.0), 1e-12));
  }
}

TEST_CASE("a law dissipates, by its declared trait, exactly when a closed cycle of elongation does work on it") {
  // e(t) = A sin^2(pi t / T) out and back: the samples of the way back repeat
  // those of the way out, so the trapezoidal work of a law that only stores
  // energy (F a function of e) telescopes to zero up to round-off, while a
  // law with a rate dependence or hysteresis takes positive work.
  constexpr double A = 0.1, T = 1.0;
  constexpr int n = 20000;
  for (const LawInfo& l : device_laws()) {
    CAPTURE(l.name);
    const DeviceLaw law = example_law(l);
    const double pi = std::numbers::pi, dt = T / n;
    const auto e_at = [&](double t) { return A * std::sin(pi * t / T) * std::sin(pi * t / T); };
    const auto rate_at = [&](double t) { return A * pi / T * std::sin(2 * pi * t / T); };
    double z = 0, work = 0, peak = 0;
    double F_prev = law_force(law, 0.0, 0.0, 0.0);
    for (int i = 0; i < n; ++i) {
      const double t = i * dt;
      // z by the midpoint rule (second order; the law's state is small here).
      const double zh = z + 0.5 * dt * law_rate(law, e_at(t), rate_at(t), z);
      z += dt * law_rate(law, e_at(t + 0.5 * dt), rate_at(t + 0.5 * dt), zh);
      const double F = law_force(law, e_at(t + dt), rate_at(t + dt), z);
      work += 0.5 * (F_prev + F) * (e_at(t + dt) - e_at(t));
      peak = std::max(peak, std::abs(F));
      F_prev = F;
    }
    REQUIRE(peak > 0);
    if (law_dissipates(law)) CHECK(work > 1e-3 * peak * A);  // a loop of a thousandth of its box or more
    else CHECK(std::abs(work) < 1e-9 * peak * A);             // round-off of 2e4 telescoping terms
  }
}
