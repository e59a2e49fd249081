// `rocking record`: the measures of records in every format, as a table and
// as JSON (numbers equal to the library's), figures and their data, every
// format through simulate, and one-line errors.
#include <doctest/doctest.h>
#include "close.hpp"
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <string>
#include "csv_table.hpp"
#include "records.hpp"
#include "run_program.hpp"
#include "gnuplot_columns.hpp"
#include "temp_path.hpp"
import rocking.ground_motion;
import rocking.intensity;
import rocking.geometry;
import rocking.records;

namespace fs = std::filesystem;
using namespace cli;

TEST_CASE("record --json gives the measures and metadata of every format") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string f = *dir + "/formats/";
  const Result r = run("record --json --periods 0.5,1 " + *dir + "/elcentro_1940_ns.at2 " + f +
                       "20161113_110259_WTMC_20.V2A " + f + "AOM0011801241951.EW " + f + "us1000hyfh_akbmrp_bnz.V2c");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  REQUIRE(j.size() == 4);
  for (const auto& rec : j)
    for (const char* key : {"pga_g", "pgv_m_s", "pgd_m", "arias_m_s", "d5_95_s", "cav_m_s", "periods_s", "psa_g", "dt_s",
                            "npts", "format", "event", "station", "component", "units", "stated_peak_g"})
      CHECK_MESSAGE(rec.contains(key), key);
  CHECK(j[0]["format"] == "at2");
  CHECK(j[0]["pga_g"].get<double>() == close_to(0.3188, 1e-3));
  CHECK(j[0]["periods_s"].size() == 2);
  CHECK(j[0]["psa_g"].size() == 2);
  // Each file's PGA is the peak its header states, to 0.1 %.
  for (std::size_t i = 1; i < 4; ++i) {
    CAPTURE(j[i]["id"]);
    CHECK(j[i]["pga_g"].get<double>() == close_to(j[i]["stated_peak_g"].get<double>(), 1e-3));
  }
  CHECK(j[1]["format"] == "geonet");
  CHECK(j[1]["component"] == "N28W");
  CHECK(j[1]["pga_g"].get<double>() == close_to(9.7331 / 9.81, 1e-3));
  CHECK(j[2]["format"] == "knet");
  CHECK(j[3]["format"] == "cosmos");
}

TEST_CASE("record writes the record and spectrum figures with their data, and marks a scene's periods") {
  const auto dir = records_dir();
  if (!dir) return;
  const fs::path out = temp_path("record_figures");
  const Result r = run("record " + *dir + "/elcentro_1940_ns.at2 --formats png --log --scene " +
                       std::string(ROCKING_SOURCE_DIR) + "/data/scenes/christchurch_chimney.toml --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.out.find("PGA [g]           0.3188") != std::string::npos);
  for (const char* file : {"record.png", "spectrum.png", "spectrum.csv", "record.json", "record.data/record_1.csv"})
    CHECK_MESSAGE(fs::exists(out / file), file);
  const std::string script = file_text(out / "spectrum.gp");
  CHECK(script.find("T1 = 0.460 s") != std::string::npos);  // the chimney's first fixed-base period
  CHECK(script.find("set logscale xy") != std::string::npos);
  for (const char* gp : {"spectrum.gp", "record.gp"})  // columns by header name
    CHECK_MESSAGE(numbered_column(file_text(out / gp)).empty(), gp, ": ", numbered_column(file_text(out / gp)));
}

TEST_CASE("simulate takes every format: record errors are one line with exit 2") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string f = *dir + "/formats/";
  const fs::path out = temp_path("record_simulate");
  const Result k = run("simulate --json --duration 5 --record " + f + "AOM0011801241951.EW --out " + out.string());
  CHECK_MESSAGE(k.code == 0, k.err);
  const Result s62w = run("simulate --json --duration 5 --component S62W --record " + f +
                          "20161113_110259_WTMC_20.V2A --out " + out.string());
  CHECK_MESSAGE(s62w.code == 0, s62w.err);
  CHECK(nlohmann::json::parse(s62w.out)["motion"].get<std::string>().find("S62W") != std::string::npos);
  // The vertical component is no horizontal motion: the error points to --vertical.
  const Result up = run("simulate --duration 5 --component Up --record " + f + "20161113_110259_WTMC_20.V2A --out " +
                        out.string());
  CHECK(up.code == 2);
  CHECK(up.err == "rocking: error: " + f + "20161113_110259_WTMC_20.V2A: component Up is vertical: give it as the "
                  "vertical motion (--vertical Up) and choose a horizontal component for the horizontal one\n");
  const Result bad = run("record " + f + "AOM0011801241951.EW --component 2");
  CHECK(bad.code == 2);
  CHECK(bad.err == "rocking: error: " + f + "AOM0011801241951.EW: --component 2: a K-NET file holds one component\n");
  const Result damping = run("record " + f + "AOM0011801241951.EW --damping 1.5");
  CHECK(damping.code == 2);
  CHECK(damping.err == "rocking: error: --damping 1.5: must be in [0, 1)\n");
  const Result periods = run("record " + f + "AOM0011801241951.EW --periods 0,1");
  CHECK(periods.code == 2);
  CHECK(periods.err == "rocking: error: --periods 0,1: period 0 s: must be in [0.001, 1000] s\n");
  const Result none = run("record /no/such.V2A");
  CHECK(none.code == 2);
  CHECK(none.err == "rocking: error: /no/such.V2A: record file not found\n");
  const Result stray = run("simulate --component 2");
  CHECK(stray.code == 2);
  CHECK(stray.err.find("--format, --component, --units, --dt and --process describe a --record file") != std::string::npos);
}

