// rocking.ground_motion: the three AT2 header styles on the real records,
// column files, units, pulses, interpolation, and one-line errors.
#include <doctest/doctest.h>
#include "close.hpp"
#include "temp_path.hpp"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <initializer_list>
#include <vector>
#include "one_line_error.hpp"
#include "records.hpp"
import rocking.ground_motion;
import rocking.errors;
import rocking.records;

using namespace rocking;

namespace {

std::string error_of(const std::string& path, RecordOptions o = {}) {
  return one_line_error<InputError>([&] { read_record(path, o); }, path);
}

}  // namespace

TEST_CASE("the three AT2 header styles read with the NPTS, DT and PGA of SOURCES.md") {
  const auto dir = records_dir();
  if (!dir) return;
  struct Expect { const char* file; int npts; double dt, pga_g, pga_time; };
  for (const Expect& e : {Expect{"elcentro_1940_ns.at2", 1559, 0.02, 0.3188, 2.02},                 // F1, LF
                          Expect{"elcentro_1940_ns_peer_ielc180.at2", 4000, 0.01, 0.3129, 2.15},    // F2, LF
                          Expect{"christchurch2011_pphs_s57e.at2", 8401, 0.005, 0.1990, 10.54}}) {  // F3, CRLF
    CAPTURE(e.file);
    const GroundMotion g = read_record(*dir + "/" + e.file);
    CHECK(g.sample_count() == static_cast<std::size_t>(e.npts));
    // Every sample is a breakpoint, found one after another from before the start.
    long found = 0;
    double last = -1.0;
    for (double t = g.next_breakpoint(-1.0); std::isfinite(t); t = g.next_breakpoint(t)) {
      CHECK(t > last);
      CHECK(t == close_to(found * e.dt, 1e-12));
      last = t;
      ++found;
    }
    CHECK(found == e.npts);
    CHECK(g.duration() == close_to((e.npts - 1) * e.dt, 1e-12));
    CHECK(g.peak() / 9.81 == close_to(e.pga_g, 5e-4));
    CHECK(std::abs(g.acceleration(e.pga_time)) / 9.81 == close_to(e.pga_g, 5e-4));
  }
}

TEST_CASE("the acceleration is linear between samples and zero outside the record") {
  const GroundMotion g = GroundMotion::from_samples("ramp", {0.0, 1.0, 2.0}, {0.0, 2.0, -2.0});
  CHECK(g.acceleration(0.25) == close_to(0.5, 1e-12));
  CHECK(g.acceleration(1.5) == within(0.0, 1e-15));  // halfway between 2 and -2, to round-off
  CHECK(g.acceleration(2.0) == close_to(-2.0, 1e-12));
  CHECK(g.acceleration(-0.1) == 0.0);
  CHECK(g.acceleration(2.1) == 0.0);
  CHECK(g.scaled(3.0).acceleration(0.25) == close_to(1.5, 1e-12));
  CHECK(g.next_breakpoint(0.0) == 1.0);  // strictly after
  CHECK(g.next_breakpoint(0.999) == 1.0);
  CHECK(std::isinf(g.next_breakpoint(2.0)));
  // Uneven samples keep their own times.
  const GroundMotion u = GroundMotion::from_samples("uneven", {0.0, 0.1, 0.3}, {1.0, 3.0, 1.0});
  CHECK(u.acceleration(0.2) == close_to(2.0, 1e-12));
  CHECK(u.next_breakpoint(0.1) == 0.3);
  CHECK(u.acceleration(0.3) == close_to(1.0, 1e-12));
  CHECK(u.acceleration(0.31) == 0.0);
  CHECK(u.acceleration(-0.01) == 0.0);
  // A record that starts late is zero before its first sample.
  const GroundMotion late = GroundMotion::from_samples("late", {0.5, 0.6, 0.7}, {1.0, 3.0, 1.0});
  CHECK(late.acceleration(0.4) == 0.0);
  CHECK(late.acceleration(0.55) == close_to(2.0, 1e-12));
  // A scaled copy reads the samples it shares after the original is gone.
  const GroundMotion copy = [] {
    const GroundMotion even = GroundMotion::evenly_sampled("even", 0.5, {0.0, 1.0, 4.0});
    return even.scaled(2.0);
  }();
  CHECK(copy.acceleration(0.75) == close_to(5.0, 1e-12));
  CHECK(copy.acceleration(1.0) == close_to(8.0, 1e-12));
  CHECK(copy.acceleration(1.01) == 0.0);
  CHECK(copy.acceleration(std::numeric_limits<double>::quiet_NaN()) == 0.0);
}

