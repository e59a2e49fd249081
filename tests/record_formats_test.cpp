// Record formats (rocking.ground_motion readers): the real GeoNet V2A, K-NET
// and COSMOS files of shared/data/records/formats read with the peak their
// own headers state; files of each format written here (other stations,
// counts, time steps) read the same way; headed CSV; and the malformed files
// of each format refused in one line naming the file and line.
#include <doctest/doctest.h>
#include "close.hpp"
#include "temp_path.hpp"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <fmt/format.h>
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

// A GeoNet V2A component: values [mm/s^2] at dt, with velocity and
// displacement blocks of the same count, in ten 8-character fields a line.
std::string v2a_component(const std::string& name, const std::vector<double>& acc, double dt, double stated_peak) {
  auto rows = [](const std::vector<double>& v, const char* format) {
    std::string out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      out += fmt::format(fmt::runtime(format), v[i]);
      if (i % 10 == 9 || i + 1 == v.size()) out += "\n";
    }
    return out;
  };
  std::string s;
  s += "Corrected accelerogram 20230101_000000_TEST_20 GNS Science\n";
  s += "Site TEST      41 00 00S  174 00 00E     Cusp file:  20230101_000000_TEST\n";
  s += "Test Station Road\nInstrument Cusp_1\nResolution: 18-bit   Instr Period: 0.0050 s   Damping: 0.700\n";
  s += "Accelerogram 20230101_000000_TEST_20                 Processed 2023 January 02\n";
  s += "10 km north of Testville\n2023 January 01         00:00:00 UT\n";
  s += "Epicentre  41 00 00S 174 00 00E  Bearing N00E  Dist   10km  Depth   10km Mw 6.10\n";
  s += fmt::format("Number of points  {}    Duration {:.2f} sec\n", acc.size(), dt * acc.size());
  s += fmt::format("Instrument corrected data at {:.3f} sec intervals\n", dt);
  s += "Band-pass filter transition bands are .10-.25 Hz and 24.50-25.50 Hz\n";
  s += fmt::format("Component {}  Longitudinal Accelerometer Axis\n", name);
  s += fmt::format("Acceleration:  peak  {:.1f} mm/s/s at   1.00 sec     rms    1.0 mm/s/s\n", stated_peak);
  s += "Velocity:      peak    1.00 mm/s   at   1.00 sec     rms    1.00 mm/s\n";
  s += "Displacement:  peak   1.000 mm     at   1.00 sec     rms    1.000 mm\n";
  std::vector<double> ints(40, 0.0), reals(60, 0.0);
  ints[33] = static_cast<double>(acc.size());
  ints[34] = static_cast<double>(acc.size());
  ints[35] = static_cast<double>(acc.size());
  reals[0] = 200.0;
  reals[25] = dt;
  s += rows(ints, "{:8.0f}") + rows(reals, "{:8.4f}");
  s += rows(acc, "{:8.1f}") + rows(std::vector<double>(acc.size(), 0.0), "{:8.1f}") +
       rows(std::vector<double>(acc.size(), 0.0), "{:8.1f}");
  return s;
}

std::string v2a(std::size_t n, double dt) {
  std::vector<double> a(n), b(n), c(n);
  for (std::size_t i = 0; i < n; ++i) {
    a[i] = 100.0 * std::sin(0.3 * i);
    b[i] = -2.0 * a[i];
    c[i] = 0.5 * a[i];
  }
  auto peak = [](const std::vector<double>& v) {
    double p = 0;
    for (double x : v) p = std::abs(x) > std::abs(p) ? x : p;
    return p;
  };
  return v2a_component("N10E", a, dt, peak(a)) + v2a_component("N80W", b, dt, peak(b)) +
         v2a_component("Up", c, dt, peak(c));
}

