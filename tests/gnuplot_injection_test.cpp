// Text from input never reaches gnuplot's interpreter (TOOLCHAIN.md, gnuplot
// and untrusted text). gnuplot runs backquoted text as a shell command and
// evaluates system(...) in a string that is closed early; every figure is
// fed a record whose header, file name, a scene name, a run folder, a cyclic
// test and an animation named with such text, and must render it as text:
// the figure is written and no command ran (no marker file appears).
#include <doctest/doctest.h>
#include "temp_path.hpp"
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

// Every way into gnuplot's command line: backquotes, a closed single-quoted
// and a closed double-quoted string calling system(), a newline that starts a
// command of its own (and gnuplot's shell escape "!"), backslashes, printf
// conversions and a macro. Each would create a file named owned_N.
const std::string hostile =
    "`touch owned_1` x' . system('touch owned_2') . ' y\" . system(\"touch owned_3\") . \""
    "\\\nsystem(\"touch owned_4\")\n!touch owned_5\n%s %d @GPVAL_TERM \\n \\";

// The same text as one shell word.
std::string shell_word(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The same text as a TOML basic string.
std::string toml_string(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '\n') out += "\\n";
    else if (c == '"' || c == '\\') out += std::string("\\") + c;
    else out += c;
  }
  return out + "\"";
}

// A scene file of the project with its name replaced by the hostile text.
std::string hostile_scene(const fs::path& dir, const std::string& scene) {
  std::ifstream in(std::string(ROCKING_SOURCE_DIR) + "/data/scenes/" + scene);
  std::stringstream text;
  text << in.rdbuf();
  const std::string renamed =
      std::regex_replace(text.str(), std::regex("\nname = \"[^\"]*\""), "\nname = " + toml_string(hostile),
                         std::regex_constants::format_first_only);
  REQUIRE(renamed != text.str());
  const fs::path file = dir / ("hostile_" + scene);
  std::ofstream(file) << renamed;
  return file.string();
}

// A PEER record whose file name and header lines carry the hostile text (one
// line each: a header line cannot hold a newline), 4 s of a 1 Hz sine at 0.3 g.
std::string hostile_record(const fs::path& dir) {
  std::string one_line = hostile;
  for (char& c : one_line)
    if (c == '\n') c = ' ';
  const fs::path file = dir / (hostile + ".at2");
  std::ofstream out(file);
  out << "PEER NGA STRONG MOTION DATABASE RECORD " << one_line << "\n"
      << one_line << ", 1/1/2000, " << one_line << ", N\n"
      << "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS= 400, DT= .01 SEC\n";
  for (int i = 0; i < 400; ++i) out << 0.3 * std::sin(2 * 3.141592653589793 * 0.01 * i) << (i % 5 == 4 ? "\n" : " ");
  return file.string();
}

// Marker files anywhere under dir.
std::vector<std::string> markers(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().starts_with("owned")) found.push_back(e.path().string());
  return found;
}

void renders(const std::string& args, const fs::path& dir) {
  const Result r = run(args);
  CHECK_MESSAGE(r.code == 0, args << "\n -> " << r.code << " " << r.err);
  CHECK_MESSAGE(markers(dir).empty(), args);
  CHECK_MESSAGE(markers(fs::current_path()).empty(), args);
}

}  // namespace

TEST_CASE("the hostile text is what it claims to be: gnuplot runs it when spliced into a double-quoted string") {
  // The test's own check: were the figures to splice text as they once did,
  // this text would run commands. gnuplot itself shows it.
  const fs::path dir = scratch_dir("injection_control");
  const Result gnuplot = run("--version");  // the program runs; gnuplot is found the same way by every figure
  REQUIRE(gnuplot.code == 0);
  std::ofstream(dir / "control.gp") << "set title \"" << "`touch owned_control`" << "\"\n";
  REQUIRE(std::system(("cd " + dir.string() + " && gnuplot control.gp >/dev/null 2>&1").c_str()) == 0);
  CHECK(fs::exists(dir / "owned_control"));
}

