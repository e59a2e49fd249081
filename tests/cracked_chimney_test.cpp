// The shipped cracked chimney (data/scenes/chimney_cracked.toml, MODEL.md 15):
// the Christchurch chimney on its rocking base with its dampers, cracked
// through at node 3, its top piece a rigid block free on the shaft. Its
// question: does the rocking base still protect the cracked top? Held here,
// through the program as a user runs it:
// - the run ends `separated`, stated (exit 0, summary.json's separation
//   naming joint 1), never continued and never a failure;
// - under the scene's pulse the crack opens after the base lifts, and the run
//   ends at the base's first impact, whose momentum law leaves the base's
//   contact in tension (stated as joint 0 separating); on a fixed base the
//   crack opens as early and the top rocks further before it leaves its joint;
// - a study's hunt finds the level at which the top leaves its joint under El
//   Centro the same on the rocking and the fixed base, and at that level the
//   base never lifts: the crack opens below the base's own threshold, so the
//   rocking base cannot protect it.
// The times and levels are the README's, held to half a unit of their last
// printed digit (a regression guard for what it quotes; the physics of
// joints is held to closed forms in joints_test and joints_devices_test).
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

#include "close.hpp"
#include "csv_table.hpp"
#include "records.hpp"
#include "run_program.hpp"
#include "temp_path.hpp"

namespace {

const std::string scene = std::string(ROCKING_SCENES) + "/chimney_cracked.toml";

nlohmann::json simulate(const std::string& name, const std::string& more) {
  const std::filesystem::path out = scratch_dir(name);
  const cli::Result r = cli::run(fmt::format("-q simulate {} {} --out {}", scene, more, out.string()), 120);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  return nlohmann::json::parse(file_text(out / "summary.json"));
}

}  // namespace

TEST_CASE("the cracked chimney under its pulse: the crack opens after the base lifts, and the run ends separated at the base's first impact, stated") {
  const nlohmann::json s = simulate("cracked", "");
  CHECK(s["outcome"] == "separated");
  REQUIRE(s.contains("separation"));
  CHECK_MESSAGE(s["separation"].get<std::string>().starts_with("joint 0 at t = "), s["separation"]);
  CHECK(s["separated_joint"] == 0);
  const auto& base = s["joints"][0];
  const auto& crack = s["joints"][1];
  CHECK(base["first_uplift_s"].get<double>() < crack["first_uplift_s"].get<double>());
  CHECK(s["t_end"].get<double>() == base["first_impact_s"].get<double>());
  CHECK(base["first_uplift_s"].get<double>() == within(0.1295, 5e-5));
  CHECK(crack["first_uplift_s"].get<double>() == within(0.1482, 5e-5));
  CHECK(base["first_impact_s"].get<double>() == within(0.4560, 5e-5));
  CHECK(s["t_end"].get<double>() == within(0.456, 5e-4));
  CHECK(crack["peak_theta"].get<double>() == within(0.0096, 5e-5));

  const nlohmann::json fixed = simulate("cracked_fixed", "--set contact.rocking=false");
  CHECK(fixed["outcome"] == "separated");
  CHECK_MESSAGE(fixed["separation"].get<std::string>().starts_with("joint 1 at t = "), fixed["separation"]);
  CHECK(fixed["separated_joint"] == 1);
  CHECK(fixed["joints"][0]["uplifts"].get<long>() == 0);
  CHECK(fixed["joints"][1]["first_uplift_s"].get<double>() == within(0.1453, 5e-5));
  CHECK(fixed["joints"][1]["peak_theta"].get<double>() == within(0.0172, 5e-5));
  CHECK(fixed["t_end"].get<double>() == within(0.592, 5e-4));
  MESSAGE("rocking base: crack opens at " << crack["first_uplift_s"] << " s, top leaves at " << s["t_end"]
                                          << " s; fixed base: " << fixed["joints"][1]["first_uplift_s"] << " s, "
                                          << fixed["t_end"] << " s");
}

TEST_CASE("the cracked chimney's hunt under El Centro: the top leaves its joint at the same level on the rocking and the fixed base, below the base's uplift") {
  const auto dir = records_dir();
  if (!dir) return;  // records_dir said why (and failed under CI)
  const std::string record = *dir + "/elcentro_1940_ns.at2";
  const std::filesystem::path out = scratch_dir("cracked_hunt");
  const cli::Result r = cli::run(fmt::format("-q ida {} --record {} --variants scene,fixed-base --im pga --levels 0.01 "
                                             "--hunt --hunt-step 0.01 --no-plot --out {}",
                                             scene, record, out.string()),
                                 300);
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const CsvTable hunt = csv_table(file_text(out / "hunt.csv"));
  REQUIRE(hunt.rows.size() == 2);
  double scale = 0;
  for (std::size_t i = 0; i < 2; ++i) {
    CAPTURE(hunt.at(i, "variant"));
    CHECK(hunt.at(i, "error").empty());
    // The README's 0.067 g, to the hunt's precision (0.0005 g).
    CHECK(std::stod(hunt.at(i, "collapse_level")) == within(0.067, 5e-4));
    scale = std::stod(hunt.at(i, "collapse_scale"));
  }
  // At that level the top leaves its joint with the base never lifted.
  const nlohmann::json s = simulate("cracked_at_level", fmt::format("--record {} --scale {:.12g}", record, scale));
  CHECK(s["outcome"] == "separated");
  CHECK(s["joints"][0]["uplifts"].get<long>() == 0);
  MESSAGE("separation at pga " << hunt.at(0, "collapse_level") << " g (scale " << scale << "), base uplifts "
                               << s["joints"][0]["uplifts"]);
}
