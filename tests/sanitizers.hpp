#pragma once
// Tests that run whole studies (a hunt of hundreds of runs, a suite, a study
// run twice to compare it with its --resume) repeat, many times over, code
// that lighter tests of the same commands already run under AddressSanitizer
// and UndefinedBehaviorSanitizer; under them (`make sanitize`) such a test
// takes minutes to a quarter of an hour. In the sanitizer build it stops at
// its first line with exit 77, which CTest reports as skipped (not passed),
// saying why; `make test` runs it in full.
#include <cstdio>
#include <cstdlib>

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ROCKING_TEST_UNDER_ASAN 1
#endif
#endif

inline void skip_under_sanitizers([[maybe_unused]] const char* why) {
#ifdef ROCKING_TEST_UNDER_ASAN
  std::fprintf(stderr, "SKIPPED under the sanitizers: %s; make test runs it\n", why);
  std::fflush(stderr);
  std::_Exit(77);
#endif
}
