// The `rocking` program as a user meets it: help that teaches, JSON that other
// tools can read, and bad input that ends in one line on stderr and exit code 2.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <string>
#include "run_program.hpp"


TEST_CASE("rocking --help lists the subcommands and modal --help explains --set") {
  const Result top = run("--help");
  CHECK(top.code == 0);
  CHECK(top.out.find("modal") != std::string::npos);
  const Result modal = run("modal --help");
  CHECK(modal.code == 0);
  CHECK(modal.out.find("--set") != std::string::npos);
  CHECK(modal.out.find("structure.EI_scale") != std::string::npos);
}

TEST_CASE("modal --json prints one object with every documented key, in SI units") {
  const Result r = run("modal --json");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"fixed_base_hz", "rocking_hz", "rocking_p", "damper_pre_yield_hz",
                          "damper_post_yield_p", "r_eq10", "J_p", "H_cg", "alpha_cg", "M_ref", "V_ref"})
    CHECK_MESSAGE(j.contains(key), key);
  CHECK(j["fixed_base_hz"].size() == 4);
  CHECK(j["fixed_base_hz"][0].get<double>() == doctest::Approx(2.176).epsilon(5e-3));
}

TEST_CASE("modal on a scene file with --set changes the result as asked") {
  const std::string scene = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/christchurch_chimney.toml";
  const auto base = nlohmann::json::parse(run("modal " + scene + " --json").out);
  const auto soft = nlohmann::json::parse(run("modal " + scene + " --json --set structure.EI_scale=0.25").out);
  CHECK(soft["fixed_base_hz"][0].get<double>() ==
        doctest::Approx(0.5 * base["fixed_base_hz"][0].get<double>()).epsilon(1e-9));
  const auto no_damper = nlohmann::json::parse(run("modal --json --set damper.enabled=false").out);
  CHECK(no_damper["damper_pre_yield_hz"].is_null());
  // A central tendon a --set away: the rocking stiffness gains k B^2 and the prestress holds P0 B.
  const auto tendon = nlohmann::json::parse(
      run(R"(modal --json --set 'device+={kind="elastic", at=0, kinematics="vertical", free_length=33, P0=2e6, k=5e7}')").out);
  const double B = 3.3;
  CHECK(tendon["k_theta"]["right"]["at_rest"].get<double>() ==
        doctest::Approx(base["k_theta"]["right"]["at_rest"].get<double>() + 5e7 * B * B).epsilon(1e-12));
  CHECK(tendon["device_held_moment"]["left"].get<double>() == doctest::Approx(2e6 * B).epsilon(1e-12));
}

TEST_CASE("bad input exits 2 with one line on stderr naming what and where") {
  struct Case {
    const char* args;
    const char* says;
  };
  for (const Case& c : {Case{"modal --set structure.masses=[1,-2,3,4]", "structure.masses[1]: must be in [0.001, 1e+12] kg"},
                        Case{"modal --set structure", "--set structure: expected TABLE.KEY=VALUE"},
                        Case{"modal /no/such/scene.toml", "/no/such/scene.toml: scene file not found"},
                        Case{"modal --no-such-flag", "--no-such-flag"},
                        Case{"", "A subcommand is required"}}) {
    const Result r = run(c.args);
    CHECK_MESSAGE(r.code == 2, c.args);
    CHECK_MESSAGE(lines(r.err) == 1, c.args << " -> " << r.err);
    CHECK_MESSAGE(r.err.find(c.says) != std::string::npos, c.args << " -> " << r.err);
    CHECK(r.out.empty());
  }
}
