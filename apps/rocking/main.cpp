// `rocking`: the command-line program. Parses arguments, runs one subcommand,
// and maps failures to exit codes: 2 for bad input (a one-line message naming
// what and where), 3 for a run that cannot finish.
#include <CLI/CLI.hpp>
#include "log.hpp"
#include <fmt/format.h>
#include <algorithm>
#include <array>
#include <cstring>
#include <exception>
#include <string>
#include <vector>
#include "commands.hpp"
#include "stop_signals.hpp"
import rocking.errors;

namespace {

// Levenshtein distance, for "did you mean" on a mistyped subcommand.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The first word that is not an option (the program's own options, -v, -q,
// --help and --version, take no value): the subcommand asked for, or empty.
std::string first_word(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') return argv[i];
  return {};
}

// The first word that is not an option must be a subcommand: an error naming
// it, with the nearest subcommand when one is close, or empty.
std::string unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  if (const std::string word = first_word(argc, argv); !word.empty()) {
    std::string best;
    std::size_t best_distance = 3;  // suggest only a near miss
    for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
      if (sub->get_name() == word) return {};
      const std::size_t d = edit_distance(word, sub->get_name());
      if (d < best_distance || (sub->get_name().starts_with(word) && best.empty())) {
        best_distance = std::min(d, best_distance);
        best = sub->get_name();
      }
    }
    return best.empty() ? fmt::format("unknown subcommand '{}' (`rocking --help` lists them)", word)
                        : fmt::format("unknown subcommand '{}'; did you mean '{}'?", word, best);
  }
  return {};
}

// An option given an empty value (an unset variable in a script: --record
// "$FILE") must not run what leaving the option out runs: an error naming the
// option and what it takes, or empty.
std::string empty_value(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands())
    for (const CLI::Option* opt : sub->get_options())
      if (opt->count() > 0 && opt->get_type_size_max() > 0)
        for (const std::string& value : opt->results())
          if (value.find_first_not_of(" \t") == std::string::npos) {
            const std::string name = opt->get_lnames().empty() ? opt->get_name() : "--" + opt->get_lnames().front();
            const std::string takes = opt->get_type_name().empty() ? "a value" : opt->get_type_name();
            return fmt::format("{} '{}': an empty value; it takes {} (leave the option out for its default)", name,
                               value, takes);
          }
  return {};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "rocking: earthquake response of flexible structures that rock on their base,\n"
      "with hysteretic dampers at the rocking interface. The default scene is the\n"
      "Christchurch chimney (data/scenes/christchurch_chimney.toml, built in).\n",
      "rocking"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "rocking " ROCKING_VERSION);
  // -v and -q belong to the program, and are taken before or after the subcommand.
  app.fallthrough();
  app.footer("Run `rocking SUBCOMMAND --help` for what each one does and its options.");
  bool verbose = false, quiet = false;
  app.add_flag("-v,--verbose", verbose, "Log what is being done (debug level)");
  app.add_flag("-q,--quiet", quiet, "Log only warnings and errors");

  // Each subcommand's options are built only when it is the one asked for
  // (the first word that is not an option): building them all costs more
  // than the rest of the program's start-up. `rocking --help`, and a word that
  // names no subcommand, build them all, to list them or to suggest one.
  struct Subcommand {
    const char* name;
    rocking::app::Command (*add)(CLI::App&);
    rocking::app::Command run;
  };
  std::array<Subcommand, 11> subcommands{{{"modal", rocking::app::add_modal_command, {}},
                                          {"simulate", rocking::app::add_simulate_command, {}},
                                          {"plot", rocking::app::add_plot_command, {}},
                                          {"ida", rocking::app::add_ida_command, {}},
                                          {"sweep", rocking::app::add_sweep_command, {}},
                                          {"tradeoff", rocking::app::add_tradeoff_command, {}},
                                          {"spectrum", rocking::app::add_spectrum_command, {}},
                                          {"animate", rocking::app::add_animate_command, {}},
                                          {"record", rocking::app::add_record_command, {}},
                                          {"fit", rocking::app::add_fit_command, {}},
                                          {"serve", rocking::app::add_serve_command, {}}}};
  const std::string asked = first_word(argc, argv);
  const bool known = std::any_of(subcommands.begin(), subcommands.end(),
                                 [&](const Subcommand& c) { return asked == c.name; });
  const bool help = std::any_of(argv + 1, argv + argc, [](const char* a) {
    return std::strcmp(a, "--help") == 0 || std::strcmp(a, "-h") == 0;
  });
  const bool all = asked.empty() ? help : !known;
  for (Subcommand& c : subcommands)
    if (all || asked == c.name) c.run = c.add(app);

  namespace log = rocking::app::log;
  log::start(log::Level::info);
  if (const std::string unknown = unknown_subcommand(app, argc, argv); !unknown.empty()) {
    fmt::print(stderr, "rocking: error: {}\n", unknown);
    return rocking::exit_input_error;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr && app.get_subcommands().empty()) {
      // No subcommand named: say which there are.
      std::string names;
      for (const Subcommand& c : subcommands) names += fmt::format("{}{}", names.empty() ? "" : ", ", c.name);
      fmt::print(stderr, "rocking: error: name a subcommand: {} (`rocking --help` says what each does)\n", names);
      return rocking::exit_input_error;
    }
    fmt::print(stderr, "rocking: error: {}\n", e.what());
    return rocking::exit_input_error;
  }
  if (const std::string empty = empty_value(app); !empty.empty()) {
    fmt::print(stderr, "rocking: error: {}\n", empty);
    return rocking::exit_input_error;
  }
  log::show(verbose ? log::Level::debug : quiet ? log::Level::warn : log::Level::info);

  try {
    for (const Subcommand& c : subcommands)
      if (c.run && app.got_subcommand(c.name)) return c.run();
  } catch (const rocking::InputError& e) {
    fmt::print(stderr, "rocking: error: {}\n", e.what());
    return rocking::exit_input_error;
  } catch (const rocking::RunError& e) {
    // A run or a drawing that Ctrl-C or SIGTERM cut short: the files each
    // command keeps are whole; the code is the signal's (130, 143).
    if (const int signal = rocking::app::stop_signal(); signal != 0) {
      fmt::print(stderr, "rocking: stopped by {}: {}\n", rocking::app::stop_signal_name(signal), e.what());
      return rocking::app::stop_exit_code(signal);
    }
    fmt::print(stderr, "rocking: run stopped: {}\n", e.what());
    return rocking::exit_run_error;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rocking: internal error: {}\n", e.what());
    return 1;
  }
  return 0;
}
