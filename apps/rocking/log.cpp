// spdlog behind log.hpp: a colour logger on stderr named "rocking", each
// message as "LEVEL: text" (the level coloured on a terminal).
#include "log.hpp"
#include <spdlog/spdlog.h>
#include <spdlog/sinks/stdout_color_sinks.h>

namespace rocking::app::log {

namespace {
spdlog::level::level_enum level_of(Level l) {
  switch (l) {
    case Level::debug: return spdlog::level::debug;
    case Level::info: return spdlog::level::info;
    case Level::warn: return spdlog::level::warn;
    case Level::error: return spdlog::level::err;
  }
  return spdlog::level::info;
}
}  // namespace

void start(Level shown) {
  spdlog::set_default_logger(spdlog::stderr_color_mt("rocking"));
  spdlog::set_pattern("%^%l%$: %v");
  show(shown);
}

void show(Level shown) { spdlog::set_level(level_of(shown)); }

bool shows(Level level) { return spdlog::default_logger_raw()->should_log(level_of(level)); }

void write(Level level, const std::string& message) { spdlog::log(level_of(level), "{}", message); }

}  // namespace rocking::app::log
