// What a run reports, as a user reads it (issue 39): every quantity under the
// name the schema (rocking.quantities) gives it, every device under its scene
// name with the numbers of its own history, and nothing a scene lacks.
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
#include <vector>
#include "run_program.hpp"
#include "csv_table.hpp"
#include "gnuplot_columns.hpp"
#include "records.hpp"

namespace fs = std::filesystem;
using namespace cli;

namespace {

const std::string wall = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/controlled_rocking_wall.toml";

// The largest |value| of a history column (its empty fields skipped).
double column_peak(const CsvTable& t, const std::string& header) {
  const std::size_t k = t.column(header);
  double peak = 0;
  for (const auto& row : t.rows)
    if (k < row.size() && !row[k].empty()) peak = std::max(peak, std::abs(std::stod(row[k])));
  return peak;
}

}  // namespace

TEST_CASE("the wall reports its tendon and each damper under their names, with the peaks of their own histories") {
  const fs::path dir = scratch_dir("outputs_wall");
  // A fine history, so that its maxima come close to the peaks taken on the dense output.
  const Result r = run("simulate " + wall + " --every 0.0005 --json --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  const CsvTable history = csv_table(file_text(dir / "history.csv"));
  // The wall has no [damper]: no damper_d or damper_F anywhere.
  CHECK(!j["peaks"].contains("damper_d"));
  CHECK(!j["peaks"].contains("damper_F"));
  CHECK(!history.has("damper_d [m]"));
  REQUIRE(j["devices"].size() == 3);
  for (const auto& d : j["devices"]) {
    const std::string name = d["name"].get<std::string>();
    CAPTURE(name);
    const double e = d["peak_elongation_m"].get<double>(), f = d["peak_force_N"].get<double>();
    CHECK(j["peaks"][name + ".elongation"].get<double>() == e);
    CHECK(j["peaks"][name + ".force"].get<double>() == f);
    // The reported peak is its own history's maximum, to the history's sampling.
    CHECK(column_peak(history, name + ".elongation [m]") == close_to(e, 2e-3));
    CHECK(column_peak(history, name + ".force [N]") == close_to(f, 2e-3));
  }
  // The tendon is no damper: its force is its prestress and more, its law named.
  const auto& tendon = j["devices"][0];
  CHECK(tendon["name"] == "tendon");
  CHECK(tendon["law"] == "elastic");
  CHECK(tendon["peak_force_N"].get<double>() > tendon["force_at_rest_N"].get<double>());
  CHECK(j["devices"][1]["peak_elongation_m"].get<double>() > tendon["peak_elongation_m"].get<double>());
  // The text summary names each with its law, the tendon with its prestress.
  const Result text = run("simulate " + wall + " --out " + dir.string());
  REQUIRE(text.code == 0);
  CHECK(contains(text.out, "  tendon            elastic, prestress 2.6e+06 N: peak e "));
  CHECK(contains(text.out, "  dampers_left      bouc-wen: peak e "));
  CHECK(!contains(text.out, "damper_d"));
}

TEST_CASE("a broken device reports its peak up to fracture, its fracture time, and no elongation after") {
  const fs::path dir = scratch_dir("outputs_broken");
  // The chimney's plates under three times its pulse break at e_u = 0.07 m.
  const Result r = run("simulate --scale 3 --set damper.capacity=0.07 --json --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  const CsvTable history = csv_table(file_text(dir / "history.csv"));
  CHECK(j["peaks"]["damper_d"].get<double>() <= 0.07 * (1 + 1e-6));  // not the anchor's chord after fracture
  for (const auto& d : j["devices"]) {
    const std::string name = d["name"].get<std::string>();
    CAPTURE(name);
    REQUIRE(d["fracture_s"].is_number());
    CHECK(d["state"] == "broken");
    CHECK(d["peak_elongation_m"].get<double>() == close_to(0.07, 1e-6));
    // Its history's fields are empty from its fracture on, and only then (t
    // is written to 9 digits).
    const double broke = d["fracture_s"].get<double>();
    const std::size_t e = history.column(name + ".elongation [m]"), t = history.column("t [s]");
    for (const auto& row : history.rows) CHECK(row[e].empty() == (std::stod(row[t]) >= broke * (1 - 1e-8)));
  }
}

TEST_CASE("a run into a folder that holds another run's files replaces them, leaving nothing partial") {
  const fs::path dir = scratch_dir("outputs_again");
  const std::string scene = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  REQUIRE(run("-q simulate " + scene + " --set excitation.kind=none --set initial.theta=0.05 --out " + dir.string())
              .code == 0);
  const std::string first = file_text(dir / "history.csv");
  REQUIRE(run("-q simulate " + scene + " --set excitation.kind=none --set initial.theta=0.1 --out " + dir.string())
              .code == 0);
  const std::string second = file_text(dir / "history.csv");
  CHECK(second != first);
  CHECK(nlohmann::json::parse(file_text(dir / "summary.json"))["peaks"]["theta"].get<double>() ==
        close_to(0.1, 1e-6));
  for (const auto& entry : fs::directory_iterator(dir)) {
    CAPTURE(entry.path().filename().string());
    CHECK((entry.path().filename() == "history.csv" || entry.path().filename() == "summary.json"));
  }
}

TEST_CASE("--list-quantities names what a scene reports, with units, and what it lacks") {
  const Result r = run("simulate " + wall + " --list-quantities");
  REQUIRE(r.code == 0);
  CHECK(contains(r.out, "tendon.force                 N       history,peak,study"));
  CHECK(contains(r.out, "damper_d                     m       history,peak,study   damper elongation (signed by the "
                        "pivot) (not in this scene)"));
  CHECK(contains(r.out, "delta_t                      -       history,peak,study   total top drift\n"));
  // The energy balance's terms and each device's work are given on request: a run tracks them.
  CHECK(contains(r.out, "tendon.work                  J       on request           work done on it since the start of "
                        "tendon (elastic)\n"));
  CHECK(contains(r.out, "W_ground                     J       on request           work done by the ground since the "
                        "start\n"));
}

TEST_CASE("IDA columns and --limit take each device by its name") {
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("outputs_ida");
  const std::string rec = *records + "/elcentro_1940_ns.at2";
  const Result r = run("-q ida " + wall + " --record " + rec + " --scales 1,3 --variants scene,without:tendon "
                       "--limit dampers_left.elongation=0.01 --duration 12 --no-plot --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable ida = csv_table(file_text(dir / "ida.csv"));
  REQUIRE(ida.rows.size() == 4);
  CHECK(!ida.has("damper_d"));
  for (std::size_t i = 0; i < ida.rows.size(); ++i) {
    CAPTURE(i);
    CHECK(!ida.at(i, "dampers_left.elongation").empty());
    CHECK(ida.at(i, "tendon.force").empty() == (ida.at(i, "variant") == "without:tendon"));
  }
  CHECK(contains(file_text(dir / "fragility.csv"), "scene,dampers_left.elongation>=0.01,sf,"));
  CHECK(contains(file_text(dir / "summary.csv"), "scene,tendon.force,sf,1,1,"));
  // A device the scene lacks is refused before any run, in one line.
  const Result typo = run("-q ida " + wall + " --record " + rec + " --scales 1 --limit plates.elongation=0.07 "
                          "--no-plot --out " + (dir / "typo").string());
  CHECK(typo.code == 2);
  CHECK(lines(typo.err) == 1);
  CHECK(contains(typo.err, "no device 'plates' in the study's scene (devices: tendon, dampers_left, dampers_right)"));
}

TEST_CASE("theta_dot: a block released from a tilt reaches sqrt(2 p^2 (cos(alpha - theta0) - cos alpha)) at its first impact") {
  // Energy: m g R (cos(alpha - theta0) - cos alpha) = J_p theta_dot^2 / 2, p^2 = m g R / J_p.
  const std::string block = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  const Result modal = run("modal " + block + " --json");
  REQUIRE(modal.code == 0);
  const auto m = nlohmann::json::parse(modal.out);
  const double p = m["p"].get<double>(), alpha = m["alpha_cg"].get<double>(), theta0 = 0.1;
  const fs::path dir = scratch_dir("outputs_theta_dot");
  const Result r = run("simulate " + block + " --set initial.theta=0.1 --set excitation.kind=none --duration 2 --json "
                       "--out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const auto j = nlohmann::json::parse(r.out);
  const double expected = std::sqrt(2 * p * p * (std::cos(alpha - theta0) - std::cos(alpha)));
  CHECK(j["peaks"]["theta_dot"].get<double>() == close_to(expected, 1e-5));
  // The same quantity is a history column, an IDA column and a limit state.
  CHECK(csv_table(file_text(dir / "history.csv")).has("theta_dot [rad/s]"));
  const auto records = records_dir();
  if (!records) return;
  const Result study = run("-q ida " + block + " --record " + *records + "/elcentro_1940_ns.at2 --scales 1,2 "
                           "--variants scene --limit theta_dot=0.1 --duration 10 --no-plot --out " + (dir / "ida").string());
  REQUIRE_MESSAGE(study.code == 0, study.err);
  const CsvTable ida = csv_table(file_text(dir / "ida" / "ida.csv"));
  REQUIRE(ida.rows.size() == 2);
  CHECK(std::stod(ida.at(1, "theta_dot")) > 0);
  CHECK(file_text(dir / "ida" / "fragility.csv").find("scene,theta_dot>=0.1,sf,") != std::string::npos);
}

TEST_CASE("a_N: on a fixed base the top's absolute acceleration is a_g + u_N'' of its own history") {
  // The chimney on a fixed base under its pulse, history every 0.5 ms: the
  // central second difference of u_N plus a_g agrees with the reported a_N
  // to the difference's truncation error (about (omega h)^2 / 12 of the peak).
  const fs::path dir = scratch_dir("outputs_a_top");
  const Result r = run("simulate --set contact.rocking=false --every 0.0005 --rtol 1e-8 --atol 1e-12 --json --out " +
                       dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(dir / "history.csv"));
  const std::size_t t = h.column("t [s]"), u = h.column("u_N [m]"), a_g = h.column("a_g [m/s2]"),
                    a_N = h.column("a_N [m/s2]");
  auto v = [&](std::size_t row, std::size_t col) { return std::stod(h.rows[row][col]); };
  double worst = 0, peak = 0;
  for (std::size_t i = 1; i + 1 < h.rows.size(); ++i) {
    const double dt = v(i, t) - v(i - 1, t);
    REQUIRE(std::abs(v(i + 1, t) - v(i, t) - dt) < 1e-9);  // evenly spaced (no events on a fixed base)
    const double second = (v(i + 1, u) - 2 * v(i, u) + v(i - 1, u)) / (dt * dt);
    worst = std::max(worst, std::abs(second + v(i, a_g) - v(i, a_N)));
    peak = std::max(peak, std::abs(v(i, a_N)));
  }
  CHECK(worst < 2e-3 * peak);
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["peaks"]["a_N"].get<double>() == close_to(peak, 1e-3));
}

TEST_CASE("--history chooses the history's columns from the schema: a wrong choice is one line before any run") {
  const fs::path dir = scratch_dir("outputs_history");
  const Result all = run("simulate --json --out " + (dir / "all").string());
  REQUIRE(all.code == 0);
  const Result some = run("simulate --history theta,a_N,damper_left.force,delta_t --out " + (dir / "some").string());
  REQUIRE_MESSAGE(some.code == 0, some.err);
  const CsvTable full = csv_table(file_text(dir / "all" / "history.csv"));
  const CsvTable chosen = csv_table(file_text(dir / "some" / "history.csv"));
  CHECK(chosen.header == std::vector<std::string>{"t [s]", "theta [rad]", "a_N [m/s2]", "damper_left.force [N]",
                                                  "delta_t [-]"});
  REQUIRE(chosen.rows.size() == full.rows.size());
  for (const std::string& h : chosen.header)  // the same numbers as the full history's, column by column
    for (std::size_t i = 0; i < chosen.rows.size(); ++i) CHECK(chosen.at(i, h) == full.at(i, h));
  struct Bad {
    std::string choice, says;
  };
  for (const Bad& b : {Bad{"nope", "--history nope: unknown quantity"},
                       Bad{"theta,theta", "--history theta: named twice"},
                       Bad{"plates.force", "--history plates.force: no device 'plates' in this scene"}}) {
    CAPTURE(b.choice);
    const Result r = run("simulate --history " + b.choice + " --out " + (dir / "bad").string());
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(contains(r.err, b.says));
    CHECK(!fs::exists(dir / "bad"));  // refused before any output
  }
  const Result block = run("simulate " + std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml --history "
                           "base_shear --out " + (dir / "bad").string());
  CHECK(block.code == 2);
  CHECK(contains(block.err, "--history base_shear: this scene does not report it"));
}

TEST_CASE("plot response finds its series by name: a column inserted in the middle of a history moves nothing") {
  // A history with an extra column before delta_t, as a new quantity inserted
  // in the middle of the schema would write: the figure still draws delta_t,
  // theta_over_alpha and the damper's loop from their own columns.
  const fs::path dir = scratch_dir("outputs_inserted");
  REQUIRE(run("-q simulate --out " + (dir / "run").string()).code == 0);
  const std::string text = file_text(dir / "run" / "history.csv");
  const CsvTable plain = csv_table(text);
  const std::size_t at = plain.column("delta_t [-]");
  std::string shifted;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f = csv_split(line);
    f.insert(f.begin() + static_cast<long>(at), shifted.empty() ? "inserted [m]" : "0.5");
    for (std::size_t k = 0; k < f.size(); ++k) shifted += (k ? "," : "") + f[k];
    shifted += "\n";
  }
  fs::create_directories(dir / "moved");
  std::ofstream(dir / "moved" / "history.csv") << shifted;
  const Result r = run("-q plot response --from " + (dir / "moved").string() + " --formats png --out " +
                       (dir / "fig").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string gp = file_text(dir / "fig" / "response.gp");
  const CsvTable moved = csv_table(shifted);
  CHECK(moved.column("delta_t [-]") == at + 1);
  // Every series by its header name, whatever its position; no column by number.
  CHECK(contains(gp, "set datafile columnheaders"));
  CHECK(contains(gp, "using (column('t [s]')):(column('delta_t [-]')*100)"));
  CHECK(contains(gp, ":(column('theta_over_alpha [-]')*1)"));
  CHECK(contains(gp, "(column('damper_d [m]') == 0 || column('damper_F [N]') == 0 ? NaN"));
  CHECK(!contains(gp, "column('inserted"));  // the inserted column is not drawn (the folder's name holds the word)
  CHECK_MESSAGE(numbered_column(gp).empty(), numbered_column(gp));
}

TEST_CASE("node and element recorders agree with the schema's own quantities and with statics") {
  // The chimney under its pulse: element E spans node E-1 to E; its shear and
  // end moments come from f = K u, so element1's are the base's, element2's
  // shear is the mid-height shear (16.5 m lies in element 2) and the moment,
  // linear along an element with no load between its nodes, interpolates to
  // the mid-height moment. Node 4 is the top: u_N, delta_t H_N and a_N.
  const fs::path dir = scratch_dir("outputs_members");
  const Result modal = run("modal --json");
  REQUIRE(modal.code == 0);
  const auto m = nlohmann::json::parse(modal.out);
  const double V_ref = m["V_ref"].get<double>(), M_ref = m["M_ref"].get<double>();
  const Result r = run("simulate --history u_N,delta_t,a_N,base_shear,base_moment,mid_shear,mid_moment,node4.u,"
                       "node4.x,node4.a_abs,node4.x_abs,x_g,node1.y,element1.V,element1.M_bottom,element2.V,"
                       "element2.M_bottom,element2.M_top --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(dir / "history.csv"));
  REQUIRE(h.rows.size() > 100);
  auto v = [&](std::size_t i, const char* col) { return std::stod(h.at(i, col)); };
  const double H_N = 33.05, H_1 = 10.4, H_2 = 17.95, mid = H_N / 2;
  double peak_V = 0, peak_M = 0, uplift = 0;
  for (std::size_t i = 0; i < h.rows.size(); ++i) {
    CAPTURE(i);
    peak_V = std::max(peak_V, std::abs(v(i, "element1.V [N]")));
    peak_M = std::max(peak_M, std::abs(v(i, "element1.M_bottom [N m]")));
    uplift = std::max(uplift, v(i, "node1.y [m]"));
    // 9 significant digits in the file: agreement to 1e-8 of the values.
    CHECK(v(i, "element1.V [N]") / V_ref == close_to(v(i, "base_shear [V_ref]"), 1e-7, 1e-13));
    CHECK(v(i, "element1.M_bottom [N m]") / M_ref == close_to(v(i, "base_moment [M_ref]"), 1e-7, 1e-13));
    CHECK(v(i, "element2.V [N]") / V_ref == close_to(v(i, "mid_shear [V_ref]"), 1e-7, 1e-13));
    const double w = (mid - H_1) / (H_2 - H_1);
    const double M_mid = (1 - w) * v(i, "element2.M_bottom [N m]") + w * v(i, "element2.M_top [N m]");
    CHECK(M_mid / M_ref == close_to(v(i, "mid_moment [M_ref]"), 1e-7, 1e-13));
    CHECK(v(i, "node4.u [m]") == v(i, "u_N [m]"));
    CHECK(v(i, "node4.x [m]") / H_N == close_to(v(i, "delta_t [-]"), 1e-7, 1e-16));
    CHECK(v(i, "node4.a_abs [m/s2]") == close_to(v(i, "a_N [m/s2]"), 1e-7, 1e-13));
    const double x = v(i, "node4.x [m]"), x_g = v(i, "x_g [m]"), x_abs = v(i, "node4.x_abs [m]");
    CHECK(std::abs(x_abs - x - x_g) <= 1e-8 * (std::abs(x) + std::abs(x_g) + std::abs(x_abs)));
  }
  CHECK(peak_V > 0.1 * V_ref);  // the comparisons above saw real forces
  CHECK(peak_M > 0.1 * M_ref);
  CHECK(uplift > 1e-4);  // the pulse makes it rock: node 1 lifts
}

TEST_CASE("x_g: the ground's displacement is a_g integrated twice (the one-sine pulse's closed form)") {
  // The chimney's pulse: A sin(w t) on [0, T] from rest gives
  // x_g = A / w (t - sin(w t) / w), then A T / w at rest after it.
  const fs::path dir = scratch_dir("outputs_x_g");
  const Result r = run("simulate --set excitation.kind=pulse --set excitation.pulse=one-sine "
                       "--set excitation.amplitude_g=0.5 --set excitation.period=0.8 --set excitation.duration=2 "
                       "--history a_g,x_g --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(dir / "history.csv"));
  const double A = 0.5 * 9.81, T = 0.8, w = 2 * 3.141592653589793 / T;
  REQUIRE(h.rows.size() > 100);
  for (std::size_t i = 0; i < h.rows.size(); ++i) {
    const double t = std::stod(h.at(i, "t [s]")), tt = std::min(t, T);
    CAPTURE(t);
    CHECK(std::stod(h.at(i, "x_g [m]")) == close_to(A / w * (tt - std::sin(w * tt) / w), 1e-8, 1e-17));
  }
}

TEST_CASE("x_g under a record: the trapezoidal double integral of the history's own a_g") {
  // El Centro, sampled every 0.02 s, recorded every 2 ms: a_g is linear
  // between rows, so v by the trapezoid rule is exact and x's trapezoid errs
  // by h^3 / 12 |a'| a row (about 1e-5 m over 10 s).
  const auto records = records_dir();
  if (!records) return;
  const fs::path dir = scratch_dir("outputs_x_g_record");
  const Result r = run("simulate --record " + *records + "/elcentro_1940_ns.at2 --duration 10 --every 0.002 "
                       "--history a_g,x_g --out " + dir.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(dir / "history.csv"));
  double v = 0, x = 0, worst = 0, peak = 0;
  for (std::size_t i = 1; i < h.rows.size(); ++i) {
    const double dt = std::stod(h.at(i, "t [s]")) - std::stod(h.at(i - 1, "t [s]"));
    if (dt <= 0) continue;  // an event's row repeats no time, but may fall between
    const double v_next = v + dt * (std::stod(h.at(i - 1, "a_g [m/s2]")) + std::stod(h.at(i, "a_g [m/s2]"))) / 2;
    x += dt * (v + v_next) / 2;
    v = v_next;
    worst = std::max(worst, std::abs(x - std::stod(h.at(i, "x_g [m]"))));
    peak = std::max(peak, std::abs(x));
  }
  CHECK(peak > 0.02);
  CHECK(worst < 1e-3 * peak);
}

TEST_CASE("recorders refuse what the structure lacks, in one line") {
  const fs::path dir = scratch_dir("outputs_members_bad");
  const std::string block = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/rigid_block.toml";
  struct Bad {
    std::string scene, choice, says;
  };
  for (const Bad& b : {Bad{"", "node5.x", "--history node5.x: no node 5 (this structure's nodes are 1 to 4)"},
                       Bad{"", "element0.V", "--history element0.V: no element 0"},
                       Bad{"", "node4.v", "--history node4.v: unknown quantity"},
                       Bad{block, "node1.u", "--history node1.u: this scene does not report it"},
                       Bad{block, "element1.M_top", "--history element1.M_top: this scene does not report it"}}) {
    CAPTURE(b.choice);
    const Result r = run("simulate " + b.scene + " --history " + b.choice + " --out " + (dir / "bad").string());
    CHECK(r.code == 2);
    CHECK(lines(r.err) == 1);
    CHECK(contains(r.err, b.says));
    CHECK(!fs::exists(dir / "bad"));
  }
  // A rigid block's nodes still move as the block does: the top's x is delta_t H.
  const Result ok = run("simulate " + block + " --history delta_t,node1.x,node1.y --out " + (dir / "block").string());
  REQUIRE_MESSAGE(ok.code == 0, ok.err);
  const CsvTable h = csv_table(file_text(dir / "block" / "history.csv"));
  REQUIRE(!h.rows.empty());
}

TEST_CASE("a scene's [output] table chooses the history's columns and interval, and the options replace it") {
  const fs::path dir = scratch_dir("outputs_scene_table");
  const std::string chimney = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/christchurch_chimney.toml";
  const std::string set = " --set 'output.history=[\"theta\",\"node4.x_abs\",\"element1.V\"]' --set output.interval=0.05";
  const Result r = run("simulate " + chimney + set + " --out " + (dir / "scene").string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable h = csv_table(file_text(dir / "scene" / "history.csv"));
  CHECK(h.header == std::vector<std::string>{"t [s]", "theta [rad]", "node4.x_abs [m]", "element1.V [N]"});
  REQUIRE(h.rows.size() > 3);
  CHECK(std::stod(h.at(1, "t [s]")) == close_to(0.05, 1e-12));
  const Result replaced = run("simulate " + chimney + set + " --history delta_t --every 0.02 --out " + (dir / "opt").string());
  REQUIRE_MESSAGE(replaced.code == 0, replaced.err);
  const CsvTable o = csv_table(file_text(dir / "opt" / "history.csv"));
  CHECK(o.header == std::vector<std::string>{"t [s]", "delta_t [-]"});
  CHECK(std::stod(o.at(1, "t [s]")) == close_to(0.02, 1e-12));
  // A wrong name is refused where it stands; one the scene cannot report names the table.
  const fs::path file = dir / "bad.toml";
  std::ofstream(file) << file_text(chimney) << "\n[output]\nhistory = [\"theta\", \"nodes.x\"]\n";
  const Result bad = run("simulate " + file.string() + " --out " + (dir / "bad").string());
  CHECK(bad.code == 2);
  CHECK(lines(bad.err) == 1);
  CHECK(contains(bad.err, file.string() + ":"));
  CHECK(contains(bad.err, "output.history[1]: 'nodes.x': unknown quantity"));
  const Result lacks = run("simulate " + chimney +  " --set structure.rigid=true --set 'output.history=[\"node2.u\"]' --out " +
                           (dir / "bad").string());
  CHECK(lacks.code == 2);
  CHECK(contains(lacks.err, "output.history node2.u: this scene does not report it"));
}
