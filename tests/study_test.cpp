// rocking.study: the thread pool hands results back in job order whatever the
// number of threads; a bad record fails its own jobs only; the collapse hunt
// brackets the overturning scale to the asked precision.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>
#include "one_line_error.hpp"
import rocking.study;
import rocking.errors;

using namespace rocking;
namespace fs = std::filesystem;

namespace {

// A one-sine pulse, 0.4 g and 0.5 s, sampled every 5 ms, then 3.5 s of rest:
// a two-column record (t [s], a [g]).
std::string pulse_record() {
  const fs::path file = temp_path("study_pulse.txt");
  std::ofstream out(file);
  for (int i = 0; i <= 800; ++i) {
    const double t = 0.005 * i;
    out << t << ' ' << (t <= 0.5 ? 0.4 * std::sin(2 * std::numbers::pi * t / 0.5) : 0.0) << '\n';
  }
  return file.string();
}

std::string rigid_block() { return std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml"; }

}  // namespace

TEST_CASE("parallel_ordered emits every result once, in job order, for any number of threads") {
  for (int threads : {1, 2, 4, 7}) {
    std::vector<std::size_t> order;
    std::vector<long> values;
    parallel_ordered<long>(
        100, threads, [](std::size_t i) { return static_cast<long>(i * i); },
        [&](std::size_t i, const long& v) {
          order.push_back(i);
          values.push_back(v);
        });
    REQUIRE(order.size() == 100);
    for (std::size_t i = 0; i < 100; ++i) {
      CHECK(order[i] == i);
      CHECK(values[i] == static_cast<long>(i * i));
    }
  }
}

TEST_CASE("number lists: ladders and lists; anything else is a one-line error quoting the text, naming no flag") {
  CHECK(parse_number_list("1:5:1") == std::vector<double>{1, 2, 3, 4, 5});
  CHECK(parse_number_list("0.5:1.5:0.5") == std::vector<double>{0.5, 1.0, 1.5});
  CHECK(parse_number_list("0.5,2,3") == std::vector<double>{0.5, 2, 3});
  for (const char* bad : {"1:5", "5:1:1", "1:5:0", "a,b", "1;2", "", "1,2,"}) {
    const std::string message = one_line_error<InputError>([&] { parse_number_list(bad); }, bad);
    CHECK(message.find("'" + std::string(bad) + "'") != std::string::npos);
    CHECK(message.find("--") == std::string::npos);
  }
}

TEST_CASE("a bad record fails its own jobs and the others run") {
  const Study study(rigid_block(), {}, {pulse_record(), "/nonexistent/record.at2"}, RecordOptions{},
                    {named_variant("scene")}, RunOptions{});
  const std::vector<Job> jobs = study.ladder({1.0, 2.0});
  REQUIRE(jobs.size() == 4);
  const JobResult good = study.run(jobs[0]);
  CHECK(good.error.empty());
  CHECK(good.run.counts.uplifts > 0);  // 0.4 g > g tan(alpha) = 0.26 g
  const JobResult bad = study.run(jobs[2]);
  CHECK(bad.run.outcome == Outcome::failed);
  CHECK(bad.error.find("/nonexistent/record.at2") != std::string::npos);
}

TEST_CASE("the collapse hunt brackets the overturning scale to the asked precision") {
  const Study study(rigid_block(), {}, {pulse_record()}, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const HuntResult h = hunt_collapse(study, 0, 0, 1.0, 1.0, 20.0, 0.01);
  REQUIRE(h.collapsed);
  CHECK(h.collapse_scale - h.survived_scale <= 0.01);
  CHECK(h.collapse_scale > 1.0);
  // The bracket is real: one side overturns, the other does not.
  CHECK(study.run({0, h.collapse_scale, 0}).run.outcome == Outcome::overturned);
  CHECK(study.run({0, h.survived_scale, 0}).run.outcome == Outcome::completed);
}

TEST_CASE("a fixed base cannot overturn: the hunt says so without running") {
  const Study study("", {}, {pulse_record()}, RecordOptions{}, {named_variant("fixed-base")}, RunOptions{});
  const HuntResult h = hunt_collapse(study, 0, 0, 1.0, 1.0, 20.0, 0.01);
  CHECK(h.fixed_base);
  CHECK(h.runs == 0);
}

TEST_CASE("overturning spectrum: no uplift below g tan(alpha), a boundary that rises with frequency") {
  const Scene block = load_scene(rigid_block());
  std::vector<double> freqs{2, 4, 8}, amps;
  for (double a = 0.5; a <= 12.01; a += 0.1) amps.push_back(a);
  for (PulseShape shape : {PulseShape::one_sine, PulseShape::ricker}) {
    const BlockSpectrum s = overturning_spectrum(block, 1.0, shape, freqs, amps, 2);
    std::vector<double> threshold(freqs.size(), 1e9);
    for (const SpectrumPoint& pt : s.points) {
      if (pt.amplitude_ratio < 1.0) {
        CHECK_FALSE(pt.uplift);
      }
      const auto k = static_cast<std::size_t>(std::find(freqs.begin(), freqs.end(), pt.frequency_ratio) - freqs.begin());
      if (pt.overturned) threshold[k] = std::min(threshold[k], pt.amplitude_ratio);
    }
    CAPTURE(static_cast<int>(shape));
    CHECK(threshold[0] < 1e9);  // the strongest low-frequency pulses do overturn it
    CHECK(threshold[0] < threshold[1]);
    CHECK(threshold[1] < threshold[2]);
  }
}

TEST_CASE("size effect: one curve in normalised axes, and in seconds the larger block survives more") {
  const Scene block = load_scene(rigid_block());
  std::vector<double> freqs, amps;
  for (double f = 1.0; f <= 8.01; f += 1.0) freqs.push_back(f);
  for (double a = 1.0; a <= 8.01; a += 0.5) amps.push_back(a);
  const BlockSpectrum small = overturning_spectrum(block, 1.0, PulseShape::one_sine, freqs, amps, 2);
  const BlockSpectrum large = overturning_spectrum(block, 4.0, PulseShape::one_sine, freqs, amps, 2);
  CHECK(large.p == doctest::Approx(small.p / 2.0));  // p ~ 1 / sqrt(size)
  CHECK(large.alpha == doctest::Approx(small.alpha));
  std::size_t same = 0, overturned = 0;
  for (std::size_t i = 0; i < small.points.size(); ++i) {
    same += small.points[i].overturned == large.points[i].overturned;
    overturned += small.points[i].overturned;
  }
  CHECK(overturned > 10);
  CHECK(same == small.points.size());  // similarity: the same outcome at every normalised point
  // In seconds: the same pulse periods for both blocks.
  std::vector<double> periods{0.3, 0.5, 0.8, 1.2};
  auto overturn_count = [&](double size, double p) {
    std::vector<double> f;
    for (double T : periods) f.push_back(2 * std::numbers::pi / (T * p));
    const BlockSpectrum s = overturning_spectrum(block, size, PulseShape::one_sine, f, amps, 2);
    long n = 0;
    for (const SpectrumPoint& pt : s.points) n += pt.overturned;
    return n;
  };
  const long small_count = overturn_count(1.0, small.p), large_count = overturn_count(4.0, large.p);
  CHECK(small_count > 0);
  CHECK(large_count < small_count);
}
