#include "commands.hpp"

namespace rocking::app {

void add_scene_options(CLI::App& cmd, SceneOptions& opts) {
  cmd.add_option("scene", opts.path,
                 "Scene file (TOML), e.g. data/scenes/christchurch_chimney.toml.\n"
                 "Without it: the Christchurch chimney built into the program.");
  cmd.add_option("--set", opts.overrides,
                 "Override a scene value, TABLE.KEY=VALUE (repeatable), e.g.\n"
                 "--set structure.EI_scale=0.5 --set damper.enabled=false")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
}

}  // namespace rocking::app
