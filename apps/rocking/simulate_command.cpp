// `rocking simulate`: one run of a scene under a ground motion (MODEL.md 2-7).
#include "commands.hpp"
#include "run_output.hpp"
#include "stop_signals.hpp"
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <csignal>
#include <iostream>
#include <memory>

namespace rocking::app {

namespace {

// About 1.5 GB of history.csv: more is a mistake, not a study.
constexpr double max_history_rows = 1e7;

struct SimulateOptions {
  SceneOptions scene;
  MotionOptions motion;
  SolverOptions solver;
  std::string out = "out/simulate";
  double output_interval = 0.01;
  bool json = false;
};

void print_text(const nlohmann::json& s) {
  const auto& p = s["peaks"];
  auto num = [](const nlohmann::json& v) { return v.is_null() ? std::string("-") : fmt::format("{:.4g}", v.get<double>()); };
  auto count = [](long n, const char* one) { return fmt::format("{} {}{}", n, one, n == 1 ? "" : "s"); };
  const ScaleFactors scale{s["scale_factors"]["scene"].get<double>(), s["scale_factors"]["option"].get<double>()};
  fmt::print("{} under {} ({})\n", s["scene"].get<std::string>(), s["motion"].get<std::string>(), scale.describe());
  fmt::print("  outcome       {} at t = {:.3f} s\n", s["outcome"].get<std::string>(), s["t_end"].get<double>());
  fmt::print("  top total     {:.1f} mm (delta_t {})\n", s["top_total_mm"].get<double>(), num(p["delta_t"]));
  fmt::print("  top elastic   delta_e {}\n", num(p["delta_e"]));
  fmt::print("  rocking angle {} rad = {} alpha_cg; at the end {:.3g} rad\n", num(p["theta"]), num(p["theta_over_alpha"]),
             s["final_theta"].get<double>());
  if (p["damper_d"].is_null()) fmt::print("  damper        -\n");
  else fmt::print("  damper        d {} m, F {} N\n", num(p["damper_d"]), num(p["damper_F"]));
  for (const auto& d : s["devices"]) {
    const std::string broke =
        d["fracture_s"].is_null() ? "" : fmt::format(", broke at t = {:.4f} s", d["fracture_s"].get<double>());
    const std::string work = d["work_J"].is_null() ? "" : fmt::format(", work {:.4g} J", d["work_J"].get<double>());
    fmt::print("  device        {}: e {:.4g} m, F {:.4g} N{}{}\n", d["name"].get<std::string>(),
               d["peak_elongation_m"].get<double>(), d["peak_force_N"].get<double>(), work, broke);
  }
  fmt::print("  base          V/V_ref {}, M/M_ref {}\n", num(p["base_shear"]), num(p["base_moment"]));
  fmt::print("  mid-height    V/V_ref {}, M/M_ref {}\n", num(p["mid_shear"]), num(p["mid_moment"]));
  fmt::print("  contacts      {}, {}\n", count(s["counts"]["uplifts"].get<long>(), "uplift"),
             count(s["counts"]["impacts"].get<long>(), "impact"));
  fmt::print("  cost          {} ({} rhs, {} steps, {:.3g} s)\n", s["integrator"].get<std::string>(),
             s["stats"]["rhs"].get<long>(), s["stats"]["steps"].get<long>(), s["wall_s"].get<double>());
}

int run(const SimulateOptions& o) {
  const Scene scene = load_scene(o.scene);
  const GroundMotion motion = load_motion(scene, o.motion);
  RunOptions ro = run_options(scene, o.solver, o.motion.record.empty());
  if (!(o.output_interval > 0) || !std::isfinite(o.output_interval))
    throw InputError(fmt::format("--every {}: must be positive", o.output_interval));
  const double duration = ro.duration > 0 ? ro.duration : motion.duration();
  if (duration / o.output_interval > max_history_rows)
    throw InputError(fmt::format("--every {:g}: {:.3g} rows of history for {:g} s (at most {:g}); choose a larger "
                                 "interval",
                                 o.output_interval, duration / o.output_interval, duration, max_history_rows));
  ro.output_interval = o.output_interval;
  const ContactModel model = make_contact_model(scene, true);
  catch_stop_signals();
  ro.stop = [] { return stop_signal() != 0; };
  const std::filesystem::path dir(o.out);
  make_output_dir(dir);
  HistoryCsv history(dir / "history.csv", motion, model.devices);
  const ScaleFactors scale = motion_scale(scene, o.motion);
  spdlog::info("simulating '{}' under {} ({}) with {}", scene.name, motion.name(), scale.describe(), o.solver.integrator);
  const RunResult result = simulate(model, motion, ro, &history);
  if (result.outcome == Outcome::failed) {  // the history may be what failed: keep what it holds, say why
    try {
      history.close();
    } catch (const RunError&) {
    }
  } else {
    history.close();
  }
  const RunLabel label{scene.name,    scene.source,       describe_motion(motion), o.motion.record,
                       scale.total(), scale.scene,         scale.option,                   ro.tolerances.rtol,
                       ro.tolerances.atol};
  nlohmann::json summary = nlohmann::json::parse(summary_json(label, result));
  if (stop_signal() != 0) {
    summary["interrupted"] = true;
    summary["outcome"] = "interrupted";
  }
  write_text(dir / "summary.json", summary.dump(2) + "\n");
  if (o.json) std::cout << summary.dump(2) << '\n';
  else print_text(summary);
  spdlog::info("wrote {} and {}", (dir / "history.csv").string(), (dir / "summary.json").string());
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
  cmd->add_option("--every", o->output_interval, "History interval [s] (default 0.01)")->type_name("S");
  cmd->add_flag("--json", o->json, "Print the summary as JSON on stdout");
  cmd->footer(
      "Examples:\n"
      "  rocking simulate                       the chimney under its default pulse\n"
      "  rocking simulate --record ../shared/data/records/elcentro_1940_ns.at2\n"
      "  rocking simulate --set damper.enabled=false --scale 3 --record FILE\n"
      "  rocking simulate --set contact.rocking=false   (the same chimney on a fixed base)\n"
      "  rocking simulate data/scenes/rigid_block.toml --json");
  return [o]() { return run(*o); };
}

}  // namespace rocking::app