std::string knet(const std::vector<long>& counts, const std::string& scale = "Scale Factor      2000(gal)/8388608",
                 const std::string& max_acc = "") {
  double mean = 0;
  for (long c : counts) mean += static_cast<double>(c);
  mean /= static_cast<double>(counts.size());
  double peak = 0;
  for (long c : counts) peak = std::max(peak, std::abs((static_cast<double>(c) - mean) * 2000.0 / 8388608.0));
  std::string s = "Origin Time       2020/01/01 00:00:00\nLat.              35.0\nLong.             139.0\n"
                  "Depth. (km)       10\nMag.              5.5\nStation Code      TKY999\nStation Lat.      35.5\n"
                  "Station Long.     139.5\nStation Height(m) 10\nRecord Time       2020/01/01 00:00:10\n"
                  "Sampling Freq(Hz) 50Hz\n";
  s += fmt::format("Duration Time(s)  {}\nDir.              N-S\n{}\n", counts.size() / 50, scale);
  s += max_acc.empty() ? fmt::format("Max. Acc. (gal)   {:.3f}\n", peak) : max_acc + "\n";
  s += "Last Correction   2020/01/01 00:00:10\nMemo.             \n";
  for (std::size_t i = 0; i < counts.size(); ++i) s += fmt::format("{:9}{}", counts[i], i % 8 == 7 ? "\n" : "");
  return s;
}

std::vector<long> knet_counts(std::size_t n) {
  std::vector<long> c(n);
  for (std::size_t i = 0; i < n; ++i) c[i] = 1000 + static_cast<long>(std::lround(50000 * std::sin(0.05 * i)));
  return c;
}

// A COSMOS V2 file: 8 values a line in F10.3, in the unit `code` (04 cm/s2, 02 g).
std::string cosmos(const std::vector<double>& acc, double dt_ms, int code, const std::string& unit) {
  double peak = 0;
  for (double x : acc) peak = std::abs(x) > std::abs(peak) ? x : peak;
  std::string s = "Corrected acceleration    (Format v01.20 with 13 text lines)\n"
                  "Record of Test Earthquake of Sun Jan 1, 2023 00:00 UTC\nHypocenter: 0 0 H= 10km Mw=6.0\n"
                  "Origin: 2023/01/01 00:00:00 UTC\nStatn No: 01-00001 Code:XX-TST  NET  Test Site, CA, USA\n"
                  "Coords: 0 0  Site geology:\nRecorder: x\nRcrd start time: 2023/01/01 00:00:01 UTC\n"
                  "Sta Chan   1:N00E\nRaw record length = 1.000 sec\n";
  s += fmt::format("Processed:2023-01-02, TEST, Max = {:10.3f} {} at 1.000 sec\n", peak, unit);
  s += "Record filtered below 0.1 Hz\nValues used when parameter or data value is unknown/unspecified:   -999, -999.00\n";
  s += " 100 Integer-header values follow on  10 lines, Format= (10I8)\n";
  for (int i = 0; i < 100; ++i) s += fmt::format("{:8}{}", -999, i % 10 == 9 ? "\n" : "");
  s += " 100 Real-header values follow on  20 lines, Format= (5F15.6)\n";
  for (int i = 0; i < 100; ++i) s += fmt::format("{:15.6f}{}", i == 61 ? dt_ms : -999.0, i % 5 == 4 ? "\n" : "");
  s += "   1 Comment line(s) follow, each starting with a \"|\":\n|<SCNL>TST.HN1.XX.--\n";
  s += fmt::format("{:8} acceleration pts, approx   1 secs, units={}({:02}),Format=(8F10.3)\n", acc.size(), unit, code);
  for (std::size_t i = 0; i < acc.size(); ++i) s += fmt::format("{:10.3f}{}", acc[i], i % 8 == 7 || i + 1 == acc.size() ? "\n" : "");
  s += "End-of-data for Chan  1 acceleration\n";
  return s;
}

}  // namespace

