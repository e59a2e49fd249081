// `rocking simulate` as a user meets it: the files and keys the issue names,
// the scene variants reachable with --set, bad input in one line with exit 2,
// and a run that cannot finish exiting 3 with what it had written kept.
#include <doctest/doctest.h>
#include "close.hpp"
#include "temp_path.hpp"
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include "run_program.hpp"
#include "gnuplot_columns.hpp"
#include "csv_table.hpp"
#include "records.hpp"

namespace fs = std::filesystem;

namespace {

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

const std::string at2_header =
    "PEER STRONG MOTION DATABASE RECORD\nTEST RECORD\nACCELERATION TIME SERIES IN UNITS OF G\n";

}  // namespace

TEST_CASE("simulate runs the embedded chimney and writes history.csv and summary.json") {
  const fs::path dir = scratch_dir("simulate_test_default");
  const Result r = run("simulate --json --out " + dir.string());
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j == nlohmann::json::parse(file_text(dir / "summary.json")));
  for (const char* key : {"delta_t", "delta_e", "theta", "theta_over_alpha", "damper_d", "damper_F", "base_shear",
                          "base_moment", "mid_shear", "mid_moment"})
    CHECK_MESSAGE(j["peaks"][key].is_number(), key);
  for (const char* key : {"top_total_mm", "counts", "outcome", "stats", "wall_s"}) CHECK_MESSAGE(j.contains(key), key);
  for (const char* key : {"rhs", "steps", "rejected", "events"}) CHECK(j["stats"][key].get<long>() >= 0);
  CHECK(j["outcome"] == "completed");
  CHECK(j["counts"]["uplifts"].get<long>() > 0);  // the default pulse lifts the chimney
  CHECK(j["top_total_mm"].get<double>() == close_to(j["peaks"]["delta_t"].get<double>() * 33.05e3, 1e-12));
  const std::string history = file_text(dir / "history.csv");
  CHECK(history.starts_with("t [s],phase,u_N [m],theta [rad]"));
  CHECK(lines(history) > 800);  // 8 s every 0.01 s, and the events
}

TEST_CASE("the fixed-base, no-damper and rigid-block variants are reachable from the scene keys") {
  const fs::path dir = scratch_dir("simulate_test_variants");
  const Result fixed = run("simulate --json --set contact.rocking=false --out " + dir.string());
  REQUIRE(fixed.code == 0);
  const auto f = nlohmann::json::parse(fixed.out);
  CHECK(f["counts"]["uplifts"] == 0);
  CHECK(!f["peaks"].contains("theta"));  // a fixed base does not rock: no rocking quantity
  CHECK(f["peaks"]["base_moment"].get<double>() > 1.0);  // a fixed base carries more than M_ref
  const Result free = run("simulate --json --set damper.enabled=false --out " + dir.string());
  REQUIRE(free.code == 0);
  CHECK(!nlohmann::json::parse(free.out)["peaks"].contains("damper_F"));  // no damper, no damper force
  CHECK(!nlohmann::json::parse(free.out)["peaks"].contains("damper_d"));
  const Result block = run("simulate " + std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml --json --out " +
                           dir.string());
  REQUIRE(block.code == 0);
  const auto b = nlohmann::json::parse(block.out);
  CHECK(!b["peaks"].contains("base_shear"));  // a rigid block has no elastic forces
  CHECK(b["peaks"]["theta"].get<double>() > 0.0);
}

