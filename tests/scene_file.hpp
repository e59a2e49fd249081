// A scene given as TOML text, written to a file of this test process and
// read back as the program reads a scene file (rocking.scene's load_scene,
// with its checks and the --set overrides).
#pragma once
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include "temp_path.hpp"
import rocking.scene;

inline rocking::Scene scene_from(const std::string& name, const std::string& toml,
                                 const std::vector<std::string>& overrides = {}) {
  const std::filesystem::path path = temp_path(name + ".toml");
  std::ofstream(path) << toml;
  return rocking::load_scene(path.string(), overrides);
}