TEST_CASE("the real GeoNet, K-NET and COSMOS files read with the peak their headers state") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string f = *dir + "/formats/";
  // V2A: "Acceleration: peak -9733.1 mm/s/s" for N28W; 7966.4 for S62W.
  const GroundMotion w = read_record(f + "20161113_110259_WTMC_20.V2A");
  CHECK(w.info().format == "geonet");
  CHECK(w.info().component == "N28W");
  CHECK(w.info().station.starts_with("WTMC"));
  CHECK(w.info().npts == 8192);
  CHECK(w.info().dt == close_to(0.02, 1e-12));
  CHECK(w.peak() == close_to(9.7331, 1e-3));
  CHECK(w.info().stated_peak.value() == close_to(9.7331, 1e-12));
  // "at 44.88 sec" from the trigger, 5 s (real-header field (3,2)) into the record.
  CHECK(std::abs(w.acceleration(44.88 + 5.0)) == close_to(w.peak(), 1e-12));
  const GroundMotion w2 = read_record(f + "20161113_110259_WTMC_20.V2A", {.component = "S62W"});
  CHECK(w2.peak() == close_to(7.9664, 1e-3));
  CHECK(read_record(f + "20161113_110259_WTMC_20.V2A", {.component = "3", .read_as = ReadAs::any}).info().component == "Up");
  // K-NET: counts x 3920/6182761 gal, mean removed; "Max. Acc. (gal) 4.078".
  const GroundMotion k = read_record(f + "AOM0011801241951.EW");
  CHECK(k.info().format == "knet");
  CHECK(k.info().station == "AOM001");
  CHECK(k.info().component == "E-W");
  CHECK(k.info().npts == 10200);
  CHECK(k.info().dt == close_to(0.01, 1e-12));
  CHECK(k.peak() == close_to(0.04078, 1e-3));
  CHECK_MESSAGE(k.description().ends_with(", PGA 0.0042 g"), k.description());  // 0.04078 m/s2, not "0.00 g"
  // COSMOS V2c: "Max = -6.852 cm/sec2".
  // A vertical channel (BNZ), read as measured, whichever its direction.
  const GroundMotion c = read_record(f + "us1000hyfh_akbmrp_bnz.V2c", {.read_as = ReadAs::any});
  CHECK(c.info().format == "cosmos");
  CHECK(c.info().npts == 42000);
  // 42000 points over "approx 210 secs": 0.005 s, the real header's field 62
  // (5 ms; SOURCES.md's 0.02 s is its field 34); the peak is where the
  // header's "at 76.215 sec" puts it.
  CHECK(c.info().dt == close_to(0.005, 1e-12));
  CHECK(std::abs(c.acceleration(76.215)) == close_to(c.peak(), 1e-12));
  CHECK(c.info().component == "BNZ");
  CHECK(c.peak() == close_to(0.06852, 1e-3));
  // The format forced agrees with the one detected.
  CHECK(read_record(f + "AOM0011801241951.EW", {.format = "knet"}).peak() == k.peak());
}

TEST_CASE("GeoNet V2A files of other stations, counts and time steps: three components, mm/s2") {
  const std::string path = write_temp("other.V2A", v2a(23, 0.005));
  const GroundMotion g = read_record(path);
  CHECK(g.sample_count() == 23);
  CHECK(g.info().dt == close_to(0.005, 1e-12));
  // The file holds each reading to 0.1 mm/s2 ({:8.1f}): 100 sin(0.3) = 29.55 is written 29.6.
  const auto written = [](double mm_s2) { return std::round(10 * mm_s2) / 10 * 1e-3; };
  CHECK(g.acceleration(0.005) == close_to(written(100.0 * std::sin(0.3)), 1e-12));
  CHECK(g.info().station == "TEST (Test Station Road)");
  CHECK(g.info().event == "Mw 6.10 (10 km north of Testville)");
  const GroundMotion up = read_record(path, {.component = "up", .read_as = ReadAs::any});
  CHECK(up.info().component == "Up");
  CHECK(up.acceleration(0.005) == close_to(written(50.0 * std::sin(0.3)), 1e-12));
  CHECK(error_of(path, {.component = "E"}) ==
        path + ": --component E: the file's components are 1 N10E, 2 N80W, 3 Up");
  CHECK(error_of(path, {.unit = AccelerationUnit::g}).ends_with("--units g: the file states its values in mm/s2"));
}

TEST_CASE("malformed GeoNet files: a component missing, truncated, text in a number, a wrong count") {
  const std::string good = v2a(23, 0.005);
  const std::size_t second = good.find("Corrected accelerogram", 10);
  const std::string two = write_temp("two.V2A", good.substr(0, good.find("Corrected accelerogram", second + 10)));
  CHECK(error_of(two).ends_with("a GeoNet file holds three components, each with its header; this one holds 2"));
  // The first component's displacement block loses its last line.
  std::string cut = good;
  const std::size_t last_line = cut.rfind('\n', second - 2);
  cut.erase(last_line + 1, second - last_line - 1);
  const std::string truncated = write_temp("cut.V2A", cut);
  CHECK(error_of(truncated).find("component N10E: 23 accelerations, 23 velocities and 23 displacements take 9 lines, found 8") !=
        std::string::npos);
  std::string text = good;
  text.replace(text.find("    29.6"), 8, "     abc");
  CHECK(error_of(write_temp("text.V2A", text)).find("'abc' is not a number") != std::string::npos);
  std::string count = good;
  count.replace(count.find("Number of points  23"), 20, "Number of points  24");
  CHECK(error_of(write_temp("count.V2A", count)).find("expected 4 values on this line, found 3") != std::string::npos);
  std::string peak = good;
  const std::size_t number = peak.find("peak  ") + 6;
  peak.replace(number, peak.find(" mm", number) - number, "120.0");
  CHECK(error_of(write_temp("peak.V2A", peak)).find("the file states a peak of 0.12 m/s2 but its data peak at 0.") !=
        std::string::npos);
}

