// Two vectors entry by entry to a relative tolerance, with a floor of that
// tolerance times the larger vector's largest entry for an entry that cancels
// to nothing (tests/close.hpp's close_to with a floor).
#pragma once
#include <rocking/eigen.hpp>
#include <algorithm>
#include "close.hpp"

inline void check_vector(const Eigen::VectorXd& actual, const Eigen::VectorXd& expected, double tol) {
  REQUIRE(actual.size() == expected.size());
  const double floor = tol * std::max(actual.cwiseAbs().maxCoeff(), expected.cwiseAbs().maxCoeff());
  for (Eigen::Index k = 0; k < expected.size(); ++k) CHECK(actual[k] == close_to(expected[k], tol, floor));
}
