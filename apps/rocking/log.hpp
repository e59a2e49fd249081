// The program's messages on stderr ("info: ...", "warning: ..."), shown from
// the level --verbose and --quiet choose. spdlog writes them; it is compiled
// in one file (log.cpp), so that the command files take only this header.
#pragma once
#include <fmt/format.h>
#include <string>
#include <utility>

namespace rocking::app::log {

enum class Level { debug, info, warn, error };

// The logger on stderr, showing messages of `shown` and above (main).
void start(Level shown);
void show(Level shown);
// Whether a message of this level is shown.
bool shows(Level level);
void write(Level level, const std::string& message);

template <class... Args>
void debug(fmt::format_string<Args...> f, Args&&... args) {
  if (shows(Level::debug)) write(Level::debug, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void info(fmt::format_string<Args...> f, Args&&... args) {
  if (shows(Level::info)) write(Level::info, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void warn(fmt::format_string<Args...> f, Args&&... args) {
  if (shows(Level::warn)) write(Level::warn, fmt::format(f, std::forward<Args>(args)...));
}
template <class... Args>
void error(fmt::format_string<Args...> f, Args&&... args) {
  if (shows(Level::error)) write(Level::error, fmt::format(f, std::forward<Args>(args)...));
}

}  // namespace rocking::app::log