TEST_CASE("K-NET files: counts x scale factor in gal, the mean removed, checked against Max. Acc.") {
  const std::vector<long> counts = knet_counts(200);
  const std::string path = write_temp("TKY9990001010000.NS", knet(counts));
  const GroundMotion g = read_record(path);
  double mean = 0;
  for (long c : counts) mean += static_cast<double>(c);
  mean /= 200;
  CHECK(g.info().dt == close_to(0.02, 1e-12));
  CHECK(g.sample_count() == 200);
  CHECK(g.acceleration(0.02 * 7) == close_to((counts[7] - mean) * 2000.0 / 8388608.0 * 0.01, 1e-12));
  CHECK(g.info().component == "N-S");
  const std::string no_scale = write_temp("noscale.NS", knet(counts, "Scale Factor"));
  CHECK(error_of(no_scale) == no_scale + ":14: Scale Factor '' is not 'N(gal)/M'");
  const std::string missing = write_temp("missing.NS", knet(counts, "Memo.             "));
  CHECK(error_of(missing) == missing + ":14: expected the K-NET header line 'Scale Factor' (line 14 of 17)");
  std::vector<long> short_counts(counts.begin(), counts.end() - 9);
  std::string cut = knet(counts);
  cut.erase(cut.size() - 9 * 9 - 1);  // nine values and a line end fewer
  const std::string truncated = write_temp("cut.NS", cut);
  CHECK(error_of(truncated).ends_with("50 Hz for 4 s is 200 samples, but the file holds 191"));
  const std::string wrong_peak = write_temp("peak.NS", knet(counts, "Scale Factor      2000(gal)/8388608",
                                                             "Max. Acc. (gal)   99.000"));
  CHECK(error_of(wrong_peak).find(":15: the file states a peak of 0.99 m/s2 but its data peak at 0.141") !=
        std::string::npos);
  std::string text = knet(counts);
  text.replace(text.rfind("  "), 2, " x");
  CHECK(error_of(write_temp("text.NS", text)).find("is not a number") != std::string::npos);
}

TEST_CASE("COSMOS V2 files: the unit and time step from the headers, the stated maximum checked") {
  std::vector<double> acc(30);
  for (std::size_t i = 0; i < acc.size(); ++i) acc[i] = 12.5 * std::sin(0.4 * i);
  const std::string path = write_temp("test.V2", cosmos(acc, 10.0, 4, "cm/sec2"));
  const GroundMotion g = read_record(path);
  CHECK(g.info().format == "cosmos");
  CHECK(g.info().dt == close_to(0.01, 1e-12));
  CHECK(g.info().units == "cm/sec2");
  CHECK(g.info().station.starts_with("XX-TST"));
  // The file holds each reading to 3 decimals ({:10.3f}): as written, converted exactly.
  const auto written = [](double x) { return std::round(1000 * x) / 1000; };
  CHECK(g.acceleration(0.03) == close_to(written(12.5 * std::sin(1.2)) * 0.01, 1e-12));
  std::vector<double> in_g(acc);
  for (double& a : in_g) a /= 100;
  const GroundMotion gg = read_record(write_temp("g.V2", cosmos(in_g, 10.0, 2, "g")));
  CHECK(gg.acceleration(0.03) == close_to(written(0.125 * std::sin(1.2)) * 9.81, 1e-12));
  std::string cut = cosmos(acc, 10.0, 4, "cm/sec2");
  cut.erase(cut.find("End-of-data"));
  cut.erase(cut.rfind('\n', cut.size() - 2) + 1);
  const std::string truncated = write_temp("cut.V2", cut);
  CHECK(error_of(truncated).ends_with("the file ends after 24 of its 30 accelerations"));
  std::string count = cosmos(acc, 10.0, 4, "cm/sec2");
  count.replace(count.find("      30 acceleration pts"), 8, "      31");
  CHECK(error_of(write_temp("count.V2", count)).find("expected 7 accelerations on this line, found 6") != std::string::npos);
  std::string text = cosmos(acc, 10.0, 4, "cm/sec2");
  text.replace(text.find("End-of-data") - 11, 10, "     1.2.3");
  CHECK(error_of(write_temp("text.V2", text)).find("'1.2.3' is not a number") != std::string::npos);
  std::string unit = cosmos(acc, 10.0, 4, "cm/sec2");
  unit.replace(unit.find("(04)"), 4, "(50)");
  CHECK(error_of(write_temp("unit.V2", unit)).find("names no acceleration unit this program knows") != std::string::npos);
}

