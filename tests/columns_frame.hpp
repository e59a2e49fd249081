// A structure on rocking columns for the tests of devices on columns
// (MODEL.md 16 with 11): a rigid deck on three uniform rigid columns, its
// devices and the rest of the scene given as TOML text.
#pragma once
#include <fmt/format.h>
#include <gsl/gsl_integration.h>

#include <cmath>
#include <functional>
#include <string>

namespace columns_frame {

// A rigid deck (a cap beam and one mass 2 m above it) on three columns 0.5 m
// wide, 4 m tall, 6 m apart, with the devices given.
constexpr double b = 0.25, h = 2.0, mc = 2000.0, beam = 6000.0, deck = 7000.0, spacing = 6.0;
constexpr int n = 3;
inline std::string frame(const std::string& devices, const std::string& more) {
  return fmt::format(R"(
[structure]
rigid = true
half_width = 0.25
heights = [2.0]
masses = [{}]
base_mass = {}

[columns]
count = {}
half_width = {}
half_height = {}
mass = {}
spacing = {}

[contact]
restitution = "momentum"
{}
{})",
                     deck, beam, n, b, h, mc, spacing, devices, more);
}

// MODEL.md 16's frame: R, alpha, everything the beam carries and J.
struct Frame {
  double R = std::hypot(b, h), alpha = std::atan2(b, h), m_d = beam + deck;
  double J = 4.0 / 3.0 * n * mc * R * R + 4 * R * R * m_d;
  double lever = R * (n * mc + 2 * m_d);  // gravity's: J theta'' = -lever g sin(alpha - theta) about the right corner
};

// The time to fall from a release at rest at th0 to theta = 0 under the
// potential U with inertia J, the quadrature of the energy equation:
// t = int_0^th0 dth / sqrt(2 (U(th0) - U(th)) / J), with th = th0 - w^2 to
// remove the endpoint's singularity (GSL's adaptive Gauss-Kronrod, 1e-12).
inline double fall_time(const std::function<double(double)>& U, double th0, double J) {
  struct P {
    const std::function<double(double)>* U;
    double th0, J;
  } par{&U, th0, J};
  gsl_function F{[](double w, void* v) {
                   const P& p = *static_cast<P*>(v);
                   return 2 * w / std::sqrt(2 * ((*p.U)(p.th0) - (*p.U)(p.th0 - w * w)) / p.J);
                 },
                 &par};
  gsl_integration_workspace* ws = gsl_integration_workspace_alloc(1000);
  double t = 0, err = 0;
  gsl_integration_qag(&F, 0.0, std::sqrt(th0), 0.0, 1e-12, 1000, GSL_INTEG_GAUSS61, ws, &t, &err);
  gsl_integration_workspace_free(ws);
  return t;
}

}  // namespace columns_frame
