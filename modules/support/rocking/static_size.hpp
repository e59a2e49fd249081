// Small dense kernels at sizes known when compiling. The structures here have
// a handful of nodes (the chimney 4, a state of 11), and a loop over a size
// known only at run time costs more in control than in arithmetic at such
// sizes. with_static_size(n, f) calls f(std::integral_constant<int, n>) for n
// in 1..max_static_size, so that a kernel written once, with loops bounded by
// static_or(S, n), is unrolled and vectorised for each size; beyond that it
// calls f(std::integral_constant<int, 0>), which means "use the run-time size".
#pragma once
#include <type_traits>
#include <utility>

namespace rocking {

inline constexpr int max_static_size = 16;

// The loop bound of a kernel instantiated for static size S (0: dynamic).
template <int S>
constexpr long static_or(long n) {
  if constexpr (S > 0) return S;
  else return n;
}

namespace detail {
template <class F, int... I>
void dispatch_static_size(long n, F& f, std::integer_sequence<int, I...>) {
  const bool done = ((n == I + 1 ? (f(std::integral_constant<int, I + 1>{}), true) : false) || ...);
  if (!done) f(std::integral_constant<int, 0>{});
}
}  // namespace detail

template <class F>
void with_static_size(long n, F&& f) {
  detail::dispatch_static_size(n, f, std::make_integer_sequence<int, max_static_size>{});
}

// r -= K u + C v for column-major n x n K and C (n static when S > 0), a
// column at a time: the elastic and viscous forces of every right-hand side
// of a flexible structure. r is best a local array of static size, which the
// compiler knows aliases nothing.
template <int S>
inline void subtract_stiffness_damping(const double* K, const double* C, const double* u, const double* v, double* r,
                                       long n_runtime) {
  const long n = static_or<S>(n_runtime);
  for (long j = 0; j < n; ++j) {
    const double uj = u[j], vj = v[j];
    for (long i = 0; i < n; ++i) r[i] -= K[j * n + i] * uj + C[j * n + i] * vj;
  }
}

}  // namespace rocking