TEST_CASE("simulate: bad input is one line on stderr, naming the file and line, and exit code 2") {
  const fs::path dir = scratch_dir("simulate_test_bad");
  write(dir / "npts.at2", at2_header + "NPTS=    5, DT= .01000 SEC\n0.1 0.2 0.3 0.4\n");
  write(dir / "text.at2", at2_header + "NPTS=    4, DT= .01000 SEC\n0.1 0.2\nabc 0.4\n");
  write(dir / "nan.at2", at2_header + "NPTS=    4, DT= .01000 SEC\n0.1 nan 0.3 0.4\n");
  write(dir / "dt.at2", at2_header + "NPTS=    4, DT= 0.0 SEC\n0.1 0.2 0.3 0.4\n");
  const std::string out = " --out " + (dir / "out").string();
  struct Case {
    std::string args, expect;
  };
  for (const Case& c : {Case{"--record " + (dir / "missing.at2").string(), "missing.at2"},
                        Case{"--record " + (dir / "npts.at2").string(), "npts.at2:"},
                        Case{"--record " + (dir / "text.at2").string(), "text.at2:6"},
                        Case{"--record " + (dir / "nan.at2").string(), "nan.at2:"},
                        Case{"--record " + (dir / "dt.at2").string(), "dt.at2:"},
                        Case{"--record " + (dir / "npts.at2").string() + " --units furlongs", "furlongs"},
                        Case{"--integrator euler", "euler"},
                        Case{"--rtol 0", "--rtol"},
                        Case{"--set contact.restitution=1.5", "contact.restitution"}}) {
    const Result r = run("simulate" + out + " " + c.args);
    CAPTURE(c.args);
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(r.err.find(c.expect) != std::string::npos);
  }
}

TEST_CASE("a run that cannot finish exits 3 naming the time and phase, and keeps its files") {
  const fs::path dir = scratch_dir("simulate_test_stopped");
  for (const std::string& limit : {std::string("--max-steps 300"), std::string("--max-events 3")}) {
    CAPTURE(limit);
    const Result r = run("simulate --out " + dir.string() + " " + limit);
    CHECK(r.code == 3);
    CHECK(r.err.find("at t = ") != std::string::npos);
    CHECK(r.err.find("phase ") != std::string::npos);
    const auto j = nlohmann::json::parse(file_text(dir / "summary.json"));
    CHECK(j["outcome"] == "failed");
    CHECK(j["t_end"].get<double>() > 0.0);
    CHECK(lines(file_text(dir / "history.csv")) > 2);
  }
}

TEST_CASE("tradeoff measures each backend against the reference and draws the work-precision figure") {
  const fs::path dir = scratch_dir("simulate_test_tradeoff");
  const Result r = run("-q tradeoff --duration 2 --rtols 1e-3,1e-6 --backends rk45,cvode --repeats 1 --formats png --out " +
                       dir.string());
  REQUIRE(r.code == 0);
  CHECK(r.out.find("reference: rk45 at rtol 1e-12") != std::string::npos);
  const std::string csv = file_text(dir / "tradeoff.csv");
  CHECK(lines(csv) == 1 + 2 * 2);
  const CsvTable table = csv_table(csv);
  std::vector<double> rk45_errors;
  for (std::size_t i = 0; i < table.rows.size(); ++i)
    if (table.at(i, "backend") == "rk45") rk45_errors.push_back(std::stod(table.at(i, "err_delta_t")));
  REQUIRE(rk45_errors.size() == 2);
  CHECK(rk45_errors[1] < rk45_errors[0]);  // a tighter tolerance is more accurate
  // Each point of the work-precision figure is labelled with its rtol.
  CHECK(file_text(dir / "work_precision.gp").find("with labels") != std::string::npos);
  CHECK_MESSAGE(numbered_column(file_text(dir / "work_precision.gp")).empty(), numbered_column(file_text(dir / "work_precision.gp")));
  CHECK(file_text(dir / "tradeoff.data" / "rk45.csv").find(",1e-03\n") != std::string::npos);
  CHECK(rk45_errors[0] < 1e-2);
  CHECK(fs::is_regular_file(dir / "work_precision.png"));
}

