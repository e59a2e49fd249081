// Where tests find the shared ground-motion records: $ROCKING_RECORDS, else
// ../shared/data/records beside the checkout. Missing records fail the test
// under CI=true and skip it loudly otherwise.
#pragma once
#include <doctest/doctest.h>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

inline std::optional<std::string> records_dir() {
  const char* env = std::getenv("ROCKING_RECORDS");
  const std::filesystem::path dir = env ? std::filesystem::path(env)
                                        : std::filesystem::path(ROCKING_SOURCE_DIR) / ".." / "shared" / "data" / "records";
  if (std::filesystem::is_directory(dir)) return dir.lexically_normal().string();
  const char* ci = std::getenv("CI");
  const std::string msg = "ground-motion records not found at " + dir.string() + " (set ROCKING_RECORDS)";
  if (ci && std::string(ci) == "true") FAIL(msg);
  WARN_MESSAGE(false, "SKIPPED: " << msg);
  return std::nullopt;
}
