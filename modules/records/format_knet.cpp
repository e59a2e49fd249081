// K-NET and KiK-net ASCII files (NIED, Japan; one component a file, .EW .NS
// .UD, KiK-net .EW1 .EW2 ...): 17 header lines "Name  value" with the value
// from column 19 ("Sampling Freq(Hz) 100Hz", "Duration Time(s) 102",
// "Dir. E-W", "Scale Factor 3920(gal)/6182761", "Max. Acc. (gal) 4.078"),
// then integer counts, eight a line. Acceleration [gal] = counts x the scale
// factor, with the record's mean removed, as the format requires; the stated
// Max. Acc. is the peak of that.
module;
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking::records {

namespace {

constexpr std::size_t header = 17;

bool detect(const std::string&, const std::vector<Line>& lines) {
  return !lines.empty() && lines[0].text.starts_with("Origin Time");
}

// The value of header line `index` (0-based), which must start with `name`.
std::string field(const std::string& path, const std::vector<Line>& lines, std::size_t index, std::string_view name) {
  if (index >= lines.size() || !lines[index].text.starts_with(name))
    fail(path, index < lines.size() ? lines[index].number : static_cast<int>(lines.size()),
         fmt::format("expected the K-NET header line '{}' (line {} of 17)", name, index + 1));
  return trim(std::string_view(lines[index].text).substr(name.size()));
}

double positive(const std::string& path, const Line& line, std::string_view text, std::string_view what) {
  const std::optional<double> v = whole_number(text);
  if (!v || !(*v > 0) || !std::isfinite(*v))
    fail(path, line.number, fmt::format("{} '{:.40}' is not a positive number", what, text));
  return *v;
}

GroundMotion read(const std::string& path, const std::vector<Line>& lines, const RecordOptions& o) {
  refuse_component(path, o, "K-NET");
  RecordInfo info;
  const std::string origin = field(path, lines, 0, "Origin Time");
  const std::string magnitude = field(path, lines, 4, "Mag.");
  info.station = field(path, lines, 5, "Station Code");
  info.date = origin + " JST";
  info.event = magnitude.empty() ? origin : fmt::format("M{} {}", magnitude, origin);
  std::string freq = field(path, lines, 10, "Sampling Freq(Hz)");
  if (freq.ends_with("Hz")) freq.resize(freq.size() - 2);
  const double rate = positive(path, lines[10], freq, "Sampling Freq");
  const double duration = positive(path, lines[11], field(path, lines, 11, "Duration Time(s)"), "Duration Time");
  info.component = field(path, lines, 12, "Dir.");
  // "3920(gal)/6182761": gal per count.
  const std::string sf = field(path, lines, 13, "Scale Factor");
  const std::size_t slash = sf.find('/'), gal = sf.find("(gal)");
  if (slash == std::string::npos || gal == std::string::npos || gal > slash)
    fail(path, lines[13].number, fmt::format("Scale Factor '{:.40}' is not 'N(gal)/M'", sf));
  const double factor = positive(path, lines[13], sf.substr(0, gal), "Scale Factor") /
                        positive(path, lines[13], sf.substr(slash + 1), "Scale Factor");
  const std::string max_text = field(path, lines, 14, "Max. Acc. (gal)");
  field(path, lines, 15, "Last Correction");
  field(path, lines, 16, "Memo.");
  refuse_dt(path, lines[10].number, o, 1.0 / rate);
  const AccelerationUnit unit = file_unit(path, lines[13].number, AccelerationUnit::cm_per_s2, o);
  // Counts to m/s^2, then less their mean.
  std::vector<double> values;
  for (std::size_t i = header; i < lines.size(); ++i)
    for (double v : numbers_of(path, lines[i])) {
      values.push_back(v * factor * to_si(unit));
      check_acceleration(path, lines[i].number, values.back());
    }
  // The file states its length in whole seconds: the count is rate x duration.
  const double expected = rate * duration;
  if (std::abs(static_cast<double>(values.size()) - expected) > 0.5)
    fail(path, lines.back().number, fmt::format("{} Hz for {} s is {} samples, but the file holds {}", rate, duration,
                                                expected, values.size()));
  double mean = 0;
  for (double v : values) mean += v;
  mean /= static_cast<double>(std::max<std::size_t>(values.size(), 1));
  for (double& v : values) v -= mean;
  info.units = "gal";
  const std::optional<double> peak = whole_number(max_text);
  if (!peak || !std::isfinite(*peak)) fail(path, lines[14].number, fmt::format("Max. Acc. '{:.40}' is not a number", max_text));
  info.stated_peak = std::abs(*peak) * to_si(unit);
  return evenly_sampled(path, lines[14].number, std::move(values), 1.0 / rate, std::move(info),
                        printed_resolution(max_text) * to_si(unit));
}

// The 17 header lines, then counts of 0.0981 gal (1e-4 g), eight a line.
std::string example() {
  const ExampleRecord e = example_record();
  std::vector<long> counts;
  long peak = 0;
  for (double g : e.values) {
    counts.push_back(std::lround(g * 1e4));
    peak = std::max(peak, std::abs(counts.back()));
  }
  std::string s = "Origin Time       2000/01/01 00:00:00\nLat.              35.000\nLong.             139.000\n"
                  "Depth. (km)       10\nMag.              5.5\nStation Code      XXX000\nStation Lat.      35.100\n"
                  "Station Long.     139.100\nStation Height(m) 10\nRecord Time       2000/01/01 00:00:10\n"
                  "Sampling Freq(Hz) 100Hz\nDuration Time(s)  1\nDir.              N-S\n"
                  "Scale Factor      981(gal)/10000\n";
  s += fmt::format("Max. Acc. (gal)   {:.3f}\n", static_cast<double>(peak) * 0.0981);
  s += "Last Correction   2000/01/01 00:00:10\nMemo.\n";
  for (std::size_t i = 0; i < counts.size(); ++i)
    s += fmt::format("{:9}{}", counts[i], i % 8 == 7 || i + 1 == counts.size() ? "\n" : "");
  return s;
}

}  // namespace

FormatReader knet_format() {
  return {"knet", "K-NET/KiK-net ASCII (Japan; counts x Scale Factor in gal, mean removed)", detect, read, example};
}

}  // namespace rocking::records
