// `rocking modal`: linearised modal analysis of a scene (MODEL.md 8).
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <iostream>
#include "commands.hpp"
import rocking;

namespace rocking::app {

namespace {

nlohmann::json to_json(const ModalSummary& m) {
  auto optional = [](double v) { return v > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"fixed_base_hz", m.fixed_base_hz},
          {"rocking_hz", m.rocking_hz},
          {"rocking_p", optional(m.rocking_p)},
          {"damper_pre_yield_hz", optional(m.damper_pre_yield_hz)},
          {"damper_post_yield_p", optional(m.damper_post_yield_p)},
          {"r_eq10", m.r_eq10},
          {"J_p", m.J_p},
          {"H_cg", m.H_cg},
          {"alpha_cg", m.alpha_cg},
          {"M_ref", m.reference.base_moment},
          {"V_ref", m.reference.base_shear}};
}

std::string hz_list(const std::vector<double>& hz) {
  return fmt::format("{:.3f}", fmt::join(hz, "  "));
}

void print_table(const Scene& scene, const ModalSummary& m) {
  fmt::print("{} ({})\n\n", scene.name, scene.source);
  fmt::print("Geometry\n");
  fmt::print("  J_p       {:<12.5g} kg m^2  moment of inertia about a pivot, at rest\n", m.J_p);
  fmt::print("  H_cg      {:<12.4f} m       height of the centre of gravity\n", m.H_cg);
  fmt::print("  alpha_cg  {:<12.4f} rad     slenderness, atan(B / H_cg)\n", m.alpha_cg);
  fmt::print("  r         {:<12.4f} -       restitution from the geometry (Eq. 10)\n\n", m.r_eq10);
  fmt::print("Modes (linearised)\n");
  fmt::print("  fixed base              f = {} Hz\n", hz_list(m.fixed_base_hz));
  fmt::print("  rocking, free           f = {} Hz\n", hz_list(m.rocking_hz));
  fmt::print("                          rocking mode p = {:.3f} rad/s (unstable: e^(pt))\n", m.rocking_p);
  if (scene.damper.enabled) {
    fmt::print("  rocking, damper elastic lowest mode f = {:.3f} Hz\n", m.damper_pre_yield_hz);
    if (m.damper_post_yield_p > 0)
      fmt::print("  rocking, damper yielded rocking mode p = {:.3f} rad/s\n", m.damper_post_yield_p);
    else
      fmt::print("  rocking, damper yielded stable (post-yield stiffness outweighs gravity)\n");
  } else {
    fmt::print("  (the scene has no damper)\n");
  }
  fmt::print("\nReference forces at uplift, first-mode push, no damper\n");
  fmt::print("  M_ref     {:<12.4g} N m     base moment\n", m.reference.base_moment);
  fmt::print("  V_ref     {:<12.4g} N       base shear\n", m.reference.base_shear);
}

}  // namespace

Command add_modal_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "modal",
      "Linearised modal analysis: fixed-base modes, the rocking phase about\n"
      "theta = 0 (free, with the damper elastic, with it yielded), the geometric\n"
      "restitution r of Eq. 10, and the reference forces M_ref, V_ref.");
  auto opts = std::make_shared<SceneOptions>();
  auto json = std::make_shared<bool>(false);
  add_scene_options(*cmd, *opts);
  cmd->add_flag("--json", *json, "Print one JSON object (SI units) instead of a table");
  cmd->footer("Example: rocking modal --set structure.EI_scale=0.5 --json");
  return [opts, json]() {
    const Scene scene = load_elastic_scene(*opts);
    spdlog::debug("modal analysis of '{}' from {}", scene.name, scene.source);
    const ModalSummary m = modal_analysis(scene.structure, scene.damper);
    if (*json) std::cout << to_json(m).dump(2) << '\n';
    else print_table(scene, m);
    return 0;
  };
}

}  // namespace rocking::app
