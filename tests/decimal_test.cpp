// rocking/decimal.hpp: write_g9 writes every value as std::to_chars
// (general, precision 9) does, which is printf's "%.9g": over log-uniform
// magnitudes from 1e-20 to 1e35, random bit patterns, exact and near rounding
// ties at the ninth digit, values that round up to the next power of ten,
// integers, powers of ten and their neighbours, zeros and non-finite values.
#include <doctest/doctest.h>
#include <rocking/decimal.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

using rocking::g9_max_chars;
using rocking::write_g9;

namespace {

std::string fast(double v) {
  char buf[g9_max_chars];
  return std::string(buf, write_g9(buf, v));
}

std::string library(double v) {
  char buf[64];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 9).ptr);
}

// Counts the values of `count` draws where the two differ (and reports the first).
template <class Draw>
long mismatches(long count, Draw draw) {
  long bad = 0;
  for (long i = 0; i < count; ++i) {
    const double v = draw();
    const std::string a = fast(v), b = library(v);
    if (a != b && bad++ == 0) MESSAGE("first mismatch at ", library(v), ": ", a, " against ", b);
  }
  return bad;
}

}  // namespace

TEST_CASE("write_g9 equals %.9g on log-uniform magnitudes of either sign from 1e-20 to 1e35") {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> exponent(-20, 35);
  CHECK(mismatches(1000000, [&] {
          const double v = std::pow(10.0, exponent(rng));
          return rng() % 2 == 0 ? v : -v;
        }) == 0);
}

TEST_CASE("write_g9 equals %.9g on random bit patterns") {
  std::mt19937_64 rng(7);
  CHECK(mismatches(1000000, [&] {
          for (;;) {
            const std::uint64_t bits = rng();
            double v;
            std::memcpy(&v, &bits, sizeof v);
            if (std::isfinite(v)) return v;
          }
        }) == 0);
}

TEST_CASE("write_g9 equals %.9g at and beside rounding ties of the ninth digit, and where it rounds to a power of ten") {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> decade(-14, 29);
  std::uniform_int_distribution<std::uint32_t> nine(100000000u, 999999999u);
  int step = 0;
  CHECK(mismatches(600000, [&] {
          const double scale = std::pow(10.0, decade(rng) - 8);
          double v = (nine(rng) + 0.5) * scale;  // a tie, or the double nearest one
          if (step % 3 == 1) v = (999999999.5 + (rng() % 100) * 1e-3) * scale;  // rounds up to 10^(e+1)
          for (int k = static_cast<int>(rng() % 5) - 2; k != 0; k += k > 0 ? -1 : 1)  // up to two ulps aside
            v = std::nextafter(v, k > 0 ? 1e300 : -1e300);
          ++step;
          return v;
        }) == 0);
  // ties exactly representable: 2^-k has a terminating decimal expansion
  for (int k = 0; k < 60; ++k) CHECK(fast(std::ldexp(1.0, -k)) == library(std::ldexp(1.0, -k)));
  for (double v : {1234567885.0, 1234567895.0, 0.1234567885, 999999999.5, 9999999995.0, 0.5, 2.5e-9})
    CHECK(fast(v) == library(v));
}

TEST_CASE("write_g9 equals %.9g on integers, powers of ten and their neighbours, zeros and non-finite values") {
  long bad = 0;
  for (long n = -100000; n <= 100000; ++n) bad += fast(static_cast<double>(n)) != library(static_cast<double>(n));
  CHECK(bad == 0);
  for (int e = -320; e <= 308; ++e) {
    const double p = std::pow(10.0, e);
    for (double v : {p, std::nextafter(p, 0.0), std::nextafter(p, 1e308), -p})
      CHECK_MESSAGE(fast(v) == library(v), library(v));
  }
  for (double v : {0.0, -0.0, std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                   std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::denorm_min(),
                   std::numeric_limits<double>::max(), std::numeric_limits<double>::min()})
    CHECK(fast(v) == library(v));
  // the history's own: the chimney's time grid and a few responses
  for (int i = 0; i <= 3200; ++i) CHECK(fast(0.01 * i) == library(0.01 * i));
  CHECK(fast(-0.00275605028) == "-0.00275605028");
  CHECK(fast(136058.18112023055) == "136058.181");
  CHECK(fast(1.145e-5) == "1.145e-05");
}
