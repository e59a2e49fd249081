// The `rocking` program as a user meets it: help that teaches, JSON that other
// tools can read, and bad input that ends in one line on stderr and exit code 2.
#include <doctest/doctest.h>
#include "close.hpp"
#include <nlohmann/json.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>
#include "run_program.hpp"
#include "temp_path.hpp"


TEST_CASE("rocking --help lists the subcommands and modal --help explains --set") {
  const Result top = run("--help");
  CHECK(top.code == 0);
  CHECK(top.out.find("modal") != std::string::npos);
  const Result modal = run("modal --help");
  CHECK(modal.code == 0);
  CHECK(modal.out.find("--set") != std::string::npos);
  CHECK(modal.out.find("structure.EI_scale") != std::string::npos);
}

TEST_CASE("the program starts without the web server's or MPI's libraries, and opens each plugin only when needed") {
  // What the dynamic loader maps for the program: none of cpp-httplib,
  // OpenSSL or OpenMPI (they live in librocking_serve.so and librocking_mpi.so).
  const std::string err = temp_path("ldd.err").string();
  FILE* pipe = popen(("ldd " + std::string(ROCKING_BIN) + " 2>" + err).c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string mapped;
  char buf[512];
  while (std::fgets(buf, sizeof buf, pipe) != nullptr) mapped += buf;
  REQUIRE(pclose(pipe) == 0);
  INFO(mapped);
  CHECK(mapped.find("libc.so") != std::string::npos);
  for (const char* library : {"httplib", "libssl", "libcrypto", "libmpi", "libbrotli", "libz."})
    CHECK_MESSAGE(mapped.find(library) == std::string::npos, library);
  // The program alone, without its plugins beside it: the commands that need
  // one say which, in one line, exit 3; the others run.
  const std::filesystem::path alone = scratch_dir("alone") / "rocking";
  std::filesystem::copy_file(ROCKING_BIN, alone);
  const auto run_alone = [&](const std::string& env, const std::string& args) {
    const std::string out = temp_path("alone.err").string();
    const int status = std::system((env + " " + alone.string() + " " + args + " >/dev/null 2>" + out).c_str());
    return std::pair{WIFEXITED(status) ? WEXITSTATUS(status) : -1, file_text(out)};
  };
  const auto [serve_code, serve_err] = run_alone("", "serve --port 0");
  CHECK(serve_code == 3);
  CHECK(lines(serve_err) == 1);
  CHECK(serve_err.find("the lab's web server cannot be loaded") != std::string::npos);
  const auto [mpi_code, mpi_err] =
      run_alone("OMPI_COMM_WORLD_SIZE=2", "sweep --set damper.thickness=1,2 --record " + std::string(ROCKING_SOURCE_DIR) +
                                              "/data/scenes/christchurch_chimney.toml");
  CHECK(mpi_code == 3);
  CHECK(lines(mpi_err) == 1);
  CHECK(mpi_err.find("started by mpirun, but MPI cannot be loaded") != std::string::npos);
  CHECK(run_alone("", "modal --json").first == 0);
}

TEST_CASE("modal --json prints one object with every documented key, in SI units") {
  const Result r = run("modal --json");
  REQUIRE(r.code == 0);
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"fixed_base_hz", "rocking_hz", "rocking_p", "damper_pre_yield_hz",
                          "damper_post_yield_p", "r_eq10", "J_p", "H_cg", "alpha_cg", "M_ref", "V_ref"})
    CHECK_MESSAGE(j.contains(key), key);
  CHECK(j["fixed_base_hz"].size() == 4);
  CHECK(j["fixed_base_hz"][0].get<double>() == within(2.176, 5e-4));  // MODEL.md 8, to its digits
}

TEST_CASE("modal on a scene file with --set changes the result as asked") {
  const std::string scene = std::string(ROCKING_SOURCE_DIR) + "/data/scenes/christchurch_chimney.toml";
  const auto base = nlohmann::json::parse(run("modal " + scene + " --json").out);
  const auto soft = nlohmann::json::parse(run("modal " + scene + " --json --set structure.EI_scale=0.25").out);
  CHECK(soft["fixed_base_hz"][0].get<double>() ==
        close_to(0.5 * base["fixed_base_hz"][0].get<double>(), 1e-9));
  const auto no_damper = nlohmann::json::parse(run("modal --json --set damper.enabled=false").out);
  CHECK(no_damper["damper_pre_yield_hz"].is_null());
  // A central tendon a --set away: the rocking stiffness gains k B^2 and the prestress holds P0 B.
  const auto tendon = nlohmann::json::parse(
      run(R"(modal --json --set 'device+={kind="elastic", at=0, kinematics="vertical", free_length=33, P0=2e6, k=5e7}')").out);
  const double B = 3.3;
  CHECK(tendon["k_theta"]["right"]["at_rest"].get<double>() ==
        close_to(base["k_theta"]["right"]["at_rest"].get<double>() + 5e7 * B * B, 1e-12));
  CHECK(tendon["device_held_moment"]["left"].get<double>() == close_to(2e6 * B, 1e-12));
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
                        Case{"", "name a subcommand: modal, simulate, plot, ida"}, Case{"-q", "name a subcommand"}}) {
    const Result r = run(c.args);
    CHECK_MESSAGE(r.code == 2, c.args);
    CHECK_MESSAGE(lines(r.err) == 1, c.args << " -> " << r.err);
    CHECK_MESSAGE(r.err.find(c.says) != std::string::npos, c.args << " -> " << r.err);
    CHECK(r.out.empty());
  }
}
