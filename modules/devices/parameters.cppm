// The description of a device law's parameters, which the scene reader uses
// to read any law's keys without knowing the law.
module;
#include <string>
#include <vector>
export module rocking.devices:parameters;

export namespace rocking {

struct LawParameter {
  std::string key;         // scene key, e.g. "k"
  std::string unit;        // "N/m"
  std::string doc;         // one line
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