TEST_CASE("ida and its hunt take every format and list what each record is in records.csv") {
  const auto dir = records_dir();
  if (!dir) return;
  const fs::path out = temp_path("record_ida");
  const Result r = run("ida --no-plot --scales 0.25 --variants fixed-base --record " + *dir +
                       "/formats/20161113_110259_WTMC_20.V2A --record " + *dir + "/formats/AOM0011801241951.EW --out " +
                       out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string text = file_text(out / "records.csv");
  CHECK(text.starts_with("record,file,format,event,date,station,component,pga_g,processing\n"));
  CHECK(text.find("20161113_110259_WTMC_20.V2A,") != std::string::npos);
  CHECK(text.find(",geonet,Mw 7.82 (5 km south-west of Waiau),2016 November 13 11:02:56 UT,WTMC (Te Mara Farm Waiau),N28W,0.99") !=
        std::string::npos);
  CHECK(text.find(",knet,") != std::string::npos);
  // A hunt lists them the same way (a fixed base is not run: nothing to hunt).
  const fs::path hunt = temp_path("record_hunt");
  const Result h = run("ida --no-plot --hunt --scales 0.25 --variants fixed-base --record " + *dir +
                       "/formats/20161113_110259_WTMC_20.V2A --record " + *dir + "/formats/AOM0011801241951.EW --out " +
                       hunt.string());
  REQUIRE_MESSAGE(h.code == 0, h.err);
  CHECK(file_text(hunt / "records.csv") == text);
}

TEST_CASE("ida --vertical runs each record with its file's vertical component: a row equals simulate's run") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string waiau = *dir + "/formats/20161113_110259_WTMC_20.V2A";
  const fs::path out = temp_path("record_ida_vertical");
  const Result r = run("ida --no-plot --scales 0.5 --variants damper --duration 60 --component N28W --vertical Up --record " +
                       waiau + " --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable rows = csv_table(file_text(out / "ida.csv"));
  REQUIRE(rows.rows.size() == 1);
  const fs::path one = temp_path("record_ida_vertical_one");
  const auto peak = [&](const std::string& vertical) {
    const Result s = run("simulate --json --scale 0.5 --duration 60 --component N28W " + vertical + " --record " + waiau +
                         " --out " + one.string());
    REQUIRE_MESSAGE(s.code == 0, s.err);
    return nlohmann::json::parse(s.out)["peaks"]["theta_over_alpha"].get<double>();
  };
  const double with = peak("--vertical Up"), without = peak("");
  CHECK(std::stod(rows.at(0, "theta_over_alpha")) == close_to(with, 1e-8));
  CHECK(std::abs(with - without) > 1e-6 * without);  // the vertical motion made a difference
  const Result wrong = run("ida --no-plot --scales 0.5 --component N28W --vertical S62W --record " + waiau + " --out " +
                           out.string());
  // A horizontal component as the vertical: the record cannot run, and its rows say why.
  CHECK(wrong.code == 4);  // every run failed: the rows say why
  CHECK(wrong.err.find("see the error column") != std::string::npos);
  CHECK(csv_table(file_text(out / "ida.csv")).at(0, "error").find("component S62W is horizontal") != std::string::npos);
}

// RotD50 and RotD100 [g] by another route than the program's: the two
// components' samples projected at every degree by hand, each projection's
// PSA computed alone, the median (mean of the middle two) and the maximum of
// the 180 taken.
std::array<double, 2> rotd_by_rotation(const rocking::GroundMotion& a1, const rocking::GroundMotion& a2, double T) {
  const std::vector<double> x1 = a1.sample_values(), x2 = a2.sample_values();
  REQUIRE(a1.sample_interval() == a2.sample_interval());
  std::vector<double> psa;
  for (int k = 0; k < 180; ++k) {
    const double phi = k * std::numbers::pi / 180;
    std::vector<double> a(std::max(x1.size(), x2.size()), 0.0);
    for (std::size_t i = 0; i < a.size(); ++i)
      a[i] = (i < x1.size() ? x1[i] * std::cos(phi) : 0.0) + (i < x2.size() ? x2[i] * std::sin(phi) : 0.0);
    psa.push_back(rocking::pseudo_spectral_acceleration(rocking::GroundMotion::evenly_sampled("rotated", a1.sample_interval(), a), T));
  }
  std::ranges::sort(psa);
  return {0.5 * (psa[89] + psa[90]) / rocking::gravity, psa[179] / rocking::gravity};
}

TEST_CASE("record --rotd: RotD50 and RotD100 of the Waiau file's two horizontals equal the records rotated at every degree (1e-10)") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string waiau = *dir + "/formats/20161113_110259_WTMC_20.V2A";
  const std::vector<double> periods = {0.2, 0.5, 1, 2};
  const rocking::GroundMotion n28w = rocking::read_record(waiau, {.component = "N28W"});
  const rocking::GroundMotion s62w = rocking::read_record(waiau, {.component = "S62W"});
  const Result j = run("record " + waiau + " --rotd --periods 0.2,0.5,1,2 --json");
  REQUIRE_MESSAGE(j.code == 0, j.err);
  const auto rec = nlohmann::json::parse(j.out)[0];
  CHECK(rec["rotd_components"] == nlohmann::json::array({"N28W", "S62W"}));
  const Result r = run("record " + waiau + " --rotd --periods 0.2,0.5,1,2");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  CHECK(r.out.find("RotD of           N28W+S62W") != std::string::npos);
  for (std::size_t k = 0; k < periods.size(); ++k) {
    CAPTURE(periods[k]);
    const auto [rotd50, rotd100] = rotd_by_rotation(n28w, s62w, periods[k]);
    // Superposition against rotation: equal to round-off (tests/intensity_test.cpp).
    CHECK(rec["rotd50_g"][k].get<double>() == close_to(rotd50, 1e-10));
    CHECK(rec["rotd100_g"][k].get<double>() == close_to(rotd100, 1e-10));
    // The table prints the same numbers to 4 decimals.
    const std::string line = fmt::format("  {:<16}{:.4f} {:.4f}", fmt::format("T = {:g} s", periods[k]), rotd50, rotd100);
    CHECK_MESSAGE(r.out.find(line) != std::string::npos, line);
  }
  // The README's figures (README, "record --rotd"): T = 1 s, 1.0526 and 1.4637 g, to their 4 decimals.
  CHECK(rec["rotd50_g"][2].get<double>() == within(1.0526, 5e-5));
  CHECK(rec["rotd100_g"][2].get<double>() == within(1.4637, 5e-5));
  // A PEER pair with --second; a single-component file alone has no RotD.
  const std::string cbgs = *dir + "/christchurch2011_cbgs_";
  const Result pair = run("record " + cbgs + "n89w.at2 --rotd --second " + cbgs + "s01w.at2 --periods 1");
  CHECK_MESSAGE(pair.code == 0, pair.err);
  CHECK(pair.out.find("RotD of           N89W+S01W") != std::string::npos);
  const Result alone = run("record " + cbgs + "n89w.at2 --rotd");
  CHECK(alone.code == 2);
  CHECK(alone.err.find("holds no other horizontal component beside N89W") != std::string::npos);
  const Result stray = run("record " + cbgs + "n89w.at2 --second " + cbgs + "s01w.at2");
  CHECK(stray.code == 2);
  CHECK(stray.err == "rocking: error: --second: the other horizontal component of one record, for --rotd\n");
}

