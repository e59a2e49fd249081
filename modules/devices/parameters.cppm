// The description of a device law's parameters, which the scene reader uses
// to read any law's keys without knowing the law.
module;
#include <string>
#include <vector>
export module rocking.devices:parameters;

export namespace rocking {

// What a parameter is to a law, which says how a fit starts it from a test's
// data (rocking.fitting) and whether the law yields or depends on the rate.
enum class ParameterRole {
  stiffness,         // N/m: from the test's initial slope
  hardening_ratio,   // -: post-yield over pre-yield slope
  yield_elongation,  // m: where the slope changes; the law yields (a fit needs a test past yield)
  onset_elongation,  // m: where the force starts (a gap): from the first force above 2 % of the peak
  force,             // N: a prestress or slip force, from the peak force
  rate_coefficient,  // N (s/m)^a: force over rate^a; the law depends on the rate
  rate_exponent,     // -: the a of rate_coefficient
  reference_rate,    // m/s: from the test's rates; the law depends on the rate
  shape,             // -: its default
};

struct LawParameter {
  std::string key;         // scene key, e.g. "k"
  std::string unit;        // "N/m"
  std::string doc;         // one line
  ParameterRole role = ParameterRole::shape;
  double example = 0;      // a typical device's value: the all-law tests' device
  double default_value = 0;
  double minimum = 0;      // values below are refused
  bool minimum_exclusive = false;  // the minimum itself is refused too
  double maximum = 0;      // values above are refused: beyond it the value is a typo, not a device
  // Non-empty: the law gives the same forces when this parameter and others
  // are rescaled together, and a fit (rocking.fitting) holds it at one minus
  // the named parameter (Bouc-Wen's alpha = 1 - beta).
  std::string fitted_as_one_minus = {};
};

// A law's values that its parameters' bounds alone do not refuse: the key to
// name and why (key empty: the values are fine).
struct LawProblem {
  std::string key, why;
};

}  // namespace rocking
