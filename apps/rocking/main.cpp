// `rocking`: the command-line program. Parses arguments, runs one subcommand,
// and maps failures to exit codes: 2 for bad input (a one-line message naming
// what and where), 3 for a run that cannot finish.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <fmt/format.h>
#include <exception>
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "rocking: earthquake response of flexible structures that rock on their base,\n"
      "with hysteretic dampers at the rocking interface. The default scene is the\n"
      "Christchurch chimney (data/scenes/christchurch_chimney.toml, built in).\n",
      "rocking"};
  app.require_subcommand(1);
  app.footer("Run `rocking SUBCOMMAND --help` for what each one does and its options.");
  bool verbose = false, quiet = false;
  app.add_flag("-v,--verbose", verbose, "Log what is being done (debug level)");
  app.add_flag("-q,--quiet", quiet, "Log only warnings and errors");

  rocking::app::Command modal = rocking::app::add_modal_command(app);
  rocking::app::Command simulate = rocking::app::add_simulate_command(app);
  rocking::app::Command plot = rocking::app::add_plot_command(app);
  rocking::app::Command ida = rocking::app::add_ida_command(app);
  rocking::app::Command sweep = rocking::app::add_sweep_command(app);
  rocking::app::Command tradeoff = rocking::app::add_tradeoff_command(app);
  rocking::app::Command spectrum = rocking::app::add_spectrum_command(app);
  rocking::app::Command animate = rocking::app::add_animate_command(app);

  auto logger = spdlog::stderr_color_mt("rocking");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("%^%l%$: %v");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    fmt::print(stderr, "rocking: error: {}\n", e.what());
    return rocking::exit_input_error;
  }
  spdlog::set_level(verbose ? spdlog::level::debug : quiet ? spdlog::level::warn : spdlog::level::info);

  try {
    if (app.got_subcommand("modal")) return modal();
    if (app.got_subcommand("simulate")) return simulate();
    if (app.got_subcommand("plot")) return plot();
    if (app.got_subcommand("ida")) return ida();
    if (app.got_subcommand("sweep")) return sweep();
    if (app.got_subcommand("tradeoff")) return tradeoff();
    if (app.got_subcommand("spectrum")) return spectrum();
    if (app.got_subcommand("animate")) return animate();
  } catch (const rocking::InputError& e) {
    fmt::print(stderr, "rocking: error: {}\n", e.what());
    return rocking::exit_input_error;
  } catch (const rocking::RunError& e) {
    fmt::print(stderr, "rocking: run stopped: {}\n", e.what());
    return rocking::exit_run_error;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rocking: internal error: {}\n", e.what());
    return 1;
  }
  return 0;
}