TEST_CASE("ida --im rotd50:1 scales each record by its two horizontals' RotD50") {
  const auto dir = records_dir();
  if (!dir) return;
  const fs::path out = temp_path("record_ida_rotd");
  const Result r = run("ida --no-plot --im rotd50:1 --levels 0.5 --variants fixed-base --record " + *dir +
                       "/formats/20161113_110259_WTMC_20.V2A --record " + *dir + "/elcentro_1940_ns.at2 --out " +
                       out.string());
  CHECK(r.code == 4);  // El Centro's file holds one component: its runs fail, saying why
  const CsvTable rows = csv_table(file_text(out / "ida.csv"));
  REQUIRE(rows.rows.size() == 2);
  CHECK(std::stod(rows.at(0, "record_im")) == close_to(1.0526, 1e-4));
  CHECK(std::stod(rows.at(0, "scale")) == close_to(0.5 / 1.0526, 1e-4));
  CHECK(rows.at(1, "error").find("holds no other horizontal component") != std::string::npos);
}

TEST_CASE("record --process prints the processed measures beside the raw ones, and every output names the processing") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string knet = *dir + "/formats/AOM0011801241951.EW";
  const fs::path out = temp_path("record_processed");
  const Result r = run("record " + knet + " --process detrend=1,taper=0.05,highpass=0.1,lowpass=20 --json --out " +
                       out.string() + " --formats png");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j.size() == 2);
  CHECK(j[0]["processing"].is_null());
  CHECK(j[1]["processing"] == "detrend 1, taper 5 %, Butterworth 0.1-20 Hz order 4 zero-phase");
  CHECK(j[1]["id"].get<std::string>().ends_with(" processed"));
  CHECK(j[1]["pgd_m"].get<double>() < 0.2 * j[0]["pgd_m"].get<double>());
  CHECK(fs::exists(out / "record.png"));
  // A run under the processed record says so in its summary.
  const Result s = run("simulate --json --duration 5 --record " + knet + " --process highpass=0.1 --out " + out.string());
  REQUIRE_MESSAGE(s.code == 0, s.err);
  CHECK(nlohmann::json::parse(s.out)["motion"].get<std::string>().find("processed: Butterworth high-pass 0.1 Hz") !=
        std::string::npos);
  const Result bad = run("record " + knet + " --process highpass=0.1,lowpass=80");
  CHECK(bad.code == 2);
  CHECK(bad.err.find("at or above the Nyquist frequency 50 Hz") != std::string::npos);
  const Result spec = run("record " + knet + " --process hp=1");
  CHECK(spec.code == 2);
  CHECK(spec.err == "rocking: error: --process hp=1: hp=1: unknown key (keys: cut, detrend, taper, highpass, lowpass, order, "
                    "vfit, dt)\n");
}

