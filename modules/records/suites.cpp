// Record suites: a study's --record arguments may name folders and list
// files as well as records; this turns them into record files.
module;
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <fmt/format.h>
module rocking.records;
import rocking.errors;

namespace rocking {

namespace fs = std::filesystem;

namespace {

// The entries of a list file (lines that are not blank or # comments, with
// their line numbers), or nothing when the file is too large to be a list.
std::vector<std::pair<int, std::string>> list_entries(const std::string& path) {
  std::error_code ec;
  if (fs::file_size(path, ec) > (1u << 20) || ec) return {};
  std::ifstream in(path);
  std::vector<std::pair<int, std::string>> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t\r");
    out.emplace_back(n, line.substr(first, last - first + 1));
  }
  return out;
}

std::string resolve(const std::string& entry, const std::string& base) {
  const fs::path p(entry);
  return p.is_absolute() ? entry : (fs::path(base) / p).lexically_normal().string();
}

}  // namespace

std::vector<std::string> read_record_list(const std::string& list, const std::string& base) {
  std::vector<std::string> out;
  std::error_code ec;
  if (!fs::is_regular_file(list, ec)) throw InputError(fmt::format("{}: record list not found", list));
  for (const auto& [line, entry] : list_entries(list)) {
    const std::string path = resolve(entry, base);
    if (!fs::is_regular_file(path, ec))
      throw InputError(fmt::format("{}:{}: {}: record file not found", list, line, path));
    out.push_back(path);
  }
  if (out.empty()) throw InputError(fmt::format("{}: the list names no record file", list));
  return out;
}

std::vector<std::string> record_paths(const std::string& argument, std::vector<std::string>* skipped) {
  std::error_code ec;
  if (fs::is_directory(argument, ec)) {
    std::vector<std::string> files;
    for (const fs::directory_entry& e : fs::directory_iterator(argument, ec))
      if (e.is_regular_file(ec) && !e.path().filename().string().starts_with(".")) files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    std::vector<std::string> out;
    for (const std::string& f : files) {
      if (is_record_file(f)) out.push_back(f);
      else if (skipped) skipped->push_back(f);
    }
    if (out.empty()) throw InputError(fmt::format("{}: a folder with no record file a reader recognises", argument));
    return out;
  }
  if (!fs::is_regular_file(argument, ec) || is_record_file(argument)) return {argument};
  const auto entries = list_entries(argument);
  const std::string base = fs::path(argument).parent_path().string();
  // A list when it names some file: the entries it names that are missing
  // are then reported at their line (read_record_list).
  const bool list = std::any_of(entries.begin(), entries.end(), [&](const auto& e) {
    return fs::is_regular_file(resolve(e.second, base), ec);
  });
  return list ? read_record_list(argument, base) : std::vector<std::string>{argument};
}

}  // namespace rocking
