// The description of a device law's parameters, which the scene reader uses
// to read any law's keys without knowing the law.
module;
#include <string>
export module rocking.devices:parameters;

export namespace rocking {

struct LawParameter {
  std::string key;         // scene key, e.g. "k"
  std::string unit;        // "N/m"
  std::string doc;         // one line
  double default_value = 0;
  double minimum = 0;      // values below are refused
  bool minimum_exclusive = false;  // the minimum itself is refused too
  // Non-empty: the law gives the same forces when this parameter and others
  // are rescaled together, and a fit (rocking.fitting) holds it at one minus
  // the named parameter (Bouc-Wen's alpha = 1 - beta).
  std::string fitted_as_one_minus = {};
};

}  // namespace rocking
