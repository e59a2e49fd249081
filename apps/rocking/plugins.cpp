#include "plugins.hpp"
#include <dlfcn.h>
#include <fmt/format.h>
#include <filesystem>
import rocking.errors;

namespace rocking::app {

void* plugin_symbol(const std::string& object, const char* symbol, const std::string& why) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::string path = (self.parent_path() / object).string();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (handle == nullptr) throw RunError(fmt::format("{} cannot be loaded: {}", why, dlerror()));
  void* entry = dlsym(handle, symbol);
  if (entry == nullptr) throw RunError(fmt::format("{}: no {}: {}", path, symbol, dlerror()));
  return entry;
}

}  // namespace rocking::app
