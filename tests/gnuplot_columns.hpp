// Whether a gnuplot script addresses a data column by number: a `$k` (or
// column(k)) anywhere, or a `using` clause one of whose ':'-separated parts
// (outside parentheses) is a bare column number ("using 1:2"). The scripts
// the program writes read their data by header name (column('delta_t')).
#pragma once
#include <cctype>
#include <cstddef>
#include <string>

// The first place the script addresses a column by number (its line), or "".
inline std::string numbered_column(const std::string& script) {
  auto line_of = [&](std::size_t at) {
    const std::size_t from = script.rfind('\n', at) == std::string::npos ? 0 : script.rfind('\n', at) + 1;
    return script.substr(from, script.find('\n', at) - from);
  };
  for (std::size_t i = 0; i + 1 < script.size(); ++i)
    if (script[i] == '$' && std::isdigit(static_cast<unsigned char>(script[i + 1])) != 0) return line_of(i);
  for (std::size_t i = script.find("column("); i != std::string::npos; i = script.find("column(", i + 1))
    if (std::isdigit(static_cast<unsigned char>(script[i + 7])) != 0) return line_of(i);
  for (std::size_t i = script.find("using "); i != std::string::npos; i = script.find("using ", i + 1)) {
    // The clause: up to the first space outside parentheses and quotes.
    std::size_t end = i + 6;
    int depth = 0;
    char quote = 0;
    for (; end < script.size(); ++end) {
      const char c = script[end];
      if (quote != 0) {
        if (c == quote) quote = 0;
        continue;
      }
      if (c == '\'' || c == '"') quote = c;
      else if (c == '(') ++depth;
      else if (c == ')') --depth;
      else if ((c == ' ' || c == '\n') && depth == 0) break;
    }
    const std::string clause = script.substr(i + 6, end - i - 6);
    std::size_t from = 0;
    depth = 0;
    for (std::size_t k = 0; k <= clause.size(); ++k) {
      if (k < clause.size() && clause[k] == '(') ++depth;
      if (k < clause.size() && clause[k] == ')') --depth;
      if (k == clause.size() || (clause[k] == ':' && depth == 0)) {
        const std::string part = clause.substr(from, k - from);
        bool digits = !part.empty();
        for (char c : part) digits = digits && std::isdigit(static_cast<unsigned char>(c)) != 0;
        if (digits) return line_of(i);
        from = k + 1;
      }
    }
  }
  return "";
}