TEST_CASE("two-column and one-column files, units and scale") {
  const std::string two = write_temp("gm_two.txt", "# t a\n0.0 0.0\n0.5 100.0\n1.0 -50.0\n");
  const GroundMotion g2 = read_record(two, {.unit = AccelerationUnit::cm_per_s2});
  CHECK(g2.acceleration(0.5) == close_to(1.0, 1e-12));
  const std::string one = write_temp("gm_one.txt", "0.0\r\n0.1\r\n-0.2\r\n");
  const GroundMotion g1 = read_record(one, {.unit = AccelerationUnit::g, .dt = 0.01, .scale = 2.0});
  CHECK(g1.duration() == close_to(0.02, 1e-12));
  CHECK(g1.acceleration(0.01) == close_to(2.0 * 0.1 * 9.81, 1e-12));
  CHECK(parse_acceleration_unit("m/s2") == AccelerationUnit::m_per_s2);
}

TEST_CASE("a one-sine pulse is A sin(2 pi t / T) on [0, T] with a breakpoint where it ends") {
  const GroundMotion p = GroundMotion::pulse(PulseShape::one_sine, 3.0, 0.5);
  CHECK(p.acceleration(0.125) == close_to(3.0, 1e-12));
  CHECK(p.acceleration(0.6) == 0.0);
  CHECK(p.next_breakpoint(0.0) == 0.5);
  CHECK(std::isinf(p.next_breakpoint(0.5)));
  const GroundMotion r = GroundMotion::pulse(PulseShape::ricker, 2.0, 1.0);
  CHECK(r.acceleration(1.5) == close_to(2.0, 1e-12));  // peak at t0 = 1.5 T
  const double u0 = std::pow(1.5 * std::numbers::pi, 2);  // starts from (nearly) rest
  CHECK(r.acceleration(0.0) == close_to(2.0 * (1 - 2 * u0) * std::exp(-u0), 1e-12));
  CHECK(std::abs(r.acceleration(0.0)) < 1e-7 * 2.0);
}

TEST_CASE("bad records are one line naming the file and the line") {
  const std::string header = "PEER NGA STRONG MOTION DATABASE RECORD\nX\nACCELERATION TIME SERIES IN UNITS OF G\n";
  const std::string npts = write_temp("gm_npts.at2", header + "NPTS=   4  DT=   .0050 SEC\n 0.1 0.2 0.3\n");
  CHECK(error_of(npts) == npts + ":4: NPTS = 4 but the file holds 3 values");
  const std::string text = write_temp("gm_text.at2", header + "NPTS= 3, DT= .01 SEC\n 0.1 abc 0.3\n");
  CHECK(error_of(text) == text + ":5: 'abc' is not a number");
  const std::string nan = write_temp("gm_nan.at2", header + "NPTS= 3, DT= .01 SEC\n 0.1 nan 0.3\n");
  CHECK(error_of(nan) == nan + ":5: 'nan' is not a finite number");
  const std::string dt = write_temp("gm_dt.at2", header + "NPTS= 2, DT= 0.0 SEC\n 0.1 0.3\n");
  CHECK(error_of(dt) == dt + ":4: DT must be positive (got 0)");
  CHECK(error_of("/no/such/record.at2") == "/no/such/record.at2: record file not found");
  const std::string one = write_temp("gm_one_nodt.txt", "0.0\n0.1\n");
  CHECK(error_of(one).ends_with("a one-column record needs --dt > 0 (got 0)"));
  const std::string back = write_temp("gm_back.txt", "0.0 0.0\n0.5 1.0\n0.4 2.0\n");
  CHECK(error_of(back) == back + ":3: times must increase (0.4 after 0.5)");
  CHECK_THROWS_WITH_AS(parse_acceleration_unit("ft/s2"), "unknown acceleration unit 'ft/s2' (choose g, m/s2, cm/s2 (gal) or mm/s2)", InputError);
}
