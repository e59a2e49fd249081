// rocking.fitting: a device law fitted to a cyclic test (the paper's first
// step: "The Bouc-Wen model ... was first fit to best match the cyclic
// experimental results (Fig. 2, top right)"), for any registered law of
// rocking.devices (MODEL.md 5 and 11).
// - The law is driven along the measured elongation history e_i: its state z
//   is integrated from z = 0 by classical Runge-Kutta with e linear between
//   samples (substeps at most 1/400 of the test's elongation range, a
//   spacing fixed by the data so that the model force is a smooth function
//   of the parameters); the elongation rate at a sample is the central
//   difference of e over the times (one-sided at the ends). A test without
//   times drives a rate-independent law in unit steps; a law with a
//   parameter whose unit involves seconds (viscous, friction) needs them.
// - Nonlinear least squares on the force residuals (GSL multifit_nlinear,
//   trust region with Levenberg-Marquardt steps and geodesic acceleration,
//   finite-difference Jacobian). Each free parameter is searched as
//   p = min + exp(q) when its minimum is excluded (a stiffness, a yield
//   elongation), p = (1 - cos q) / 2 in [0, 1] when another parameter is
//   held at one minus it (LawParameter::fitted_as_one_minus: Bouc-Wen's
//   alpha = 1 - beta, which removes the law's redundant scale), and
//   p = min + |q| otherwise, so every trial law is physical.
//   Standard errors: the covariance s^2 (J'J)^-1 of the searched q, with
//   s^2 = SSR / (samples - free parameters), carried to p by dp/dq.
// - Starting values come from the data alone: the initial stiffness is the
//   slope of the first branch (least squares over its first tenth), a
//   post-yield stiffness the slope of that branch's last third, the yield
//   elongation the intersection of the two lines; a force scale is the peak
//   force, a velocity scale the peak rate, an onset elongation where the
//   force first exceeds 2 % of its peak. Each parameter starts from the one
//   its role names (rocking.devices' ParameterRole: stiffness, yield or onset
//   elongation, force, rate coefficient, reference rate, hardening ratio); a
//   shape or an exponent from its default (0.1 when that is 0).
// - Plate scaling (MODEL.md 5): a tapered plate of thickness x tau has
//   stiffness x tau^3 and yield force x tau^2, so d_y x 1/tau; the shape
//   (eps, alpha, beta, n) is kept.
module;
#include <optional>
#include <string>
#include <utility>
#include <vector>
export module rocking.fitting;
export import rocking.devices;

export namespace rocking {

// A cyclic test of a device: elongation and force at samples, SI units.
struct CyclicTest {
  std::string source;              // the file (for messages)
  std::vector<double> t, e, F;     // [s] (empty: the file has no times), [m], [N]
};

// Which columns hold what: a name (case-insensitive, without its unit) or a
// 1-based number; empty: found by name (time: t or time; elongation: a name
// starting disp, elong, e, d, u or x; force: starting force, load, f or p).
struct CyclicColumns {
  std::string time, elongation, force;
};
// Reads a table with a header row naming its columns with their units in
// brackets, e.g. "time [s], displacement [mm], force [kN]" (comma, semicolon,
// tab or space separated; '#' starts a comment). Units: m, cm, mm, in; N, kN,
// MN, lbf, kip; s, ms. InputError naming the file and line for anything else.
CyclicTest read_cyclic_test(const std::string& path, const CyclicColumns& columns = {});

// The law's force along the test's elongation history (see the top).
std::vector<double> law_force_history(const DeviceLaw& law, const CyclicTest& test);

struct FitRequest {
  std::string law = "bouc-wen";
  std::vector<std::pair<std::string, double>> fixed;  // parameters held at a value (SI)
};
struct FittedParameter {
  std::string key, unit, doc;
  ParameterRole role = ParameterRole::shape;
  double value = 0;
  double standard_error = 0;  // 0 for a fixed parameter
  bool fixed = false;
  std::string one_minus;      // non-empty: held at 1 - that parameter (its error is that one's)
};
struct Fit {
  std::string law;
  std::vector<FittedParameter> parameters;  // in the law's order
  DeviceLaw fitted;
  std::vector<double> force;      // the fitted law's force at each sample [N]
  double rms_error = 0;           // sqrt(mean (F_fit - F)^2) [N]
  double peak_error = 0;          // max |F_fit - F| [N]
  double peak_force = 0;          // max |F| of the test [N]
  double rcond = 0;               // reciprocal condition number of the Jacobian at the optimum
  int iterations = 0;
  std::size_t samples = 0;
  double value(const std::string& key) const;
};
// InputError (one line) for a test that cannot be fitted: too few samples,
// an elongation that never moves, a yielding law on a test that never yields,
// a rate-dependent law without times, an unknown law or parameter; RunError
// when the least squares do not converge.
Fit fit_law(const CyclicTest& test, const FitRequest& request);

// The fitted parameters with the plate-scaling rule applied: thickness x tau
// (k x tau^3, d_y x 1/tau), or a given stiffness and yield elongation for the
// structure's plates; only for a law with k and d_y (bouc-wen).
struct PlateScaling {
  double thickness_ratio = 1;
  std::optional<double> stiffness, yield_elongation;  // [N/m], [m]
  bool any() const { return thickness_ratio != 1 || stiffness || yield_elongation; }
};
std::vector<std::pair<std::string, double>> scaled_parameters(const Fit& fit, const PlateScaling& scaling);

}  // namespace rocking
