// The subcommands of the `rocking` program. Each registers itself on the app
// and returns the function to run if it is chosen; main() dispatches and turns
// errors into exit codes (rocking.errors).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace rocking::app {

using Command = std::function<int()>;

// SCENE (positional, optional) and --set KEY=VALUE..., shared by every command
// that works on a scene.
struct SceneOptions {
  std::string path;  // empty: the embedded Christchurch chimney
  std::vector<std::string> overrides;
};
void add_scene_options(CLI::App& cmd, SceneOptions& opts);

Command add_modal_command(CLI::App& app);

}  // namespace rocking::app
