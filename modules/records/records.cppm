// rocking.records: ground-motion records read from the files the field keeps
// them in (MODEL.md 10), one reader per format (format_*.cpp, registered in
// formats.cpp), the format detected from the content:
//   at2:     PEER .AT2 (the three header styles of shared/data/records/SOURCES.md),
//   geonet:  GeoNet V1A/V2A (New Zealand; three components per file, mm/s^2),
//   knet:    K-NET / KiK-net ASCII (counts x Scale Factor = gal, mean removed),
//   cosmos:  COSMOS V1/V2 (V2c; units and time step from its headers),
//   csv:     a header row naming the time and acceleration columns and units,
//   columns: one (acceleration, with dt given) or two (time, acceleration) columns.
// Each reader checks the data against the header it read (the count, and the
// peak the file states where it states one) and keeps the file's metadata.
// Record suites (suites.cpp): folders and list files of records.
// Every reader error is an InputError of one line: file:line and what is wrong.
// The motion itself, its units, processing and components are
// rocking.ground_motion's.
module;
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.records;
export import rocking.ground_motion;

export namespace rocking {

struct RecordFormatInfo {
  std::string name, description;
  // A small file of this format holding example_record() in the format's
  // unit, its headers stating what that format states: what a new file of
  // the format looks like, and what the tests that cover every format read
  // (made when asked: listing the formats, as every --help does, makes none).
  std::string (*example)() = nullptr;
};
// The samples every format's example holds: 0.3 g sin(2 pi i / 25) for
// i = 0 .. 99, 0.01 s apart (four whole cycles: a mean of zero).
struct ExampleRecord {
  double dt = 0.01;             // [s]
  std::vector<double> values;   // [g]
};
ExampleRecord example_record();
// Every format read_record knows, in the order detection tries them.
std::vector<RecordFormatInfo> record_formats();

GroundMotion read_record(const std::string& path, const RecordOptions& options = {});
// Whether some reader recognises the file's content as its format.
bool is_record_file(const std::string& path);

// Record suites (suites.cpp): the record files one argument names. A folder
// gives its files that a reader recognises, sorted by name (the others are
// added to `skipped`); a list file (every line that is not blank or a #
// comment names an existing file, relative to the list's folder) gives those
// files; anything else is itself (a file that cannot be read fails its own
// jobs, not the study).
std::vector<std::string> record_paths(const std::string& argument, std::vector<std::string>* skipped = nullptr);
// The files a list names, relative to `base` when not absolute; InputError
// naming the list's line of a file that does not exist.
std::vector<std::string> read_record_list(const std::string& list, const std::string& base);

}  // namespace rocking

// The readers' shared parts, seen by this module's own units only (not
// exported). A format is one file, format_NAME.cpp, defining its
// FormatReader NAME_format(), and its line in formats.cpp registering it.
namespace rocking::records {

struct Line {
  int number;        // 1-based
  std::string text;  // without the line end (CR stripped)
};

struct FormatReader {
  std::string name;         // what --format takes
  std::string description;  // for --help and for a file of no known format
  // Whether `lines` look like this format (only the first few are needed).
  bool (*detect)(const std::string& path, const std::vector<Line>& lines);
  GroundMotion (*read)(const std::string& path, const std::vector<Line>& lines, const RecordOptions& options);
  // A file of this format holding example_record() (RecordFormatInfo::example).
  std::string (*example)();
};


std::vector<Line> read_lines(const std::string& path);
[[noreturn]] void fail(const std::string& path, int line, std::string_view what);
// The number that is all of `field` (blanks aside); text or a non-finite
// value is an error at that line.
double number_at(const std::string& path, int line, std::string_view field);
// The numbers of one line separated by spaces, tabs or commas; text among
// them is an error at that line.
std::vector<double> numbers_of(const std::string& path, const Line& line);
// Fixed-width Fortran fields (10 x F8.1 ...): numbers that may touch; a
// blank field ends the line. Text in a field is an error at that line.
std::vector<double> fixed_fields(const std::string& path, const Line& line, std::size_t width);
// A number that is all of `text` after trimming blanks ("1e" is not 1).
std::optional<double> whole_number(std::string_view text);
// Where `key` (upper case; compared ignoring case) stands in `text`, or npos.
std::size_t find_word(std::string_view text, std::string_view key, std::size_t from = 0);
// The value of "KEY = value" in a header line, up to a space or comma.
std::optional<std::string> header_field(std::string_view text, std::string_view key);
std::string trim(std::string_view text);
std::string lower(std::string text);
// Runs of spaces as one ("2016 November 13     11:02" -> "2016 November 13 11:02").
std::string collapse_spaces(std::string text);
// The fields of a line: at `separator`, each trimmed (every field kept, empty
// ones too); with ' ', the words between runs of blanks.
std::vector<std::string> split_fields(std::string_view text, char separator);
// Half a unit of the last digit printed in `number` ("-9733.1" -> 0.05).
double printed_resolution(std::string_view number);
bool blank_or_comment(const Line& l);
// Each acceleration [m/s^2] within max_acceleration_g, or an error at its line.
void check_acceleration(const std::string& path, int line, double a_si);
// A unit the file states and the one the user gave must agree.
AccelerationUnit file_unit(const std::string& path, int line, AccelerationUnit stated, const RecordOptions& o);
// Options a format of one component and its own time step cannot take.
void refuse_component(const std::string& path, const RecordOptions& o, std::string_view format);
void refuse_dt(const std::string& path, int line, const RecordOptions& o, double stated_dt);
// Evenly sampled values [m/s^2] from t = 0 as a record, with the file's
// metadata; the stated peak, when there is one, checked against the data
// (within 0.1 % and half a unit of its last printed digit, `resolution`).
GroundMotion evenly_sampled(const std::string& path, int header_line, std::vector<double> values, double dt,
                            RecordInfo info, double stated_resolution = 0);

// Samples with their own times, as a table gives them, checked one by one
// where they are read: starting at t >= 0, times increasing and within
// max_record_duration, accelerations within max_acceleration_g.
class TimedSamples {
 public:
  void add(const std::string& path, int line, double t, double a_si);
  std::size_t size() const { return a_.size(); }
  // The record (at least two samples, else an error at `last_line`).
  GroundMotion record(const std::string& path, int last_line, RecordInfo info) &&;

 private:
  std::vector<double> t_, a_;
};

}  // namespace rocking::records
