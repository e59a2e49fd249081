// rocking.study: the thread pool hands results back in job order whatever the
// number of threads; a bad record fails its own jobs only; records scaled to
// an IM level meet it exactly; the hunt and fill brackets the lowest
// overturning and agrees with a fine ladder on El Centro; the summary's
// fractiles, capacities and stripes match what is worked by hand.
#include <rocking/eigen.hpp>
#include <doctest/doctest.h>
#include "sanitizers.hpp"
#include "close.hpp"
#include <nlohmann/json.hpp>
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
#include "records.hpp"
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

TEST_CASE("number lists: ladders and lists: anything else is a one-line error quoting the text, naming no flag") {
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

TEST_CASE("the collapse hunt brackets the overturning level to the asked precision, and fills below it") {
  const Study study(rigid_block(), {}, {pulse_record()}, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const HuntOptions o{1.0, 1.0, 1.5, 20.0, 0.01, 0.1};
  const HuntResult h = hunt_collapse(study, 0, 0, o);
  REQUIRE(h.collapsed);
  CHECK(h.collapse_level - h.survived_level <= 0.01);
  CHECK(h.collapse_level > 1.0);
  CHECK(h.collapse_level <= h.traced_level);
  // The bracket is real: one side overturns, the other does not.
  CHECK(study.run(study.at_level(0, 0, h.collapse_level)).run.outcome == Outcome::overturned);
  CHECK(study.run(study.at_level(0, 0, h.survived_level)).run.outcome == Outcome::completed);
  // The fill ran every 0.1 below the bracket, and nothing below the answer overturned.
  std::size_t below = 0;
  for (const HuntPoint& p : h.points)
    if (p.level < h.collapse_level) {
      ++below;
      CHECK_FALSE(p.overturned);
    }
  CHECK(below >= static_cast<std::size_t>((h.survived_level - 1.0) / 0.1));
  CHECK(h.runs == static_cast<int>(h.points.size()));
  for (const auto& [from, to] : h.resurrections) CHECK(from > h.collapse_level);
  CHECK(hunt_capacity(h).reached);
  CHECK(hunt_capacity(h).im == h.collapse_level);
}

TEST_CASE("hunt options that cannot work are refused in one line") {
  CHECK_THROWS_WITH_AS(check_hunt_options({5, 1, 1.5, 2, 0.05, 0.1}),
                       "--hunt-max 2: below the first level 5, the hunt would run nothing", InputError);
  CHECK_THROWS_AS(check_hunt_options({1, 1, 0.5, 20, 0.05, 0.1}), InputError);
  CHECK_THROWS_AS(check_hunt_options({1, 1, 1.5, 20, 0.05, 0}), InputError);
  CHECK_THROWS_AS(check_hunt_options({1, 1, 1.5, 20, 0.05, 1e-6}), InputError);
  CHECK_NOTHROW(check_hunt_options({1, 1, 1.5, 50, 0.05, 0.1}));
}

TEST_CASE("a fixed base cannot overturn: the hunt says so without running") {
  const Study study("", {}, {pulse_record()}, RecordOptions{}, {named_variant("fixed-base")}, RunOptions{});
  const HuntResult h = hunt_collapse(study, 0, 0, HuntOptions{});
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
  CHECK(large.p == close_to(small.p / 2.0, 1e-12));  // p ~ 1 / sqrt(size)
  CHECK(large.alpha == close_to(small.alpha, 1e-12));
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

TEST_CASE("IM scaling is exact: every job's scaled record has the level's IM to 1e-9") {
  const auto dir = records_dir();
  if (!dir) return;
  for (const char* name : {"pga", "pgv", "sa:0.5", "saavg:0.2:1.5"}) {
    CAPTURE(name);
    const IntensityMeasure im = parse_intensity_measure(name);
    const Study study("", {}, {*dir + "/elcentro_1940_ns.at2", *dir + "/kobe1995_kjma_000.at2"}, RecordOptions{},
                      {named_variant("damper")}, RunOptions{}, im);
    for (const Job& job : study.ladder({0.05, 0.3, 1.7})) {
      const GroundMotion scaled = study.motion(job.record)->scaled(job.scale);
      CHECK(intensity(scaled, im) == close_to(job.level, 1e-9));
      CHECK(job.scale == close_to(job.level / study.record_intensity(job.record), 1e-15));
    }
  }
  // The scale factor is its own IM: the level is the scale.
  const Study sf(rigid_block(), {}, {pulse_record()}, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  for (const Job& job : sf.ladder({0.5, 2.0})) CHECK(job.scale == job.level);
}

TEST_CASE("a record of zero IM cannot be scaled to a level: its jobs fail, saying so") {
  const fs::path file = temp_path("study_silent.txt");
  std::ofstream(file) << "0 0\n0.01 0\n0.02 0\n";
  const Study study("", {}, {file.string()}, RecordOptions{}, {named_variant("damper")}, RunOptions{},
                    parse_intensity_measure("pga"));
  CHECK(study.record_error(0).find("its pga is 0: it cannot be scaled to a level") != std::string::npos);
  CHECK(study.run(study.ladder({0.5}).front()).error == study.record_error(0));
}

TEST_CASE("on El Centro the hunt finds the first overturning of a 0.01-step ladder, and its resurrections") {
  skip_under_sanitizers("a hunt of El Centro to a 0.01 step, with resurrections");
  const auto dir = records_dir();
  if (!dir) return;
  const Study study("", {}, {*dir + "/elcentro_1940_ns.at2"}, RecordOptions{},
                    {named_variant("damper"), named_variant("no-damper")}, RunOptions{});
  // The ladder 1, 1.01, ..., 14 for both variants, on two threads.
  const std::vector<Job> jobs = study.ladder(parse_number_list("1:14:0.01"));
  std::vector<double> first_overturn(2, 0);
  parallel_ordered<JobResult>(
      jobs.size(), 2, [&](std::size_t i) { return study.run(jobs[i]); },
      [&](std::size_t i, const JobResult& r) {
        REQUIRE(r.error.empty());
        if (r.run.outcome == Outcome::overturned && first_overturn[jobs[i].variant] == 0)
          first_overturn[jobs[i].variant] = jobs[i].level;
      });
  const HuntOptions o{1.0, 1.0, 1.5, 50.0, 0.05, 0.1};
  for (std::size_t v = 0; v < 2; ++v) {
    CAPTURE(v);
    const HuntResult h = hunt_collapse(study, 0, v, o);
    REQUIRE(h.collapsed);
    REQUIRE(first_overturn[v] > 0);
    // The ladder's first overturning lies in the hunt's bracket (width <= precision).
    CHECK(h.collapse_level - h.survived_level <= o.precision + 1e-12);
    CHECK(first_overturn[v] > h.survived_level);
    CHECK(first_overturn[v] <= h.collapse_level + 1e-9);
    // Both variants survive above their first overturning (El Centro is not
    // monotonic): the hunt reports it.
    CHECK_FALSE(h.resurrections.empty());
  }
  // With dampers the trace up meets a later window first (above 13); the fill finds the one near 10.4.
  const HuntResult damper = hunt_collapse(study, 0, 0, o);
  CHECK(damper.traced_level > 13.0);
  CHECK(damper.collapse_level < 10.5);
}

namespace {

// A summary of three copies of one record at levels 1, 2, 3 whose results are
// set by hand, not run. theta/alpha by record (rows) and level (columns); -1
// marks an overturning. Record 1 overturns at 2 and survives 3 (a resurrection).
const double hand_theta[3][3] = {{0.1, 0.3, 0.6}, {0.2, -1, 0.4}, {0.3, 0.7, -1}};

StudySummary hand_summary(const Study& study, Resurrection convention) {
  StudySummary summary(study, {2.0, 1.0, 3.0}, {overturning_limit(), parse_limit("theta_over_alpha=0.5")}, convention);
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t k = 0; k < 3; ++k) {
      JobResult res;
      res.run.outcome = hand_theta[r][k] < 0 ? Outcome::overturned : Outcome::completed;
      res.run.peaks[static_cast<std::size_t>(Quantity::theta_over_alpha)] = hand_theta[r][k] < 0 ? 1.0 : hand_theta[r][k];
      summary.add(study.at_level(r, 0, 1.0 + static_cast<double>(k)), res);
    }
  return summary;
}

std::vector<std::size_t> reached_counts(const std::vector<Stripe>& stripes) {
  std::vector<std::size_t> out;
  for (const Stripe& s : stripes) out.push_back(s.reached);
  return out;
}

}  // namespace

TEST_CASE("the summary's fractiles, capacities and stripes, worked by hand") {
  const std::string rec = pulse_record();
  const Study study(rigid_block(), {}, {rec, rec, rec}, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const StudySummary summary = hand_summary(study, Resurrection::first);
  CHECK(summary.levels() == std::vector<double>{1.0, 2.0, 3.0});
  const auto rows = summary.fractiles(0, Quantity::theta_over_alpha);
  REQUIRE(rows.size() == 3);
  // Level 1: 0.1 0.2 0.3 -> 16 %: 0.1 + 0.32 x 0.1; 50 %: 0.2; 84 %: 0.2 + 0.68 x 0.1.
  CHECK(rows[0].edp[0] == close_to(0.132, 1e-12));
  CHECK(rows[0].edp[1] == close_to(0.2, 1e-12));
  CHECK(rows[0].edp[2] == close_to(0.268, 1e-12));
  // Level 2: 0.3 0.7 inf -> the 84 % fractile falls on the collapse.
  CHECK(rows[1].collapsed == 1);
  CHECK(rows[1].edp[1] == close_to(0.7, 1e-12));
  CHECK(std::isinf(rows[1].edp[2]));
  // Overturning: record 0 never (censored at 3), record 1 at 2 (and survives 3), record 2 at 3.
  const auto over = summary.capacities(0, 0);
  REQUIRE(over.size() == 3);
  CHECK_FALSE(over[0].second.reached);
  CHECK(over[0].second.im == 3.0);
  CHECK((over[1].second.reached && over[1].second.im == 2.0));
  CHECK((over[2].second.reached && over[2].second.im == 3.0));
  // theta/alpha >= 0.5: record 0 at 3, record 1 at 2 (overturned), record 2 at 2.
  const auto half = summary.capacities(0, 1);
  CHECK(half[0].second.im == 3.0);
  CHECK(half[1].second.im == 2.0);
  CHECK(half[2].second.im == 2.0);
  const auto stripes = summary.stripes(0, 0);
  REQUIRE(stripes.size() == 3);
  CHECK(stripes[2].runs == 3);
  // A record's IDA curve stops at its first overturning.
  const auto curve = summary.curve(1, 0, Quantity::theta_over_alpha);
  CHECK(curve.points.size() == 1);
  CHECK(curve.collapse_level == 2.0);
  CHECK_THROWS_AS(parse_limit("theta=0.5"), InputError);
  CHECK_THROWS_AS(parse_limit("damper_d=-1"), InputError);
  CHECK_THROWS_AS(parse_limit("damper_d"), InputError);
  CHECK(parse_limit("damper_d=0.07").name == "damper_d>=0.07");
}

TEST_CASE("resurrections: the first-collapse convention against each level as it ran, worked by hand") {
  const std::string rec = pulse_record();
  const Study study(rigid_block(), {}, {rec, rec, rec}, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const StudySummary first = hand_summary(study, Resurrection::first), keep = hand_summary(study, Resurrection::keep);
  // Level 3 as it ran: 0.6, 0.4 (record 1 stands again), inf -> 16 %: 0.4 +
  // 0.32 x 0.2, 50 %: 0.6, 84 %: inf, one collapsed.
  const auto k3 = keep.fractiles(0, Quantity::theta_over_alpha)[2];
  CHECK(k3.collapsed == 1);
  CHECK(k3.edp[0] == close_to(0.464, 1e-12));
  CHECK(k3.edp[1] == close_to(0.6, 1e-12));
  CHECK(std::isinf(k3.edp[2]));
  // Record 1 collapsed from level 2 on: 0.6, inf, inf -> every fractile past
  // position 0 falls on a collapse; two collapsed.
  const auto f3 = first.fractiles(0, Quantity::theta_over_alpha)[2];
  CHECK(f3.collapsed == 2);
  CHECK(std::isinf(f3.edp[0]));
  CHECK(std::isinf(f3.edp[1]));
  // Levels 1 and 2 are the same either way.
  for (std::size_t k = 0; k < 2; ++k) {
    CHECK(first.fractiles(0, Quantity::theta_over_alpha)[k].edp == keep.fractiles(0, Quantity::theta_over_alpha)[k].edp);
    CHECK(first.fractiles(0, Quantity::theta_over_alpha)[k].collapsed == keep.fractiles(0, Quantity::theta_over_alpha)[k].collapsed);
  }
  // Stripes of overturning: 0, 1, 2 collapsed from the first on; 0, 1, 1 as run.
  CHECK(reached_counts(first.stripes(0, 0)) == std::vector<std::size_t>{0, 1, 2});
  CHECK(reached_counts(keep.stripes(0, 0)) == std::vector<std::size_t>{0, 1, 1});
  // theta/alpha >= 0.5: at level 3 record 0 (0.6), record 1 (reached at 2), record 2 (overturned).
  CHECK(reached_counts(first.stripes(0, 1)) == std::vector<std::size_t>{0, 2, 3});
  CHECK(reached_counts(keep.stripes(0, 1)) == std::vector<std::size_t>{0, 2, 2});
  // Capacities are the first level at the limit under both.
  for (std::size_t l = 0; l < 2; ++l) {
    const auto a = first.capacities(0, l), b = keep.capacities(0, l);
    REQUIRE(a.size() == b.size());
    for (std::size_t i = 0; i < a.size(); ++i) CHECK((a[i].second.im == b[i].second.im && a[i].second.reached == b[i].second.reached));
  }
  // The one resurrection, reported under both.
  for (const StudySummary* s : {&first, &keep}) {
    const auto res = s->resurrections(0);
    REQUIRE(res.size() == 1);
    CHECK(res[0].record == 1);
    CHECK(res[0].first_overturning == 2.0);
    CHECK(res[0].survived == std::vector<double>{3.0});
  }
  CHECK(parse_resurrection("keep") == Resurrection::keep);
  CHECK_THROWS_WITH_AS(parse_resurrection("last"), doctest::Contains("--resurrection 'last'"), InputError);
}

TEST_CASE("a suite's fragility: the bootstrap resamples records, the same seed gives the same intervals") {
  // Eight copies of one record at levels 1..6, each overturning first at a
  // level set by hand (record 7 never: censored at 6); results set, not run.
  const std::string rec = pulse_record();
  const std::vector<std::string> records(8, rec);
  const Study study(rigid_block(), {}, records, RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const std::vector<double> levels{1, 2, 3, 4, 5, 6};
  StudySummary summary(study, levels, {overturning_limit()});
  const int first_overturning[8] = {2, 3, 3, 4, 4, 5, 6, 99};
  for (std::size_t r = 0; r < 8; ++r)
    for (double level : levels) {
      JobResult res;
      res.run.outcome = level >= first_overturning[r] ? Outcome::overturned : Outcome::completed;
      summary.add(study.at_level(r, 0, level), res);
    }
  FragilityOptions o;
  o.bootstrap = {400, 11, 0.9};
  const LimitFragility a = summary.fragility(0, 0, o), b = summary.fragility(0, 0, o);
  REQUIRE(a.capacity_fit.fitted);
  CHECK(a.capacity_fit.method == "censored-mle");
  REQUIRE(a.capacity_bootstrap.computed());
  REQUIRE(a.stripes_bootstrap.computed());
  CHECK((a.capacity_bootstrap.median == b.capacity_bootstrap.median));
  CHECK((a.stripes_bootstrap.beta == b.stripes_bootstrap.beta));
  // The capacities' bootstrap is that of the capacities themselves (each
  // resample's search started from the whole sample's fit).
  std::vector<Capacity> caps;
  for (const auto& c : a.capacities) caps.push_back(c.second);
  const FitBootstrap direct = bootstrap_fit(caps.size(), [&](const std::vector<std::size_t>& s) {
    std::vector<Capacity> x;
    for (std::size_t i : s) x.push_back(caps[i]);
    return fit_capacities(x, &a.capacity_fit);
  }, o.bootstrap);
  CHECK((direct.median == a.capacity_bootstrap.median));
  CHECK((direct.beta == a.capacity_bootstrap.beta));
  // Each interval holds its fit.
  CHECK((a.capacity_bootstrap.median[0] < a.capacity_fit.median && a.capacity_fit.median < a.capacity_bootstrap.median[1]));
  CHECK((a.stripes_bootstrap.median[0] < a.stripes_fit.median && a.stripes_fit.median < a.stripes_bootstrap.median[1]));
  // Modelling dispersion: beta_total in the JSON, the median unchanged.
  o.beta_modelling = 0.3;
  const nlohmann::json j = fragility_json(summary.fragility(0, 0, o), records);
  CHECK(j["capacity_fit"]["beta_total"].get<double>() ==
        close_to(std::hypot(a.capacity_fit.beta, 0.3), 1e-12));
  CHECK(j["capacity_fit"]["median"].get<double>() == a.capacity_fit.median);
  CHECK(j["capacity_fit"]["bootstrap"]["draws"].get<std::size_t>() == 400);
  o.beta_modelling = -1;
  CHECK_THROWS_WITH_AS(summary.fragility(0, 0, o), doctest::Contains("--beta-modelling"), InputError);
}
