// A CSV file the program wrote, read by column name (never by position): the
// header row names the columns; fields are split at commas (the program
// quotes no field but a last free-text one, which tests do not read).
#pragma once
#include <doctest/doctest.h>
#include <cstddef>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  // The column's index; fails the test when the header lacks it.
  std::size_t column(std::string_view name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    FAIL("no column '" << std::string(name) << "' in the CSV header");
    return 0;
  }
  bool has(std::string_view name) const {
    for (const std::string& h : header)
      if (h == name) return true;
    return false;
  }
  const std::string& at(std::size_t row, std::string_view name) const {
    const std::size_t k = column(name);
    REQUIRE(k < rows.at(row).size());
    return rows[row][k];
  }
};

inline std::vector<std::string> csv_split(const std::string& line) {
  std::vector<std::string> f;
  std::istringstream cells(line);
  for (std::string c; std::getline(cells, c, ',');) f.push_back(c);
  if (!line.empty() && line.back() == ',') f.emplace_back();
  return f;
}

// The header and the non-empty rows of a CSV text.
inline CsvTable csv_table(const std::string& text) {
  CsvTable t;
  std::istringstream in(text);
  std::string line;
  if (std::getline(in, line)) t.header = csv_split(line);
  while (std::getline(in, line))
    if (!line.empty()) t.rows.push_back(csv_split(line));
  return t;
}
