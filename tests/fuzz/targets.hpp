// The fuzz targets: every reader and parser a user's bytes reach, each as a
// function of the bytes that must either succeed or throw InputError, never
// crash, hang, leak or throw anything else. tests/fuzz/*_fuzz.cpp hand them to
// libFuzzer (`make fuzz`); tests/fuzz_replay_test.cpp replays the committed
// corpus and the regression inputs through them on every `make test`.
// Include after <rocking/eigen.hpp> and before any import.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>
import rocking.scene;
import rocking.study;
import rocking.fitting;
import rocking.errors;

namespace fuzz {

// The bytes as a file of this process's own (readers take paths).
inline std::string as_file(const std::uint8_t* data, std::size_t size, const char* name) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("rocking_fuzz_" + std::to_string(::getpid()) + "_" + name)).string();
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

// Runs f, accepting success or InputError: anything else escapes to the fuzzer.
template <class F>
void input_or_error(F&& f) {
  try {
    f();
  } catch (const rocking::InputError&) {
  }
}

// A record file of any format, detected from its content.
inline void record(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "record");
  input_or_error([&] { (void)rocking::read_record(path); });
  input_or_error([&] {  // the one-column reading, which needs --dt
    rocking::RecordOptions o;
    o.dt = 0.01;
    (void)rocking::read_record(path, o);
  });
  std::remove(path.c_str());
}

// A scene file: TOML, then the schema and every value's check.
inline void scene(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "scene.toml");
  input_or_error([&] { (void)rocking::load_scene(path); });
  std::remove(path.c_str());
}

// One --set TABLE.KEY=VALUE on the built-in chimney.
inline void set_override(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  input_or_error([&] { (void)rocking::load_default_scene({text}); });
}

// --scales, --levels, --sizes, --rtols: FIRST:LAST:STEP or a comma list.
inline void number_list(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  input_or_error([&] { (void)rocking::parse_number_list(text); });
}

// A cyclic test table (rocking fit): read, and when short, fitted (a fit
// that does not converge on such bytes is a RunError, which is refused too).
inline void cyclic_test(const std::uint8_t* data, std::size_t size) {
  const std::string path = as_file(data, size, "cyclic.csv");
  input_or_error([&] {
    const rocking::CyclicTest test = rocking::read_cyclic_test(path);
    if (test.e.size() <= 60) {
      try {
        (void)rocking::fit_law(test, {"bouc-wen", {{"n", 1.0}}});
      } catch (const rocking::RunError&) {
      }
    }
  });
  std::remove(path.c_str());
}

}  // namespace fuzz
