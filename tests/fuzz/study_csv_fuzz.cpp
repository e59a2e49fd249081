// libFuzzer target: fuzz::study_csv (tests/fuzz/targets.hpp). Built by `make sanitize`,
// run by `make fuzz` under AddressSanitizer and UndefinedBehaviorSanitizer.
#include <rocking/eigen.hpp>
#include "targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::study_csv(data, size);
  return 0;
}
