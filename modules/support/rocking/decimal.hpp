// A double as printf's "%.9g" writes it (the digits of history.csv and the
// study CSVs), at a small fraction of the library's cost: the value is scaled
// by an exact power of ten (10^0 to 10^22, one correctly rounded product or
// quotient) to nine digits before the point (within 6e-8, half its ulp), and the digits are then laid out as
// %g lays them out (fixed for decimal exponents -4 to 8, else scientific;
// trailing zeros dropped). Values whose scaled form lies within 1e-6 of a
// rounding tie, or outside 1e-14 to 1e30 in magnitude, zeros, subnormals and
// non-finite values take std::to_chars (general, precision 9), so every
// output is the library's, digit for digit (tests/decimal_test.cpp checks
// millions of values against it).
#pragma once
#include <array>
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

inline char* library_g9(char* out, double v) {
  return std::to_chars(out, out + g9_max_chars, v, std::chars_format::general, 9).ptr;
}
}  // namespace detail

// Writes v at out (at most g9_max_chars characters) and returns the end.
inline char* write_g9(char* out, double v) {
  const double a = std::fabs(v);
  if (!(a >= 1e-14 && a < 1e30)) return detail::library_g9(out, v);
  std::uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  const int binary = static_cast<int>(bits >> 52) - 1023;  // a in [2^binary, 2^(binary + 1)): a is normal here
  // floor(binary log10(2)), within one below floor(log10(a)) (78913 / 2^18 ~ log10(2))
  int e = (binary * 78913) >> 18;
  double m = 0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    const int shift = 8 - e;
    m = shift >= 0 ? a * detail::exact_powers_of_ten[static_cast<std::size_t>(shift)]
                   : a / detail::exact_powers_of_ten[static_cast<std::size_t>(-shift)];
    if (m < 1e8) --e;
    else if (m >= 1e9) ++e;
    else break;
    if (e < -14 || e > 30) return detail::library_g9(out, v);
  }
  if (!(m >= 1e8 && m < 1e9)) return detail::library_g9(out, v);
  const auto whole = static_cast<std::uint32_t>(m);  // floor: m > 0
  const double fraction = m - whole;
  if (std::fabs(fraction - 0.5) < 1e-6) return detail::library_g9(out, v);  // near a tie: the exact value decides
  std::uint32_t n = whole + (fraction > 0.5 ? 1u : 0u);
  if (n == 1000000000u) {
    n = 100000000u;
    ++e;
  }
  char digits[9];
  digits[0] = static_cast<char>('0' + n / 100000000u);
  n %= 100000000u;
  for (int i = 7; i >= 1; i -= 2) {  // two digits at a time
    const std::uint32_t pair = n % 100u;
    n /= 100u;
    digits[i] = static_cast<char>('0' + pair / 10u);
    digits[i + 1] = static_cast<char>('0' + pair % 10u);
  }
  int k = 9;  // significant digits left once trailing zeros go
  while (k > 1 && digits[k - 1] == '0') --k;
  char* p = out;
  if (v < 0) *p++ = '-';
  if (e >= -4 && e < 9) {
    if (e >= 0) {
      std::memcpy(p, digits, static_cast<std::size_t>(e + 1));
      p += e + 1;
      if (k > e + 1) {
        *p++ = '.';
        std::memcpy(p, digits + e + 1, static_cast<std::size_t>(k - e - 1));
        p += k - e - 1;
      }
    } else {
      *p++ = '0';
      *p++ = '.';
      for (int z = 0; z < -e - 1; ++z) *p++ = '0';
      std::memcpy(p, digits, static_cast<std::size_t>(k));
      p += k;
    }
    return p;
  }
  *p++ = digits[0];
  if (k > 1) {
    *p++ = '.';
    std::memcpy(p, digits + 1, static_cast<std::size_t>(k - 1));
    p += k - 1;
  }
  *p++ = 'e';
  *p++ = e < 0 ? '-' : '+';
  const int x = e < 0 ? -e : e;
  if (x >= 100) *p++ = static_cast<char>('0' + x / 100);
  *p++ = static_cast<char>('0' + x / 10 % 10);
  *p++ = static_cast<char>('0' + x % 10);
  return p;
}

}  // namespace rocking
