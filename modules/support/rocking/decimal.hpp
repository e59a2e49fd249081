// A double as printf's "%.9g" writes it (the digits of history.csv), at a
// small fraction of the library's cost: the value is scaled by an exact power
// of ten (10^0 to 10^22, one correctly rounded product or quotient) to nine
// digits before the point (within 6e-8, half its ulp), and the digits are then
// laid out as %g lays them out (fixed for decimal exponents -4 to 8, else
// scientific; trailing zeros dropped), with fixed-size copies and few
// branches. Values whose scaled form lies within 1e-6 of a rounding tie, or
// outside 1e-14 to 1e30 in magnitude, subnormals and non-finite values take
// std::to_chars (general, precision 9), so every output is the library's,
// digit for digit (tests/decimal_test.cpp checks millions of values against it).
#pragma once
#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace rocking {

// Room write_g9 may use.
inline constexpr std::size_t g9_max_chars = 32;

namespace detail {
inline constexpr std::array<double, 23> exact_powers_of_ten{
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// 10^k for k = -14 to 31, each the double nearest it.
inline constexpr std::array<double, 46> powers_of_ten{
    1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1,
    1e2,   1e3,   1e4,   1e5,   1e6,   1e7,  1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17,
    1e18,  1e19,  1e20,  1e21,  1e22,  1e23, 1e24, 1e25, 1e26, 1e27, 1e28, 1e29, 1e30, 1e31};
inline constexpr char two_digits[201] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

inline char* library_g9(char* out, double v) {
  return std::to_chars(out, out + g9_max_chars, v, std::chars_format::general, 9).ptr;
}
}  // namespace detail

// Writes v at out and returns the end; it may write up to g9_max_chars
// characters past out (beyond the end it returns too).
inline char* write_g9(char* out, double v) {
  if (v == 0) {
    if (std::signbit(v)) *out++ = '-';
    *out++ = '0';
    return out;
  }
  const double a = std::fabs(v);
  if (!(a >= 1e-14 && a < 1e30)) return detail::library_g9(out, v);
  std::uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  const int binary = static_cast<int>(bits >> 52) - 1023;
  int e = (binary * 78913) >> 18;  // floor(log10(2^binary)): floor(log10(a)) or one below
  e += a >= detail::powers_of_ten[static_cast<std::size_t>(e + 15)];
  const int shift = 8 - e;
  const double m = shift >= 0 ? a * detail::exact_powers_of_ten[static_cast<std::size_t>(shift)]
                              : a / detail::exact_powers_of_ten[static_cast<std::size_t>(-shift)];
  if (!(m >= 1e8 && m < 1e9)) return detail::library_g9(out, v);  // a power of ten's neighbour
  const auto whole = static_cast<std::uint32_t>(m);
  const double fraction = m - whole;
  if (std::fabs(fraction - 0.5) < 1e-6) return detail::library_g9(out, v);
  std::uint32_t n = whole + (fraction > 0.5 ? 1u : 0u);
  if (n == 1000000000u) {
    n = 100000000u;
    ++e;
  }
  // The nine digits: the first, then eight built in one word (first digit
  // in its lowest byte) from two-digit pairs; then zeros to pad the
  // fixed-size copies below.
  const auto pair = [](std::uint32_t x) {
    std::uint16_t two;
    std::memcpy(&two, detail::two_digits + 2 * x, 2);
    return static_cast<std::uint64_t>(two);
  };
  const std::uint32_t last8 = n % 100000000u, high = last8 / 10000u, low = last8 % 10000u;
  const std::uint64_t word = pair(high / 100u) | pair(high % 100u) << 16 | pair(low / 100u) << 32 |
                             pair(low % 100u) << 48;
  char digits[24];
  digits[0] = static_cast<char>('0' + n / 100000000u);
  std::memcpy(digits + 1, &word, 8);
  std::memset(digits + 9, '0', 15);
  // Significant digits once trailing zeros go: one past the last of the
  // eight that is not '0' (the first digit is not '0').
  const std::uint64_t nonzero = word ^ 0x3030303030303030u;
  const int k = nonzero == 0 ? 1 : 2 + (63 - std::countl_zero(nonzero)) / 8;
  char* p = out;
  *p = '-';
  p += v < 0;
  if (e >= 0 && e < 9) {
    // e + 1 digits, then the point and the rest, which end the value only
    // if a digit after the point is not zero
    std::memcpy(p, digits, 16);
    p[e + 1] = '.';
    std::memcpy(p + e + 2, digits + e + 1, 8);
    return p + (k > e + 1 ? k + 1 : e + 1);
  }
  if (e < 0 && e >= -4) {
    static constexpr char zeros[8] = {'0', '.', '0', '0', '0', '0', '0', '0'};
    std::memcpy(p, zeros, 8);
    p += 1 - e;  // "0." and -e - 1 zeros
    std::memcpy(p, digits, 16);
    return p + k;
  }
  p[0] = digits[0];
  p[1] = '.';
  std::memcpy(p + 2, digits + 1, 8);
  p += k > 1 ? k + 1 : 1;
  *p++ = 'e';
  *p++ = e < 0 ? '-' : '+';
  const int x = e < 0 ? -e : e;
  if (x >= 100) *p++ = static_cast<char>('0' + x / 100);
  std::memcpy(p, detail::two_digits + 2 * (x % 100), 2);
  return p + 2;
}

}  // namespace rocking