TEST_CASE("ida --azimuths: each azimuth a record of its own, row for row the runs at that azimuth, and their largest") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string waiau = *dir + "/formats/20161113_110259_WTMC_20.V2A";
  const fs::path out = temp_path("record_ida_azimuths");
  const Result r = run("ida --no-plot --scales 0.5 --variants damper --duration 60 --component N28W --azimuths 0,30,90 "
                       "--record " + waiau + " --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable rows = csv_table(file_text(out / "ida.csv"));
  REQUIRE(rows.rows.size() == 3);
  const fs::path one = temp_path("record_ida_azimuths_one");
  double largest = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::string phi = std::vector<std::string>{"0", "30", "90"}[i];
    CHECK(rows.at(i, "record") == "20161113_110259_WTMC_20.V2A@" + phi);
    const Result s = run("simulate --json --scale 0.5 --duration 60 --component N28W --azimuth " + phi + " --record " +
                         waiau + " --out " + one.string());
    REQUIRE_MESSAGE(s.code == 0, s.err);
    const double theta = nlohmann::json::parse(s.out)["peaks"]["theta_over_alpha"].get<double>();
    CHECK(std::stod(rows.at(i, "theta_over_alpha")) == close_to(theta, 1e-8));
    largest = std::max(largest, theta);
  }
  const CsvTable summary = csv_table(file_text(out / "azimuths.csv"));
  REQUIRE(summary.rows.size() == 1);
  CHECK(summary.at(0, "record") == "20161113_110259_WTMC_20.V2A");
  CHECK(summary.at(0, "azimuths") == "3");
  CHECK(std::stod(summary.at(0, "theta_over_alpha_max")) == close_to(largest, 1e-8));
  const Result bad = run("ida --no-plot --scales 0.5 --azimuths 0,90 --record " + *dir + "/elcentro_1940_ns.at2 --out " +
                         out.string());
  CHECK(bad.code == 2);
  CHECK(bad.err.find("holds no other horizontal component") != std::string::npos);
}

