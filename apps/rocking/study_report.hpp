// The figures `rocking ida` and `rocking sweep` draw over a suite of records
// (MODEL.md 13): one per quantity across the suite, one of the fragility
// curves (the files beside them come from rocking.study_files).
#pragma once
#include "commands.hpp"
#include <filesystem>
#include <optional>
#include <string>
#include <vector>
import rocking.study;
import rocking.study_files;

namespace rocking::app {

// An intensity measure in words for titles ("PGA", "Sa(0.46 s), 5 %").
std::string im_words(const rocking::IntensityMeasure& im);

// The axis label of an intensity measure ("PGA [g]", "scale factor [-]").
std::string im_axis_label(const rocking::IntensityMeasure& im);

// The suite figures of a ladder (IDA curves with fractiles per quantity, the
// fragility curves with their bootstrap bands, and with two or more limit
// states the damage states in one panel per variant); returns the files written.
std::vector<std::filesystem::path> draw_ladder_report(const std::filesystem::path& dir, const rocking::Study& st,
                                                      const rocking::StudySummary& summary,
                                                      const SuiteFragility& fragility, const std::string& kind,
                                                      const std::string& scene_name,
                                                      const std::vector<std::string>& formats);

}  // namespace rocking::app
