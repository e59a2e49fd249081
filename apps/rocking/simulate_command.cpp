// `rocking simulate`: one run of a scene under a ground motion (MODEL.md 2-7).
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include "log.hpp"
#include <fmt/format.h>
#include <csignal>
#include <iostream>
#include <memory>
#include <optional>
import rocking.errors;

namespace rocking::app {

namespace {

struct SimulateOptions {
  SceneOptions scene;
  MotionOptions motion;
  SolverOptions solver;
  std::string out = "out/simulate";
  std::optional<double> output_interval;  // none: the scene's [output] interval, or 0.01 s
  bool json = false;
  bool list_quantities = false;
  std::vector<std::string> history;  // chosen columns (empty: the scene's default)
};

// The summary in words: one line per peak the scene reports, named and
// described by the schema (rocking.quantities), then one per device.
void print_text(const nlohmann::json& s) {
  const auto& p = s["peaks"];
  auto count = [](long n, const char* one) { return fmt::format("{} {}{}", n, one, n == 1 ? "" : "s"); };
  const ScaleFactors scale{s["scale_factors"]["scene"].get<double>(), s["scale_factors"]["option"].get<double>()};
  fmt::print("{} under {} ({})\n", s["scene"].get<std::string>(), s["motion"].get<std::string>(), scale.describe());
  if (const auto& v = s["vertical_motion"]; !v.is_null()) fmt::print("  {:<17} {}\n", "vertical motion", v.get<std::string>());
  fmt::print("  {:<17} {} at t = {:.3f} s; {}, {}\n", "outcome", s["outcome"].get<std::string>(),
             s["t_end"].get<double>(), count(s["counts"]["uplifts"].get<long>(), "uplift"),
             count(s["counts"]["impacts"].get<long>(), "impact"));
  for (const char* stated : {"separation", "sliding", "undecided"})  // why the model ended the run there
    if (const auto it = s.find(stated); it != s.end()) fmt::print("  {:<17} {}\n", stated, it->get<std::string>());
  for (Quantity q : peak_quantities) {
    const QuantityInfo& i = info(q);
    const auto v = p.find(std::string(i.name));
    if (v == p.end()) continue;  // the scene does not report it
    std::string words(i.words);
    if (q == Quantity::delta_t) words += fmt::format(": {:.1f} mm at the top", s["top_total_mm"].get<double>());
    if (q == Quantity::theta) words += fmt::format("; at the end {:.3g} rad", s["final_theta"].get<double>());
    fmt::print("  {:<17} {:<11} {:<6} {}\n", i.name, fmt::format("{:.4g}", v->get<double>()), i.unit, words);
  }
  for (const auto& d : s["devices"]) {
    const double at_rest = d["force_at_rest_N"].get<double>();
    const std::string law = fmt::format("{}{}", d["law"].get<std::string>(),
                                        at_rest > 0 ? fmt::format(", prestress {:.4g} N", at_rest) : "");
    const std::string broke =
        d["fracture_s"].is_null() ? "" : fmt::format(", broke at t = {:.4f} s", d["fracture_s"].get<double>());
    const std::string work = d["work_J"].is_null() ? "" : fmt::format(", work {:.4g} J", d["work_J"].get<double>());
    fmt::print("  {:<17} {}: peak e {:.4g} m, F {:.4g} N{}{}\n", d["name"].get<std::string>(), law,
               d["peak_elongation_m"].get<double>(), d["peak_force_N"].get<double>(), work, broke);
  }
  if (const auto j = s.find("joints"); j != s.end())  // a structure with joints: one line each, the base first
    for (const auto& k : *j) {
      const auto at = [&](const char* key) {
        return k[key].is_null() ? std::string("never") : fmt::format("t = {:.4f} s", k[key].get<double>());
      };
      fmt::print("  {:<17} first uplift {}, first impact {}; {}, {}; peak theta {:.4g} rad, |V|/N {}\n",
                 fmt::format("joint {}", k["joint"].get<int>()), at("first_uplift_s"), at("first_impact_s"),
                 count(k["uplifts"].get<long>(), "uplift"), count(k["impacts"].get<long>(), "impact"),
                 k["peak_theta"].get<double>(),
                 k["peak_friction_demand"].is_null() ? std::string("-")
                                                     : fmt::format("{:.3g}", k["peak_friction_demand"].get<double>()));
    }
  if (const auto c = s.find("columns"); c != s.end()) {  // a structure on rocking columns (MODEL.md 16)
    const auto at = [&](const char* key) {
      return (*c)[key].is_null() ? std::string("never") : fmt::format("t = {:.4f} s", (*c)[key].get<double>());
    };
    fmt::print("  {:<17} first uplift {}, first impact {}; smallest top contact force {}\n", "columns",
               at("first_uplift_s"), at("first_impact_s"),
               (*c)["smallest_top_force_N"].is_null()
                   ? std::string("-")
                   : fmt::format("{:.4g} N at {}", (*c)["smallest_top_force_N"].get<double>(), at("smallest_top_force_s")));
  }
  fmt::print("  {:<17} {} ({} rhs, {} steps, {:.3g} s)\n", "cost", s["integrator"].get<std::string>(),
             s["stats"]["rhs"].get<long>(), s["stats"]["steps"].get<long>(), s["wall_s"].get<double>());
}

// Bytes kept for summary.json while the run writes its history: several
// times a summary of sixteen devices.
constexpr std::size_t summary_room = 1 << 16;

int run(const SimulateOptions& o) {
  const Scene scene = load_scene(o.scene);
  if (o.list_quantities) {
    fmt::print("{}", quantity_table_text(make_contact_model(scene, true)));  // as a run tracks it: its energy too
    return 0;
  }
  const PreparedRun prepared = prepare_run({.scene = scene, .motion = o.motion, .solver = o.solver,
                                       .history = {.columns = o.history, .every = o.output_interval}});
  catch_stop_signals();
  RunOptions ro = prepared.options;
  ro.stop = [] { return stop_signal() != 0; };
  const std::filesystem::path dir(o.out);
  make_output_dir(dir);
  // The summary's room first: a history that fills the disk leaves it.
  ReservedFile summary_file(dir / "summary.json", summary_room);
  HistoryCsv history(dir / "history.csv", prepared.model, prepared.columns);
  log::info("simulating '{}' under {}{} ({}) with {}", scene.name, prepared.motion.name(),
               prepared.motion.vertical() ? " and vertical " + prepared.motion.vertical()->name() : std::string(),
               prepared.scale.describe(), o.solver.integrator);
  const RunResult result = simulate(prepared.model, prepared.motion, ro, &history);
  if (result.outcome == Outcome::failed) {  // the history may be what failed: keep what it holds, say why
    try {
      history.close();
    } catch (const RunError&) {
    }
  } else {
    history.close();
  }
  nlohmann::json summary = run_summary(prepared.label, result);
  if (stop_signal() != 0) {
    summary["interrupted"] = true;
    summary["outcome"] = "interrupted";
  }
  summary_file.write(summary.dump(2) + "\n");
  if (o.json) std::cout << summary.dump(2) << '\n';
  else print_text(summary);
  log::info("wrote {} and {}", (dir / "history.csv").string(), (dir / "summary.json").string());
  if (const int signal = stop_signal(); signal != 0) {
    fmt::print(stderr, "rocking: stopped by {} at t = {:.6g} s; {} holds the history up to there, summary.json says "
                       "interrupted\n",
               stop_signal_name(signal), result.t_end, (dir / "history.csv").string());
    return stop_exit_code(signal);
  }
  if (result.outcome == Outcome::failed) throw RunError(result.failure);
  return 0;
}

}  // namespace

Command add_simulate_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Earthquake response of a scene: full contact, uplift, rocking on either\n"
      "pivot, impacts, the dampers' hysteresis. Writes DIR/history.csv (the\n"
      "response every --every seconds and at each phase change) and\n"
      "DIR/summary.json (peaks, counts, outcome, energy balance, cost).\n"
      "Exit codes: 0 done (also when the structure overturns: see outcome),\n"
      "2 bad input, 3 the run could not finish (its files are still written).");
  auto o = std::make_shared<SimulateOptions>();
  add_scene_options(*cmd, o->scene);
  add_motion_options(*cmd, o->motion);
  add_solver_options(*cmd, o->solver);
  cmd->add_option("--out", o->out, "Output folder (default out/simulate)")->type_name("DIR");
  cmd->add_option("--every", o->output_interval, "History interval [s] (default: the scene's [output]\n"
                                                 "interval, else 0.01)")->type_name("S");
  cmd->add_flag("--json", o->json, "Print the summary as JSON on stdout");
  cmd->add_option("--history", o->history,
                  "The history's columns, by name (t always first; comma-separated or\n"
                  "repeated): theta,delta_t,a_N,tendon.force, a node's node4.x_abs,\n"
                  "node2.a_abs, an element's element1.V, element2.M_top, the ground's\n"
                  "x_g (default: the scene's [output] history, else every quantity the\n"
                  "scene reports; --list-quantities names them all)")
      ->delimiter(',')
      ->type_name("Q,...");
  cmd->add_flag("--list-quantities", o->list_quantities,
                "List the quantities this scene reports (the names of history.csv's\n"
                "columns, summary.json's peaks, ida.csv's columns and --limit), with\n"
                "units, and run nothing");
  cmd->footer(
      "Examples:\n"
      "  rocking simulate                       the chimney under its default pulse\n"
      "  rocking simulate --record ../shared/data/records/elcentro_1940_ns.at2\n"
      "  rocking simulate --set damper.enabled=false --scale 3 --record FILE\n"
      "  rocking simulate --set contact.rocking=false   (the same chimney on a fixed base)\n"
      "  rocking simulate data/scenes/rigid_block.toml --json\n"
      "  rocking simulate data/scenes/controlled_rocking_wall.toml --list-quantities\n"
      "  rocking simulate --history theta,delta_t,a_N,damper_left.force\n"
      "  rocking simulate --history node4.x_abs,node4.a_abs,element1.V,element1.M_bottom");
  return [o]() { return run(*o); };
}

}  // namespace rocking::app
