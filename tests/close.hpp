// The one way the tests say "close". doctest's Approx(x).epsilon(e) passes
// when |a - b| < e (1 + max(|a|, |b|)): its default scale of 1 adds an
// absolute margin of e, so on small quantities (radians, metres, seconds) the
// tolerance it states is not the one it checks. Here the tolerance stated is
// the tolerance checked:
//
//   CHECK(a == close_to(b, rel));          |a - b| <= rel max(|a|, |b|)
//   CHECK(a == close_to(b, rel, floor));   |a - b| <= max(rel max(|a|, |b|), floor)
//   CHECK(a == within(b, abs));            |a - b| <= abs
//
// A floor is for values that may sit at zero; it is explicit and says why.
//
// The audit (tests/close_audit.py, run by `make test`): when
// ROCKING_CLOSE_LOG_DIR names a folder, every comparison appends one line to
// <folder>/<pid>.tsv: where it is (file, line), what it states (rel, floor or
// abs), the two values and their difference. The audit re-derives from them
// the tolerance each check really applies and fails when it is more than
// twice the stated one.
#pragma once
#include <doctest/doctest.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <ostream>
#include <source_location>
#include <string>
#include <unistd.h>

namespace closeness {

struct Close {
  double expected;
  double rel;    // relative tolerance, of max(|actual|, |expected|)
  double floor;  // absolute floor (an absolute-only check has rel = 0)
  std::source_location where;
};

inline std::FILE* audit_log() {
  static std::FILE* const log = [] () -> std::FILE* {
    const char* dir = std::getenv("ROCKING_CLOSE_LOG_DIR");
    if (dir == nullptr || *dir == '\0') return nullptr;
    std::error_code ignored;  // a folder that cannot be made leaves fopen to fail: no log, no audit lines
    std::filesystem::create_directories(dir, ignored);
    const std::string path = std::string(dir) + "/" + std::to_string(::getpid()) + ".tsv";
    return std::fopen(path.c_str(), "a");
  }();
  return log;
}

inline bool holds(double actual, const Close& c) {
  const double diff = std::abs(actual - c.expected);
  const double bound = std::max(c.rel * std::max(std::abs(actual), std::abs(c.expected)), c.floor);
  const bool pass = actual == c.expected || diff <= bound;  // equal infinities pass; NaN never does
  if (std::FILE* log = audit_log()) {
    std::fprintf(log, "%s\t%u\t%.17g\t%.17g\t%.17g\t%.17g\t%.17g\t%d\n", c.where.file_name(),
                 static_cast<unsigned>(c.where.line()), c.rel, c.floor, actual, c.expected, diff, pass ? 1 : 0);
    std::fflush(log);
  }
  return pass;
}

inline bool operator==(double actual, const Close& c) { return holds(actual, c); }
inline bool operator==(const Close& c, double actual) { return holds(actual, c); }
inline bool operator!=(double actual, const Close& c) { return !holds(actual, c); }
inline bool operator!=(const Close& c, double actual) { return !holds(actual, c); }

inline std::ostream& operator<<(std::ostream& out, const Close& c) {
  out << "close_to(" << c.expected;
  if (c.rel > 0) out << ", rel " << c.rel;
  if (c.floor > 0) out << (c.rel > 0 ? ", floor " : ", abs ") << c.floor;
  return out << ")";
}

}  // namespace closeness

// |actual - expected| <= rel max(|actual|, |expected|): purely relative.
inline closeness::Close close_to(double expected, double rel,
                                 std::source_location where = std::source_location::current()) {
  return {expected, rel, 0.0, where};
}

// Relative, with an explicit absolute floor for values that may be zero.
inline closeness::Close close_to(double expected, double rel, double floor,
                                 std::source_location where = std::source_location::current()) {
  return {expected, rel, floor, where};
}

// |actual - expected| <= abs: an absolute tolerance, in the quantity's units.
inline closeness::Close within(double expected, double abs,
                               std::source_location where = std::source_location::current()) {
  return {expected, 0.0, abs, where};
}
