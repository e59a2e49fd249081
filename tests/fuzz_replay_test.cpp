// Replays every committed fuzz input (tests/fuzz/corpus/TARGET and
// tests/fuzz/regressions/TARGET) through its target: each must be read or
// refused with an InputError, as under the fuzzer.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>
#include "fuzz/targets.hpp"

namespace fs = std::filesystem;

namespace {

template <class Target>
int replay(const std::string& name, Target target) {
  int count = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    const fs::path dir = fs::path(ROCKING_SOURCE_DIR) / "tests" / "fuzz" / kind / name;
    if (!fs::is_directory(dir)) continue;
    for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
      std::ifstream in(e.path(), std::ios::binary);
      const std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      CAPTURE(e.path().string());
      CHECK_NOTHROW(target(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
      ++count;
    }
  }
  return count;
}

}  // namespace

TEST_CASE("fuzz inputs replayed: record files") { CHECK(replay("record", fuzz::record) > 0); }
TEST_CASE("fuzz inputs replayed: scene files") { CHECK(replay("scene", fuzz::scene) > 0); }
TEST_CASE("fuzz inputs replayed: --set values") { CHECK(replay("set_override", fuzz::set_override) > 0); }
TEST_CASE("fuzz inputs replayed: number lists") { CHECK(replay("number_list", fuzz::number_list) > 0); }
TEST_CASE("fuzz inputs replayed: processing specifications") { CHECK(replay("processing", fuzz::processing) > 0); }
TEST_CASE("fuzz inputs replayed: lab requests") { CHECK(replay("lab_request", fuzz::lab_request) > 0); }
TEST_CASE("fuzz inputs replayed: cyclic tests") { CHECK(replay("cyclic_test", fuzz::cyclic_test) > 0); }
TEST_CASE("fuzz inputs replayed: one device key of every law") { CHECK(replay("device_set", fuzz::device_set) > 0); }
TEST_CASE("fuzz inputs replayed: option values") { CHECK(replay("option_value", fuzz::option_value) > 0); }
TEST_CASE("fuzz inputs replayed: histories read back by plot --from") { CHECK(replay("history_csv", fuzz::history_csv) > 0); }
TEST_CASE("fuzz inputs replayed: study CSVs read back by --resume") { CHECK(replay("study_csv", fuzz::study_csv) > 0); }
