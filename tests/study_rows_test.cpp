// A study's rows (rocking.study's StudyRow) from the run to the files:
// the summary a ladder gathers holds every study column of the rows it
// writes, a rocking frame's columns' peaks among them (a single record's
// median at a level is that record's peak there, as the CSV writes it), and
// a row of the study CSV read back is the row the run made, to the digits
// written.
#include <doctest/doctest.h>
#include "sanitizers.hpp"
#include "temp_path.hpp"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <numeric>
#include <string>
#include <vector>
import rocking.study_run;

using namespace rocking;
namespace fs = std::filesystem;

namespace {

// A one-sine pulse, 0.4 g and 0.5 s, sampled every 5 ms, then 1.5 s of rest:
// a two-column record (t [s], a [g]).
std::string pulse_record() {
  const fs::path file = temp_path("study_rows_pulse.txt");
  std::ofstream out(file);
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.005 * i;
    out << t << ' ' << (t <= 0.5 ? 0.4 * std::sin(2 * std::numbers::pi * t / 0.5) : 0.0) << '\n';
  }
  return file.string();
}

// The peak as the study CSV holds it (9 significant digits).
double as_written(double v) { return std::stod(peak_field(v)); }

}  // namespace

TEST_CASE("a rocking frame's ladder: its summary holds the columns' peaks its rows write, and each row read back from the CSV is the row the run made") {
  const std::string rec = pulse_record();
  const Study study(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rocking_frame.toml", {}, {rec}, RecordOptions{},
                    {named_variant("scene")}, RunOptions{});
  const Ladder ladder = plan_ladder(study, {0.5, 1.0, 2.0}, {});
  const StudyColumns& columns = ladder.columns;
  const QuantityName theta(Quantity::columns_theta_over_alpha);
  REQUIRE(columns.index(theta).has_value());
  StudySummary summary(study, ladder.levels, ladder.limits);
  std::vector<std::size_t> all(ladder.jobs.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  std::vector<JobResult> results(ladder.jobs.size());
  const std::size_t emitted = run_ladder(study, ladder, all, 1, &summary,
                                         [&](std::size_t i, const JobResult& r) { results[i] = r; }, {});
  REQUIRE(emitted == ladder.jobs.size());
  const std::vector<StudySummary::FractileRow> fractiles = summary.fractiles(0, theta);
  std::size_t standing = 0;
  const std::vector<std::string> ids = record_ids(study.records());
  for (std::size_t i = 0; i < ladder.jobs.size(); ++i) {
    const Job& job = ladder.jobs[i];
    const JobResult& r = results[i];
    REQUIRE(r.error.empty());
    // One record: the median at the level is its peak there (+inf once it collapsed).
    const double peak = r.run.peak(Quantity::columns_theta_over_alpha);
    CHECK(std::isfinite(peak));
    const auto at = std::ranges::find(fractiles, job.level, &StudySummary::FractileRow::level);
    REQUIRE(at != fractiles.end());
    if (!past_every_limit(r.run.outcome)) {
      ++standing;
      CHECK(at->edp[1] == as_written(peak));
    } else {
      CHECK(std::isinf(at->edp[1]));
    }
    // The CSV row read back: the job's level, each column's peak to 9 digits, its outcome.
    const StudyRow made = written_row(columns, job, r);
    const StudyRow read = read_study_row(columns, study_csv_row(study, columns, ids, job, r));
    CHECK(read.ran);
    CHECK(read.level == job.level);
    CHECK(read.outcome == r.run.outcome);
    CHECK(read.collapsed() == past_every_limit(r.run.outcome));
    REQUIRE(read.values.size() == columns.size());
    REQUIRE(made.values.size() == columns.size());
    for (std::size_t k = 0; k < columns.size(); ++k) {
      CHECK(std::isnan(read.values[k]) == std::isnan(made.values[k]));
      if (!std::isnan(made.values[k])) CHECK(read.values[k] == made.values[k]);
    }
    CHECK(read.value(columns, theta) == as_written(peak));
  }
  CHECK(standing > 0);
}

TEST_CASE("a job that could not run: its row has no peaks, reads back as not run, and the summary leaves it out") {
  const Study study(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml", {}, {"no_such_record.at2"},
                    RecordOptions{}, {named_variant("scene")}, RunOptions{});
  const Ladder ladder = plan_ladder(study, {1.0}, {});
  const JobResult r = study.run(ladder.jobs[0]);
  REQUIRE_FALSE(r.error.empty());
  const StudyRow made = study_row(ladder.columns, ladder.jobs[0], r);
  CHECK_FALSE(made.ran);
  CHECK(made.values.empty());
  CHECK_FALSE(made.collapsed());
  const StudyRow read = read_study_row(ladder.columns, study_csv_row(study, ladder.columns, record_ids(study.records()),
                                                                      ladder.jobs[0], r));
  CHECK_FALSE(read.ran);
  CHECK(read.values.empty());
  StudySummary summary(study, ladder.levels, ladder.limits);
  summary.add(ladder.jobs[0], read);
  CHECK(summary.capacities(0, 0).empty());
}
