// The README's table of the paper's checks, held by a golden file
// (tests/golden/paper_checks.tsv): each row names a case and the arguments of
// `rocking simulate` that run it (RECORDS/ stands for the records folder), and
// every number the run reports (all peaks, the top displacement, the counts
// and the outcome) at the default tolerance. Every `make test` runs each case
// through the program and compares: numbers to 1e-6 relative, counts and
// outcome exactly. The README's table must be the one these numbers make.
// Regenerate both, after a change that moves the numbers on purpose, with
//   make golden      (ROCKING_WRITE_GOLDEN=1 build/bin/golden_test)
// which rewrites the file and prints the table to paste into the README.
#include <doctest/doctest.h>
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include "temp_path.hpp"
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>
#include "records.hpp"
#include "run_program.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path golden_file = fs::path(ROCKING_SOURCE_DIR) / "tests" / "golden" / "paper_checks.tsv";
const std::vector<std::string> peak_keys = {"delta_t", "delta_e", "theta", "theta_over_alpha", "damper_d",
                                            "damper_F", "base_shear", "base_moment", "mid_shear", "mid_moment"};

struct Case {
  std::string name, args;
  std::vector<std::string> values;  // top_total_mm, the peaks (empty: null), uplifts, impacts, outcome
};

std::vector<std::string> split(const std::string& line, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, sep);) out.push_back(f);
  if (!line.empty() && line.back() == sep) out.emplace_back();
  return out;
}

std::string header() {
  std::string h = "case\targuments\ttop_total_mm";
  for (const std::string& k : peak_keys) h += "\t" + k;
  return h + "\tuplifts\timpacts\toutcome";
}

std::vector<Case> read_golden() {
  std::ifstream in(golden_file);
  REQUIRE_MESSAGE(in, golden_file.string() << ": not found");
  std::vector<Case> cases;
  std::string line;
  std::getline(in, line);
  REQUIRE(line == header());
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::vector<std::string> f = split(line, '\t');
    REQUIRE_MESSAGE(f.size() == 2 + 1 + peak_keys.size() + 3, golden_file.string() << ":" << n);
    cases.push_back({f[0], f[1], std::vector<std::string>(f.begin() + 2, f.end())});
  }
  return cases;
}

// Runs a case through the program; its values in the golden file's order.
std::vector<std::string> run_case(const Case& c, const std::string& records, const fs::path& out) {
  std::string args = c.args;
  for (std::size_t at; (at = args.find("RECORDS/")) != std::string::npos;) args.replace(at, 8, records + "/");
  const Result r = run("simulate " + args + " --json --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, c.name << ": " << r.err);
  const auto j = nlohmann::json::parse(r.out);
  std::vector<std::string> v = {fmt::format("{:.17g}", j["top_total_mm"].get<double>())};
  // A peak the scene does not report (no such quantity: rocking.quantities' Needs) is empty.
  const nlohmann::json& peaks = j.at("peaks");
  for (const std::string& k : peak_keys)
    v.push_back(!peaks.contains(k) ? "" : fmt::format("{:.17g}", peaks.at(k).get<double>()));
  v.push_back(std::to_string(j["counts"]["uplifts"].get<long>()));
  v.push_back(std::to_string(j["counts"]["impacts"].get<long>()));
  v.push_back(j["outcome"].get<std::string>());
  return v;
}

// The README's table rows, from a case's values.
std::string markdown_row(const Case& c) {
  auto num = [&](std::size_t i) { return std::stod(c.values[i]); };
  const std::size_t top = 0, theta_alpha = 4, V = 7, M = 8, up = 11, imp = 12;
  // A fixed base has no rocking angle: "-".
  const std::string theta = c.values[theta_alpha].empty() ? std::string("-")
                            : num(theta_alpha) == 0       ? std::string("0")
                                                          : fmt::format("{:.2g}", num(theta_alpha));
  return fmt::format("| {} | {:.1f} mm | {} | {:.2f}, {:.2f} | {}, {} |", c.name, num(top), theta, num(V), num(M),
                     c.values[up], c.values[imp]);
}

std::string markdown_table(const std::vector<Case>& cases) {
  std::string out = "| case | peak top total | theta / alpha_cg | base V/V_ref, M/M_ref | uplifts, impacts |\n"
                    "|---|---|---|---|---|\n";
  for (const Case& c : cases) out += markdown_row(c) + "\n";
  return out;
}

}  // namespace

