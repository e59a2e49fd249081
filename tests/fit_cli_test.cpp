// `rocking fit` as a user runs it: the printed table pasted into a scene
// reproduces the test's loop to the reported RMS error; the figure and the
// table are written; tests that cannot be fitted get one line and exit 2.
#include <doctest/doctest.h>
#include "close.hpp"
#include <nlohmann/json.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include "run_program.hpp"
import rocking.fitting;
import rocking.scene;

namespace fs = std::filesystem;

namespace {
const std::string source = ROCKING_SOURCE_DIR;
const std::string bouc_wen_test = source + "/data/tests/bouc_wen_cyclic.csv";
}  // namespace

TEST_CASE("the fitted table pasted into a scene reproduces the test's loop to the reported RMS error") {
  for (const char* args : {"", " --fix beta=0.3 --fix n=1.5"}) {
    const cli::Result r = cli::run("fit " + bouc_wen_test + args + " --json");
    REQUIRE(r.code == 0);
    const nlohmann::json j = nlohmann::json::parse(r.out);
    const std::string table = j["table"];
    const fs::path scene = fs::temp_directory_path() / "rocking_fit_scene.toml";
    {
      std::ifstream base(source + "/data/scenes/christchurch_chimney.toml");
      std::stringstream text;
      text << base.rdbuf();
      std::ofstream(scene) << text.str() << "\n" << table;
    }
    const rocking::Scene s = rocking::load_scene(scene.string());
    const std::vector<rocking::Device> devices = rocking::scene_devices(s);
    const auto it = std::find_if(devices.begin(), devices.end(), [](const rocking::Device& d) { return d.name == "plates_left"; });
    REQUIRE(it != devices.end());
    const rocking::CyclicTest test = rocking::read_cyclic_test(bouc_wen_test);
    const std::vector<double> F = rocking::law_force_history(it->law, test);
    double ssr = 0;
    for (std::size_t i = 0; i < F.size(); ++i) ssr += (F[i] - test.F[i]) * (F[i] - test.F[i]);
    const double rms = std::sqrt(ssr / static_cast<double>(F.size()));
    CHECK(rms == close_to(j["rms_error_N"].get<double>(), 1e-6));
    fs::remove(scene);
  }
}

TEST_CASE("rocking fit prints the parameters with their errors and writes the figure and the table") {
  const fs::path out = fs::temp_directory_path() / "rocking_fit_out";
  fs::remove_all(out);
  const cli::Result r = cli::run("fit " + bouc_wen_test + " --fix beta=0.3 --fix n=1.5 --thickness 2 --out " +
                                 out.string() + " --formats png");
  REQUIRE(r.code == 0);
  CHECK(r.out.find("+-") != std::string::npos);
  CHECK(r.out.find("(fixed)") != std::string::npos);
  CHECK(r.out.find("(1 - beta)") != std::string::npos);
  CHECK(r.out.find("[[device]]") != std::string::npos);
  CHECK(r.out.find("thickness x2") != std::string::npos);
  CHECK(fs::file_size(out / "fit.png") > 10000);
  CHECK(fs::exists(out / "fit.toml"));
  fs::remove_all(out);
}

TEST_CASE("rocking fit refuses what it cannot fit in one line, exit 2") {
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {Case{"fit /nonexistent.csv", "cannot open"},
                        Case{"fit " + source + "/data/tests/elastic_cyclic.csv", "never yields"},
                        Case{"fit " + bouc_wen_test + " --fix beta", "--fix beta: write KEY=VALUE"},
                        Case{"fit " + bouc_wen_test + " --fix q=1", "no such parameter"},
                        Case{"fit " + bouc_wen_test + " --law spring", "unknown"},
                        Case{"fit " + source + "/data/tests/viscous_cyclic.csv --law elastic --thickness 2",
                             "plate scaling needs"}}) {
    const cli::Result r = cli::run(c.args);
    INFO(c.args << " -> " << r.err);
    CHECK(r.code == 2);
    CHECK(cli::lines(r.err) == 1);
    CHECK(r.err.find(c.says) != std::string::npos);
  }
}

TEST_CASE("the README's fit of the synthetic Bouc-Wen test, to the digits the README prints") {
  // A regression guard for the README's quoted fit ("Fitting a device law to
  // a cyclic test") and nothing more: each number to half a unit of its last
  // printed digit. Whether the fit is right is tests/fitting_test.cpp's: the
  // truth within the standard errors, their calibration over 40 draws, the
  // RMS error the 1 % noise.
  const cli::Result r = cli::run("fit " + bouc_wen_test + " --json");
  REQUIRE(r.code == 0);
  const nlohmann::json j = nlohmann::json::parse(r.out);
  struct Quoted {
    std::string key;
    double value, half_digit;
  };
  const std::vector<Quoted> quoted{{"k", 1.99786e7, 50}, {"eps", 0.0505022, 5e-8}, {"d_y", 0.00399676, 5e-9},
                                   {"alpha", 0.70378, 5e-6}, {"beta", 0.29622, 5e-6}, {"n", 1.5275, 5e-5}};
  int found = 0;
  for (const Quoted& q : quoted)
    for (const auto& p : j["parameters"])
      if (p["key"] == q.key) {
        INFO(q.key);
        ++found;
        CHECK(p["value"].get<double>() == within(q.value, q.half_digit));
      }
  CHECK(found == 6);
  CHECK(j["rms_error_N"].get<double>() == within(996, 0.5));
  CHECK(j["peak_error_N"].get<double>() == within(3268, 0.5));
}