TEST_CASE("ida --pairs: a PEER pair's second file is its record's other horizontal component, for RotD and azimuths") {
  const auto dir = records_dir();
  if (!dir) return;
  const std::string cbgs = *dir + "/christchurch2011_cbgs_";
  const Result rotd = run("record " + cbgs + "n89w.at2 --rotd --second " + cbgs + "s01w.at2 --periods 1 --json");
  REQUIRE_MESSAGE(rotd.code == 0, rotd.err);
  const double rotd50 = nlohmann::json::parse(rotd.out)[0]["rotd50_g"][0].get<double>();
  const fs::path out = temp_path("record_ida_pairs");
  const Result r = run("ida --no-plot --pairs --im rotd50:1 --levels 0.5 --variants fixed-base --record " + cbgs +
                       "n89w.at2 --record " + cbgs + "s01w.at2 --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable rows = csv_table(file_text(out / "ida.csv"));
  REQUIRE(rows.rows.size() == 1);
  CHECK(std::stod(rows.at(0, "record_im")) == close_to(rotd50, 1e-8));
  // At 90 degrees the pair's run is its second file's.
  const Result turned = run("ida --no-plot --pairs --scales 1 --variants damper --azimuths 90 --record " + cbgs +
                            "n89w.at2 --record " + cbgs + "s01w.at2 --out " + out.string());
  REQUIRE_MESSAGE(turned.code == 0, turned.err);
  const CsvTable at90 = csv_table(file_text(out / "ida.csv"));
  const Result alone = run("simulate --json --record " + cbgs + "s01w.at2 --out " + out.string() + "/one");
  REQUIRE_MESSAGE(alone.code == 0, alone.err);
  CHECK(std::stod(at90.at(0, "theta_over_alpha")) ==
        close_to(nlohmann::json::parse(alone.out)["peaks"]["theta_over_alpha"].get<double>(), 1e-8));
  const Result odd = run("ida --no-plot --pairs --scales 1 --record " + cbgs + "n89w.at2 --out " + out.string());
  CHECK(odd.code == 2);
  CHECK(odd.err.find("--pairs: an odd number of record files (1)") != std::string::npos);
}