TEST_CASE("figures of records, scenes, studies and animations render hostile names as text and run nothing") {
  const fs::path dir = scratch_dir("injection");
  const std::string record = shell_word(hostile_record(dir));
  const std::string chimney = shell_word(hostile_scene(dir, "christchurch_chimney.toml"));
  const std::string block = shell_word(hostile_scene(dir, "rigid_block.toml"));
  const std::string out = (dir / "figures").string();
  renders("-q plot response " + chimney + " --record " + record + " --formats png --out " + out + "/response", dir);
  renders("-q plot modes " + chimney + " --formats png --out " + out + "/modes", dir);
  renders("-q record " + record + " --formats png --out " + out + "/record", dir);
  renders("-q ida " + block + " --record " + record + " --scales 1,3 --variants scene --formats png --out " + out + "/ida", dir);
  renders("-q ida " + block + " --record " + record + " --scales 1,3 --variants scene --per-record --formats png --out " + out +
              "/ida_per_record",
          dir);
  renders("-q sweep " + block + " --record " + record + " --scales 1,2 --set contact.restitution=0.8,0.9 "
              "--formats png --out " + out + "/sweep",
          dir);
  renders("-q spectrum " + block + " --sizes 1 --frequencies 1:2:1 --amplitudes 1:2:1 --formats png --out " + out +
              "/spectrum",
          dir);
  renders("-q tradeoff " + block + " --record " + record + " --rtols 1e-3,1e-4 --backends rk45 --repeats 1 "
              "--formats png --out " + out + "/tradeoff",
          dir);
  // A file name cannot end a line of the script: the animation's own name is the text on one line.
  std::string one_line = hostile;
  for (char& c : one_line)
    if (c == '\n') c = ' ';
  renders("-q animate " + block + " --record " + record + " --frames 4 --size 400x300 --out " +
              shell_word(out + "/animate/" + one_line + ".gif"),
          dir);
  const Result newline = run("-q animate " + block + " --frames 4 --out " + shell_word(out + "/animate/a\nb.gif"));
  CHECK(newline.code == 2);  // refused, one line naming --out's file name
  CHECK(lines(newline.err) == 1);
  // A run folder named with the text: its name is the figure's key.
  const std::string run_dir = shell_word(out + "/runs/" + hostile);
  REQUIRE(run("-q simulate " + block + " --record " + record + " --out " + run_dir).code == 0);
  renders("-q plot response --from " + run_dir + " --formats png --out " + out + "/from", dir);
  // A cyclic test whose file name is the text.
  const fs::path cyclic = dir / (hostile + ".csv");
  fs::copy_file(std::string(ROCKING_SOURCE_DIR) + "/data/tests/bouc_wen_cyclic.csv", cyclic);
  renders("-q fit " + shell_word(cyclic.string()) + " --formats png --out " + out + "/fit", dir);
  CHECK(fs::exists(out + "/fit/fit.png"));
  CHECK(fs::exists(out + "/modes/modes.png"));
}

TEST_CASE("figure names are file names in the output folder, never paths out of it") {
  const fs::path dir = scratch_dir("injection_names");
  for (const std::string& args : {"plot modes --name ../escaped --out " + (dir / "a").string(),
                                  "plot modes --name .. --out " + (dir / "a").string(),
                                  "fit " + std::string(ROCKING_SOURCE_DIR) + "/data/tests/bouc_wen_cyclic.csv "
                                      "--figure ../escaped --out " + (dir / "b").string()}) {
    const Result r = run(args);
    CHECK_MESSAGE(r.code == 2, args << " -> " << r.code << " " << r.err);
    CHECK_MESSAGE(lines(r.err) == 1, r.err);
  }
  CHECK_FALSE(fs::exists(dir / "escaped.data"));
  CHECK_FALSE(fs::exists(dir / "escaped.png"));
  CHECK_FALSE(fs::exists(dir / "escaped.csv"));
}
