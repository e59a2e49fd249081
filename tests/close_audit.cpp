// The closeness audit, run by `make test` after every other test (a CTest
// fixture's cleanup). It re-derives, from the values each comparison logged
// (tests/close.hpp, ROCKING_CLOSE_LOG_DIR), the tolerance each check really
// applies, and fails when
//   - a relative check's floor dominates at every value it met: the stated
//     relative tolerance r is not the one checked (its real one, floor / max
//     |value|, is more than 2 r);
//   - an absolute check admits zero for a value that is never zero: its
//     tolerance exceeds every |expected| it met, so it admits almost anything;
//   - any test source still uses doctest's Approx, whose default scale adds
//     an absolute margin of epsilon to every check, or writes a relative
//     check by hand (CHECK(abs(a / b - 1) < r)), which the log never sees.
// It prints, per check, the stated tolerance, the largest observed relative
// difference and the values, so the audit can be read as well as run.
//
// usage: close_audit LOG_DIR TESTS_SOURCE_DIR
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>

namespace fs = std::filesystem;

namespace {

struct Site {
  double rel = 0, floor = 0;
  long evaluations = 0;
  double largest = 0;             // largest max(|actual|, |expected|)
  double smallest_expected = HUGE_VAL;  // smallest |expected|
  double worst_rel = 0;           // largest |a - e| / max(|a|, |e|)
  double worst_diff = 0;          // largest |a - e|
  double worst_a = 0, worst_e = 0;
};

std::string name(const std::string& file) { return fs::path(file).filename().string(); }

// Raw Approx( left in the tests: the check they state is not the one they make.
int scan_sources(const fs::path& tests) {
  int found = 0;
  const std::regex raw(R"((^|[^A-Za-z_])Approx\s*\()");
  // CHECK(std::abs(a / b - 1.0) < r): a closeness check the log never sees.
  const std::regex by_hand(R"(CHECK[A-Z_]*\(\s*(std::)?f?abs\([^;]*/[^;]*-\s*1(\.0*)?\s*\)\s*<)");
  for (const auto& entry : fs::recursive_directory_iterator(tests)) {
    const auto ext = entry.path().extension();
    if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
    if (entry.path().filename() == "close.hpp" || entry.path().filename() == "close_audit.cpp") continue;
    std::ifstream in(entry.path());
    std::string line;
    for (int n = 1; std::getline(in, line); ++n)
      if (std::regex_search(line, raw)) {
        std::cout << "FAIL " << entry.path().filename().string() << ":" << n
                  << ": doctest Approx (adds an absolute margin of epsilon); use close_to or within (tests/close.hpp)\n";
        ++found;
      } else if (std::regex_search(line, by_hand)) {
        std::cout << "FAIL " << entry.path().filename().string() << ":" << n
                  << ": a relative check written by hand (abs(a / b - 1) < r) escapes this audit; use close_to\n";
        ++found;
      }
  }
  return found;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: close_audit LOG_DIR TESTS_SOURCE_DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  if (!fs::is_directory(argv[2])) {
    std::cerr << "close_audit: " << argv[2] << ": not a folder of test sources\n";
    return 2;
  }
  int problems = scan_sources(argv[2]);

  std::map<std::tuple<std::string, int, double, double>, Site> sites;
  if (fs::is_directory(dir))
    for (const auto& entry : fs::directory_iterator(dir)) {
      std::ifstream in(entry.path());
      std::string line;
      while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string file, cell[7];
        if (!std::getline(fields, file, '\t')) continue;
        bool whole = true;
        for (auto& c : cell) whole = whole && static_cast<bool>(std::getline(fields, c, '\t'));
        if (!whole) continue;  // a line cut short by a test that crashed mid-write
        int at = 0;
        double rel = 0, floor = 0, a = 0, e = 0;
        try {
          at = std::stoi(cell[0]);
          rel = std::stod(cell[1]), floor = std::stod(cell[2]), a = std::stod(cell[3]), e = std::stod(cell[4]);
        } catch (const std::exception&) {
          std::cerr << "close_audit: " << entry.path().string() << ": a line that is not a comparison: " << line << '\n';
          return 2;
        }
        const double diff = std::abs(a - e);
        Site& s = sites[{name(file), at, rel, floor}];
        s.rel = rel;
        s.floor = floor;
        ++s.evaluations;
        const double m = std::max(std::abs(a), std::abs(e));
        s.largest = std::max(s.largest, m);
        s.smallest_expected = std::min(s.smallest_expected, std::abs(e));
        const double r = m > 0 ? diff / m : 0;
        if (r > s.worst_rel || s.evaluations == 1) {
          s.worst_rel = r;
          s.worst_a = a;
          s.worst_e = e;
        }
        s.worst_diff = std::max(s.worst_diff, diff);
      }
    }

  std::printf("%-34s %-22s %-10s %-12s %-12s %s\n", "check", "stated", "runs", "observed", "largest", "worst values");
  for (const auto& [key, s] : sites) {
    const auto& [file, line, rel, floor] = key;
    char where[80], stated[64];
    std::snprintf(where, sizeof where, "%s:%d", file.c_str(), line);
    if (rel > 0 && floor > 0) std::snprintf(stated, sizeof stated, "rel %.3g floor %.3g", rel, floor);
    else if (rel > 0) std::snprintf(stated, sizeof stated, "rel %.3g", rel);
    else std::snprintf(stated, sizeof stated, "abs %.3g", floor);
    std::string verdict;
    // (A comparison that failed is doctest's to report: CHECK_FALSE(a == close_to(b, r)) fails one on purpose.)
    if (rel > 0 && floor > 2 * rel * s.largest)
      verdict = "FAIL: the floor dominates at every value met: real relative tolerance " +
                std::to_string(floor / s.largest) + ", stated " + std::to_string(rel);
    else if (rel == 0 && s.smallest_expected > 0 && floor >= s.largest)
      verdict = "FAIL: the absolute tolerance exceeds every value met: it admits zero";
    std::printf("%-34s %-22s %-10ld %-12.3g %-12.3g %.10g vs %.10g%s%s\n", where, stated, s.evaluations,
                rel > 0 ? s.worst_rel : s.worst_diff, s.largest, s.worst_a, s.worst_e, verdict.empty() ? "" : "  ",
                verdict.c_str());
    if (!verdict.empty()) ++problems;
  }
  std::printf("%zu checks audited (observed: largest relative difference for rel checks, absolute for abs checks)\n",
              sites.size());
  if (problems > 0) {
    std::printf("close audit: %d problem(s)\n", problems);
    return 1;
  }
  std::printf("close audit: every stated tolerance is the one checked\n");
  return 0;
}
