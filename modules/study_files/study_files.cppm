// rocking.study_files: the files of a suite study (MODEL.md 13), as text and
// JSON, so that `rocking ida`/`rocking sweep` and Python's Ida.write make the
// same files from the same results: the rows of ida.csv / sweep.csv (the
// job's fields, the study's columns, the run's outcome and cost), hunt.csv
// and hunt_points.csv, records.csv, and the suite's report: summary.csv (the
// 16/50/84 % fractile IDA curves), fragility.csv and fragility_points.csv
// (each limit state's lognormal fits and their data) and summary.json (all
// of it). Fields a run is resumed from are written as their shortest exact
// decimal; peaks to 9 significant digits, summaries to 6.
module;
#include <nlohmann/json.hpp>
#include <cstddef>
#include <filesystem>
#include <istream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.study_files;
export import rocking.study;

export namespace rocking {

// A CSV field: quoted (with "" for ") when it holds a comma, quote or newline.
std::string csv_field(const std::string& s);
// A number as its shortest exact decimal (read back to the same double); empty when not finite.
std::string exact_number(double v);
// A peak as the CSV writes it: empty when the run does not report it (NaN).
std::string peak_field(double v);

// A record as rows and figures name it: its file name, or as many of its
// last path components as make it unique among the study's records (two
// "a.at2" in folders x/ and y/ become "x/a.at2" and "y/a.at2"); the same file
// given twice becomes "a.at2" and "a.at2#2".
std::vector<std::string> record_ids(const std::vector<std::string>& paths);

// ida.csv / sweep.csv: the job's fields (record, scale, variant, im, level,
// record_im), the study's columns (StudyColumns: the schema's study
// quantities, then each device's by name), then the run's outcome and cost
// (top_total_mm, outcome, uplifts, impacts, rhs, error).
std::string study_csv_header(const StudyColumns& columns);
std::string job_fields(const Study& st, const std::vector<std::string>& ids, const Job& job);
std::string study_csv_row(const Study& st, const StudyColumns& columns, const std::vector<std::string>& ids,
                          const Job& job, const JobResult& r);
// The fields of a study's CSV row (no field but the last, the error, holds a
// quoted comma).
std::vector<std::string> csv_fields(const std::string& row);
// The row as the files hold it: its peaks rounded to the digits the CSV
// writes (peak_field). What every front end adds to a StudySummary and draws,
// so that a study's summary and figures are the same whether its runs were
// fresh, resumed from rows or sent by other processes.
StudyRow written_row(const StudyColumns& columns, const Job& job, const JobResult& r);
// A row of the study CSV read back (`row` as study_csv_row wrote it): its
// level, peaks and outcome by the names of study_csv_header's columns; an
// error row did not run. InputError when a field is not a number.
StudyRow read_study_row(const StudyColumns& columns, const std::string& row);

// What an interrupted study left in its CSV (`name`: the file, for messages):
// its rows in job order, each checked against the job it must be. rows: the
// text of each row kept; results: each as a StudyRow; rerun: why the rows
// stop early when a row holds a value that is not a finite number (that job
// and every one after it run again), else empty. A last line without its
// newline was cut: its job runs again. InputError naming the file and line
// for a header or row of another study or version.
struct ResumedRows {
  std::vector<std::string> rows;
  std::vector<StudyRow> results;
  std::string rerun;
};
ResumedRows read_resumed_rows(std::istream& in, const std::string& name, const std::vector<Job>& jobs,
                              const std::vector<std::string>& ids, const Study& st, const StudyColumns& columns);

// records.csv: what each record id is, as its file says.
std::string records_csv(const Study& st, const std::vector<std::string>& ids);

// hunt.csv: one row per (record, variant); hunt_points.csv: every level each
// hunt ran and why.
extern const std::string hunt_csv_header, hunt_points_header;
// The first fields of both: record, variant, im.
std::string hunt_fields(const std::string& record, const std::string& variant, const IntensityMeasure& im);
// A hunt's row as values, by hunt.csv's column names: null where the CSV is
// empty (no collapse, no error), resurrections as [from, to] pairs. The CSV
// row is written from it, and Python's Ida.hunts holds it.
nlohmann::json hunt_json(const HuntResult& h, const std::string& record, const std::string& variant,
                         const IntensityMeasure& im, const HuntOptions& o);
std::string hunt_csv_row(const HuntResult& h, const std::string& record, const std::string& variant,
                         const IntensityMeasure& im, const HuntOptions& o);
std::string hunt_points_rows(const HuntResult& h, const std::string& record, const std::string& variant,
                             const IntensityMeasure& im);
// A hunt's resurrections as "1.2-1.4 1.7" (levels at which it stands again).
std::string ranges_text(const std::vector<std::pair<double, double>>& ranges);

// Whether a variant can reach a limit at all (a fixed base never overturns).
bool limit_applies(const Study& st, std::size_t variant, const Limit& limit);
// Each variant's fragility for each limit state that applies to it
// ([variant][limit]; none where it does not apply), the (variant, limit)
// pairs on `threads` threads.
using SuiteFragility = std::vector<std::vector<std::optional<LimitFragility>>>;
SuiteFragility suite_fragility(const Study& st, const StudySummary& summary, const FragilityOptions& options,
                               int threads);

// A study's report: the files' texts, and the lines a user is told (each
// variant's overturning fits; the records that stand again above their first
// overturning).
struct StudyReport {
  std::string summary_csv;  // a ladder's fractiles (empty for a hunt)
  std::string fragility_csv, fragility_points_csv;
  nlohmann::json summary;   // summary.json
  std::vector<std::string> notes;
};
StudyReport ladder_report(const Study& st, const StudySummary& summary, const SuiteFragility& fragility,
                          const std::vector<std::string>& ids);
// The overturning fragility of hunts, one per (record, variant), record-major.
StudyReport hunt_report(const Study& st, const std::vector<HuntResult>& hunts, const std::vector<std::string>& ids,
                        const FragilityOptions& options);
// Writes the report's files into dir (summary.csv for a ladder only); returns the paths written.
std::vector<std::filesystem::path> write_report(const std::filesystem::path& dir, const StudyReport& report);

// Writes text to file whole: into a file beside it, renamed to its name once
// the file there is removed, so a file is never left partial under its name.
// RunError naming the file.
void write_text(const std::filesystem::path& file, const std::string& text);

}  // namespace rocking
