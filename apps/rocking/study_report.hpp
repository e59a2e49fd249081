// What `rocking ida` and `rocking sweep` report over a suite of records
// (MODEL.md 13): summary.csv (fractile IDA curves), fragility.csv and
// fragility_points.csv (each limit state's lognormal fits and their data),
// summary.json (all of it), and the figures: one per quantity across the
// suite, one of the fragility curves.
#pragma once
#include "commands.hpp"
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace rocking::app {

// A CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string csv_field(const std::string& s);

// An intensity measure in words for titles ("PGA", "Sa(0.46 s), 5 %").
std::string im_words(const rocking::IntensityMeasure& im);

// The axis label of an intensity measure ("PGA [g]", "scale factor [-]").
std::string im_axis_label(const rocking::IntensityMeasure& im);

// Each variant's fragility for each limit state that applies to it ([variant][limit];
// none where it does not apply), the (variant, limit) pairs on `threads` threads.
using SuiteFragility = std::vector<std::vector<std::optional<rocking::LimitFragility>>>;
SuiteFragility suite_fragility(const rocking::Study& st, const rocking::StudySummary& summary,
                               const rocking::FragilityOptions& options, int threads);

// Writes the summary files of a ladder into dir; prints each variant's
// overturning fragility in one line, and its records that survive above
// their first overturning.
void write_ladder_report(const std::filesystem::path& dir, const rocking::Study& st,
                         const rocking::StudySummary& summary, const SuiteFragility& fragility,
                         const std::vector<std::string>& ids);
// The suite figures of a ladder (IDA curves with fractiles per quantity, the
// fragility curves with their bootstrap bands, and with two or more limit
// states the damage states in one panel per variant); returns the files written.
std::vector<std::filesystem::path> draw_ladder_report(const std::filesystem::path& dir, const rocking::Study& st,
                                                      const rocking::StudySummary& summary,
                                                      const SuiteFragility& fragility, const std::string& kind,
                                                      const std::string& scene_name,
                                                      const std::vector<std::string>& formats);

// The overturning fragility of hunts, one per (record, variant) in order:
// fragility.csv, fragility_points.csv and summary.json in dir.
void write_hunt_report(const std::filesystem::path& dir, const rocking::Study& st,
                       const std::vector<rocking::HuntResult>& hunts, const std::vector<std::string>& ids,
                       const rocking::FragilityOptions& options);

}  // namespace rocking::app