TEST_CASE("tradeoff --scenes puts each method's cost at equal accuracy against the node count") {
  const fs::path dir = scratch_dir("simulate_test_tradeoff_n");
  const std::string towers = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/towers/";
  const Result r = run("-q tradeoff --duration 3 --rtols 1e-4,1e-3 --accuracy 1e-3 --reference-rtol 1e-8 --repeats 1 "
                       "--formats png --scenes " + towers + "tower_8.toml," + towers + "tower_16.toml --out " +
                       dir.string());
  REQUIRE(r.code == 0);
  const std::string csv = file_text(dir / "tradeoff_n.csv");
  CHECK(lines(csv) == 1 + 2 * 3);  // two towers, three methods (rk45+exact, rosw+exact, rosw)
  const CsvTable table = csv_table(csv);
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    REQUIRE(table.rows[i].size() == table.header.size());
    CAPTURE(i);
    CHECK(table.at(i, "over_budget") == "false");  // no method ran over the budget
    CHECK((table.at(i, "n") == "8" || table.at(i, "n") == "16"));
    CHECK(table.at(i, "rtol") == "1e-03");  // the loosest rtol is tried first, and meets 1e-3
    CHECK(std::stod(table.at(i, "err_delta_t")) <= 1e-3);  // its error is what was asked
    CHECK(table.at(i, "met") == "true");
    CHECK(std::stod(table.at(i, "reference_check")) < 1e-6);  // rk45+exact confirms the rosw reference
  }
  CHECK(file_text(dir / "tradeoff_n.data" / "rosw.csv").find("\n16,") != std::string::npos);
  CHECK(fs::is_regular_file(dir / "cost_against_n.png"));
}

TEST_CASE("tradeoff --scenes refuses a rigid block in one line") {
  const Result r = run("-q tradeoff --scenes " + std::string(ROCKING_SOURCE_DIR) +
                       "/data/scenes/rigid_block.toml --out " + scratch_dir("simulate_test_tradeoff_rigid").string());
  CHECK(r.code == 2);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.find("rigid block has no nodes") != std::string::npos);
}

TEST_CASE("tradeoff refuses an unknown backend in one line, before any run") {
  const Result r = run("-q tradeoff --backends rk45,euler+exact --out " + scratch_dir("simulate_test_bad_backend").string());
  CHECK(r.code == 2);
  CHECK(lines(r.err) == 1);
  CHECK(r.err.find("--backends euler+exact") != std::string::npos);
  CHECK(r.out.find("reference") == std::string::npos);  // no reference run was made
}

TEST_CASE("simulate with devices: each device's columns in history.csv, its peaks, work and fracture in summary.json") {
  const fs::path dir = scratch_dir("simulate_test_devices");
  const Result r = run(
      R"(simulate --json --out )" + dir.string() +
      R"( --set 'device+={name="tendon", kind="elastic", at=0, kinematics="vertical", free_length=33, P0=2e6, k=5e7, capacity=0.005}')");
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  REQUIRE(j["devices"].size() == 3);
  const auto& tendon = j["devices"][2];
  CHECK(tendon["name"] == "tendon");
  CHECK(tendon["fracture_s"].is_number());
  CHECK(j["devices"][0]["name"] == "damper_left");
  CHECK(j["devices"][0]["fracture_s"].is_null());
  CHECK(tendon["peak_force_N"].get<double>() == close_to(2e6 + 5e7 * 0.005, 1e-8));
  // At the default rtol 1e-4: the energy it stored when it broke.
  CHECK(tendon["work_J"].get<double>() == close_to(2e6 * 0.005 + 0.5 * 5e7 * 0.005 * 0.005, 1e-4));
  CHECK(tendon["peak_elongation_m"].get<double>() == close_to(0.005, 1e-9));
  const std::string history = file_text(dir / "history.csv");
  const std::string header = history.substr(0, history.find('\n'));
  CHECK(header.ends_with("a_g [m/s2],M_dev [N m],damper_left.elongation [m],damper_left.force [N],"
                         "damper_right.elongation [m],damper_right.force [N],tendon.elongation [m],tendon.force [N]"));
  // Its peaks under its name, its law and state.
  CHECK(j["peaks"]["tendon.elongation"] == tendon["peak_elongation_m"]);
  CHECK(j["peaks"]["tendon.force"] == tendon["peak_force_N"]);
  CHECK(tendon["law"] == "elastic");
  CHECK(tendon["force_at_rest_N"] == 2e6);
  CHECK(tendon["state"] == "broken");
  CHECK(j["devices"][0]["state"] == "intact");
  CHECK(r.out.find("broke at") == std::string::npos);  // --json prints the JSON alone
  const Result text = run(R"(simulate --out )" + dir.string() +
                          R"( --set 'device+={name="tendon", kind="elastic", at=0, kinematics="vertical", free_length=33, P0=2e6, k=5e7, capacity=0.005}')");
  CHECK(text.out.find("  tendon            elastic, prestress 2e+06 N: peak e 0.005") != std::string::npos);
  CHECK(text.out.find("broke at t = ") != std::string::npos);
}