TEST_CASE("the paper's checks: every number of every case matches the golden file (1e-6 relative)") {
  const auto records = records_dir();
  if (!records) return;
  std::vector<Case> cases = read_golden();
  REQUIRE(cases.size() >= 7);
  const fs::path out = scratch_dir("golden_runs");
  const char* write = std::getenv("ROCKING_WRITE_GOLDEN");
  const bool rewrite = write != nullptr && std::string(write) == "1";
  for (Case& c : cases) {
    const std::vector<std::string> now = run_case(c, *records, out);
    if (rewrite) {
      c.values = now;
      continue;
    }
    for (std::size_t i = 0; i < now.size(); ++i) {
      CAPTURE(c.name);
      CAPTURE(i);
      const std::string& was = c.values[i];
      if (i + 3 >= now.size() || was.empty() || now[i].empty()) {  // counts, outcome, absent quantities: exactly
        CHECK(now[i] == was);
      } else {
        const double a = std::stod(now[i]), b = std::stod(was);
        CHECK(std::abs(a - b) <= 1e-6 * std::max(std::abs(b), 1e-9));
      }
    }
  }
  if (rewrite) {
    std::ofstream file(golden_file);
    file << header() << '\n';
    for (const Case& c : cases) {
      file << c.name << '\t' << c.args;
      for (const std::string& v : c.values) file << '\t' << v;
      file << '\n';
    }
    MESSAGE("rewrote " << golden_file.string() << "; the README's table:\n" << markdown_table(cases));
  }
}

TEST_CASE("the README's table of the paper's checks is the one the golden file makes") {
  std::ifstream in(fs::path(ROCKING_SOURCE_DIR) / "README.md");
  std::stringstream readme;
  readme << in.rdbuf();
  CHECK_MESSAGE(readme.str().find(markdown_table(read_golden())) != std::string::npos,
                "README.md lacks the table; `make golden` prints it:\n"
                    << markdown_table(read_golden()));
}

namespace {

const fs::path suite_golden = fs::path(ROCKING_SOURCE_DIR) / "tests" / "golden" / "suite_fragility.csv";
// The README's suite study (its command, less the figures).
const std::string suite_study =
    "-q ida --suite horizontal --im pga --levels 0.2:6:0.2 --variants damper,no-damper --limit theta_over_alpha=0.5 "
    "--no-plot";

std::vector<std::vector<std::string>> csv_lines(const std::string& text) {
  std::vector<std::vector<std::string>> out;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(split(line, ','));
  return out;
}

// The README's sentence for a variant's overturning fit (a fragility.csv row
// under its header).
std::string readme_fit(const std::vector<std::string>& header, const std::vector<std::string>& row) {
  auto at = [&](const char* name) {
    return std::stod(row.at(static_cast<std::size_t>(std::ranges::find(header, name) - header.begin())));
  };
  return fmt::format("median PGA {:.2f} g (90 % interval {:.2f}-{:.2f}), beta {:.2f} ({:.2f}-{:.2f})", at("median"),
                     at("median_low"), at("median_high"), at("beta"), at("beta_low"), at("beta_high"));
}

}  // namespace

TEST_CASE("the README's suite study: its fragility.csv matches the golden file, and the README quotes it") {
  const auto records = records_dir();
  if (!records) return;
  const fs::path out = scratch_dir("golden_suite");
  const Result r = run(suite_study + " --out " + out.string());
  REQUIRE_MESSAGE(r.code == 0, r.err);
  const std::string now = file_text(out / "fragility.csv");
  const char* write = std::getenv("ROCKING_WRITE_GOLDEN");
  if (write != nullptr && std::string(write) == "1") {
    std::ofstream(suite_golden) << now;
    MESSAGE("rewrote " << suite_golden.string());
  }
  // Counts, methods and notes exactly; fitted numbers and their bootstrap
  // intervals to 1e-4 relative (a fit's last digits follow the optimiser's
  // path, and an interval's end is one resample's fit), the columns found by
  // the header's names.
  const auto was = csv_lines(file_text(suite_golden)), is = csv_lines(now);
  REQUIRE(was.size() == is.size());
  REQUIRE(!was.empty());
  const std::vector<std::string> numeric{"median",    "beta",        "log_median_se", "beta_se",        "median_low",
                                         "median_high", "beta_low",  "beta_high",     "beta_total",     "beta_total_low",
                                         "beta_total_high"};
  const std::vector<std::string>& header = was[0];
  for (std::size_t i = 0; i < was.size(); ++i) {
    REQUIRE(was[i].size() == is[i].size());
    for (std::size_t k = 0; k < was[i].size(); ++k) {
      CAPTURE(i);
      CAPTURE(header.at(k));
      if (i > 0 && std::ranges::find(numeric, header.at(k)) != numeric.end() && !was[i][k].empty())
        CHECK(std::stod(is[i][k]) == doctest::Approx(std::stod(was[i][k])).epsilon(1e-4));
      else
        CHECK(is[i][k] == was[i][k]);
    }
  }
  // The README's text with its line breaks as spaces (sentences wrap).
  std::string readme;
  for (char c : file_text(fs::path(ROCKING_SOURCE_DIR) / "README.md"))
    if (!(c == ' ' || c == '\n') || readme.empty() || readme.back() != ' ') readme += c == '\n' ? ' ' : c;
  for (const auto& row : was)
    if (row.size() > 3 && row[1] == "overturning" && row[3] != "stripes-mle")
      CHECK_MESSAGE(readme.find(row[0] + ": " + readme_fit(header, row)) != std::string::npos,
                    "README.md lacks '" << row[0] << ": " << readme_fit(header, row) << "'");
}