TEST_CASE("CSV records: the header names the columns and the units") {
  const std::string a = write_temp("a.csv", "time (s),acc (g)\n0,0\n0.01,0.1\n0.02,-0.2\n");
  const GroundMotion g = read_record(a);
  CHECK(g.info().format == "csv");
  CHECK(g.acceleration(0.01) == close_to(0.1 * 9.81, 1e-12));
  const std::string b = write_temp("b.csv", "# from a lab\nt;a_cm_s2\n0;0\n0.5;100\n1.0;-50\n");
  CHECK(read_record(b).acceleration(0.5) == close_to(1.0, 1e-12));
  const std::string c = write_temp("c.txt", "time_ms\tacc_x [m/s^2]\tacc_y [m/s^2]\n0\t1\t2\n10\t3\t4\n20\t5\t6\n");
  CHECK(error_of(c) == c + ":1: columns 'acc_x [m/s^2]', 'acc_y [m/s^2]' are all accelerations: choose one with --component");
  const GroundMotion y = read_record(c, {.component = "acc_y"});
  CHECK(y.acceleration(0.01) == close_to(4.0, 1e-12));
  CHECK(y.info().dt == close_to(0.01, 1e-12));
  CHECK(read_record(c, {.component = "2"}).acceleration(0.02) == close_to(5.0, 1e-12));
  const std::string no_unit = write_temp("nounit.csv", "time,acc\n0,0\n0.01,0.1\n");
  CHECK(error_of(no_unit) == no_unit + ":1: column 'acc' names no unit: write it as 'acc (g)' or 'acc_m_s2', or give --units");
  CHECK(read_record(no_unit, {.unit = AccelerationUnit::g}).acceleration(0.01) == close_to(0.981, 1e-12));
  const std::string no_time = write_temp("notime.csv", "acc_g\n0\n0.1\n");
  CHECK(error_of(no_time) == no_time + ":1: no time column (name one t or time), and no --dt");
  CHECK(read_record(no_time, {.dt = 0.05}).acceleration(0.05) == close_to(0.981, 1e-12));
  const std::string ragged = write_temp("ragged.csv", "t,acc_g\n0,0\n0.01\n");
  CHECK(error_of(ragged) == ragged + ":3: 1 fields, the header names 2");
  const std::string word = write_temp("word.csv", "t,acc_g\n0,0\n0.01,big\n");
  CHECK(error_of(word) == word + ":3: 'big' is not a number");
  const std::string clash = write_temp("clash.csv", "t,acc_g\n0,0\n0.01,0.1\n");
  CHECK(error_of(clash, {.unit = AccelerationUnit::cm_per_s2}) == clash + ":1: --units cm/s2: the file states its values in g");
}

TEST_CASE("a file of no known format says what it looks like and which formats exist") {
  const std::string odd = write_temp("odd.txt", "Station list for 2020\nA B C\n");
  const std::string e = error_of(odd);
  CHECK(e.starts_with(odd + ":1: not a record format this program reads: it starts with text 'Station list for 2020'"));
  std::string names;
  for (const RecordFormatInfo& f : record_formats()) names += (names.empty() ? "" : ", ") + f.name;
  CHECK(e.find("formats: " + names + "; --format forces one") != std::string::npos);
  CHECK(error_of(odd, {.format = "sac"}) == "--format sac: unknown record format (choose auto, " + names + ")");
  // A format forced on a file of another: that reader's own error.
  const std::string at2 = write_temp("x.at2", "PEER NGA\nX\nUNITS OF G\nNPTS= 2, DT= .01 SEC\n0.1 0.2\n");
  CHECK(error_of(at2, {.format = "knet"}) == at2 + ":1: expected the K-NET header line 'Origin Time' (line 1 of 17)");
  CHECK(error_of(at2, {.component = "2"}) == at2 + ": --component 2: a PEER .AT2 file holds one component");
}