TEST_CASE("the self-centring lesson: what the README says of the wall's tendon and dampers, and of plates that break") {
  // The controlled-rocking wall with and without its tendon and dampers (README, "Self-centring").
  const std::string wall = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/controlled_rocking_wall.toml";
  struct Run {
    double theta, final_theta, moment;
  };
  const auto simulate = [&](const std::string& sets) {
    const fs::path dir = scratch_dir("simulate_test_wall");
    const Result r = run("simulate " + wall + " --duration 12 --json --out " + dir.string() + " " + sets);
    REQUIRE_MESSAGE(r.code == 0, r.err);
    const auto j = nlohmann::json::parse(r.out);
    return Run{j["peaks"]["theta"].get<double>(), j["final_theta"].get<double>(), j["peaks"]["base_moment"].get<double>()};
  };
  const Run both = simulate(""), no_tendon = simulate("--set device-=tendon"), no_dampers = simulate("--set device-=dampers"),
            bare = simulate("--set device=[]");
  for (const Run& r : {both, no_tendon, no_dampers, bare}) CHECK(r.final_theta == 0.0);  // every one re-centres
  CHECK(both.theta < 0.5 * no_tendon.theta);       // the tendon more than halves the peak rotation
  CHECK(no_dampers.theta < 0.5 * bare.theta);
  CHECK(both.theta < 0.6 * no_dampers.theta);      // and the dampers cut it further
  CHECK(both.moment > 2 * no_tendon.moment);       // at the price of more than twice the base moment
  // The chimney's plates breaking at 70 mm under the Papanui record x3 (README).
  const auto records = records_dir();
  if (!records) return;
  const std::string papanui = *records + "/christchurch2011_pphs_s57e.at2";
  const auto chimney = [&](const std::string& sets) {
    const fs::path dir = scratch_dir("simulate_test_plates");
    const Result r = run("simulate --record " + papanui + " --scale 3 --json --out " + dir.string() + " " + sets);
    REQUIRE_MESSAGE(r.code == 0, r.err);
    return nlohmann::json::parse(r.out);
  };
  const auto intact = chimney(""), breaking = chimney("--set damper.capacity=0.07"),
             none = chimney("--set damper.enabled=false");
  CHECK(intact["devices"][0]["fracture_s"].is_null());
  for (const auto& d : breaking["devices"]) {
    CHECK(d["fracture_s"].is_number());
    CHECK(d["peak_elongation_m"].get<double>() == close_to(0.07, 1e-6));
  }
  const auto theta = [](const nlohmann::json& j) { return j["peaks"]["theta_over_alpha"].get<double>(); };
  CHECK(theta(breaking) > 3 * theta(intact));  // broken plates let it rock more than three times as far
  CHECK(theta(breaking) > 0.75 * theta(none)); // nearly as far as with no damper at all
}

TEST_CASE("simulate with a vertical motion: the history carries a_v, the summary names it, the plane's motion is unchanged") {
  const auto records = records_dir();
  if (!records) return;
  const std::string waiau = *records + "/formats/20161113_110259_WTMC_20.V2A";
  const fs::path dir = scratch_dir("simulate_test_vertical");
  const Result r = run("simulate --record " + waiau + " --component N28W --vertical Up --duration 60 --json --out " +
                       dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["vertical_motion"].get<std::string>().find("Up") != std::string::npos);
  CHECK(j["motion"].get<std::string>().find("N28W") != std::string::npos);
  const CsvTable h = csv_table(file_text(dir / "history.csv"));
  REQUIRE(h.has("a_v [m/s2]"));
  double peak_v = 0;
  for (std::size_t i = 0; i < h.rows.size(); ++i) peak_v = std::max(peak_v, std::abs(std::stod(h.at(i, "a_v [m/s2]"))));
  CHECK(peak_v > 1.0);  // the Up component's motion, not zeros
  // The text summary says it too; without --vertical no a_v column.
  const Result text = run("simulate --record " + waiau + " --component N28W --vertical Up --duration 5 --out " + dir.string());
  REQUIRE_MESSAGE(text.code == 0, text.err);
  CHECK(text.out.find("vertical motion") != std::string::npos);
  const Result plain = run("simulate --record " + waiau + " --component N28W --duration 5 --out " + dir.string());
  REQUIRE_MESSAGE(plain.code == 0, plain.err);
  CHECK(!csv_table(file_text(dir / "history.csv")).has("a_v [m/s2]"));
  // Bad choices, one line each.
  const Result horizontal = run("simulate --record " + waiau + " --component N28W --vertical S62W --out " + dir.string());
  CHECK(horizontal.code == 2);
  CHECK(horizontal.err.find("component S62W is horizontal") != std::string::npos);
  const Result lone = run("simulate --vertical Up --out " + dir.string());
  CHECK(lone.code == 2);
  CHECK(lone.err == "rocking: error: --vertical Up: no such file (a component name needs the --record file it is a "
                    "component of)\n");
  const Result stray = run("simulate --vertical-units g --out " + dir.string());
  CHECK(stray.code == 2);
  CHECK(stray.err.find("describe a --vertical file") != std::string::npos);
}

TEST_CASE("simulate --azimuth: 0 and 90 degrees are the file's two horizontal components, run for run") {
  const auto records = records_dir();
  if (!records) return;
  const std::string waiau = *records + "/formats/20161113_110259_WTMC_20.V2A";
  const fs::path dir = scratch_dir("simulate_test_azimuth");
  const auto peaks = [&](const std::string& args) {
    const Result r = run("simulate --json --duration 60 --record " + waiau + " " + args + " --out " + dir.string());
    REQUIRE_MESSAGE(r.code == 0, r.err);
    return nlohmann::json::parse(r.out)["peaks"];
  };
  CHECK(peaks("--component N28W --azimuth 0") == peaks("--component N28W"));
  CHECK(peaks("--component N28W --azimuth 90") == peaks("--component S62W"));
  CHECK(peaks("--component N28W --azimuth 30") != peaks("--component N28W"));
  // A PEER pair: the other component from its own file.
  const std::string cbgs = *records + "/christchurch2011_cbgs_";
  const Result pair = run("simulate --json --duration 10 --record " + cbgs + "n89w.at2 --second " + cbgs +
                          "s01w.at2 --azimuth 90 --out " + dir.string());
  REQUIRE_MESSAGE(pair.code == 0, pair.err);
  const Result alone = run("simulate --json --duration 10 --record " + cbgs + "s01w.at2 --out " + dir.string());
  REQUIRE_MESSAGE(alone.code == 0, alone.err);
  CHECK(nlohmann::json::parse(pair.out)["peaks"] == nlohmann::json::parse(alone.out)["peaks"]);
  // Bad choices, one line each.
  const Result lone = run("simulate --azimuth 30 --record " + cbgs + "n89w.at2 --out " + dir.string());
  CHECK(lone.code == 2);
  CHECK(lone.err.find("holds no other horizontal component beside N89W") != std::string::npos);
  const Result stray = run("simulate --second " + cbgs + "s01w.at2 --out " + dir.string());
  CHECK(stray.code == 2);
  CHECK(stray.err == "rocking: error: --second: the other horizontal component is for --azimuth; none was given\n");
  const Result wild = run("simulate --azimuth 1e9 --record " + waiau + " --out " + dir.string());
  CHECK(wild.code == 2);
  CHECK(wild.err.find("must be an angle in degrees, -360 to 360") != std::string::npos);
}