TEST_CASE("GeoNet V1A: uncorrected, the sampling rate in the header, values in units of the stated size") {
  // A V1A component: the same header layout, "Raw readings in units of 2.00
  // mm/s/s at intervals of 0.005 s", the sampling rate (200 Hz, as
  // v2a_component writes it) in real-header field (1,1), and the
  // accelerations alone.
  std::string file;
  for (const char* name : {"S14E", "N76E", "Up"}) {
    std::string c = v2a_component(name, {10.0, -20.0, 30.0, -40.0, 50.0, -60.0, 70.0, -80.0, 90.0, -100.0, 5.0, 1.0}, 0.005,
                                  -200.0);
    c.replace(0, std::string("Corrected").size(), "Uncorrected");
    c.replace(c.find("Instrument corrected data at 0.005 sec intervals"), 48,
              "Raw readings in units of 2.00 mm/s/s  at intervals of 0.005 s");
    // Drop the velocity and displacement blocks (two lines each for 12 values).
    for (int k = 0; k < 4; ++k) c.erase(c.rfind('\n', c.size() - 2) + 1);
    file += c;
  }
  const std::string path = write_temp("raw.V1A", file);
  const GroundMotion g = read_record(path, {.component = "N76E"});
  CHECK(g.info().component == "N76E");
  CHECK(g.info().dt == close_to(0.005, 1e-12));
  CHECK(g.sample_count() == 12);
  CHECK(g.acceleration(0.005) == close_to(-20.0 * 2.0 * 1e-3, 1e-12));
  CHECK(g.peak() == close_to(0.2, 1e-12));  // stated peak -200 mm/s/s = 2 x the largest reading
}

// The tests below take the formats from the registry (record_formats()): a
// new format is covered by its example with no test edited.

TEST_CASE("every registered format reads its own example: detected, forced, with the example's samples") {
  const ExampleRecord e = example_record();
  for (const RecordFormatInfo& f : record_formats()) {
    CAPTURE(f.name);
    const std::string path = write_temp("example_" + f.name + ".txt", f.example());
    CHECK(is_record_file(path));
    const GroundMotion g = read_record(path);
    CHECK(g.info().format == f.name);
    REQUIRE(g.sample_count() == e.values.size());
    CHECK(g.sample_interval() == close_to(e.dt, 1e-12));
    const std::vector<double> a = g.sample_values();
    // To the coarsest format's printed resolution (K-NET's count, 1e-4 g).
    for (std::size_t i = 0; i < a.size(); ++i) CHECK(std::abs(a[i] / gravity - e.values[i]) <= 5.1e-5);
    CHECK(read_record(path, {.format = f.name}).sample_values() == a);
  }
}

TEST_CASE("every registered format, forced on what is not its file, reads it or refuses in one line naming it") {
  const std::vector<RecordFormatInfo> formats = record_formats();
  const std::string empty = write_temp("empty_record.txt", "");
  for (const RecordFormatInfo& f : formats) {
    CAPTURE(f.name);
    CHECK(error_of(empty, {.format = f.name}).starts_with(empty + ":"));
    for (const RecordFormatInfo& other : formats) {
      CAPTURE(other.name);
      // Another format's example, and this format's own cut after half its lines.
      const std::string own = f.example();
      const std::string cut = own.substr(0, own.find('\n', own.size() / 2));
      for (const std::string& text : {other.example(), cut}) {
        const std::string path = write_temp("forced_" + f.name + "_" + other.name + ".txt", text);
        try {
          const GroundMotion g = read_record(path, {.format = f.name});
          CHECK(g.sample_count() >= 2);
        } catch (const InputError& x) {
          const std::string what = x.what();
          CHECK_MESSAGE(what.find('\n') == std::string::npos, what);
          CHECK_MESSAGE(what.starts_with(path + ":"), what);
        }
      }
    }
  }
}
