// `rocking modal`: linearised modal analysis of a scene (MODEL.md 8).
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <cmath>
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
          {"k_theta", {{"right", {{"at_rest", m.devices[1].at_rest}, {"yielded", m.devices[1].yielded}}},
                       {"left", {{"at_rest", m.devices[0].at_rest}, {"yielded", m.devices[0].yielded}}}}},
          {"device_held_moment", {{"right", m.devices[1].held_moment}, {"left", m.devices[0].held_moment}}},
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
  if (m.devices[0].any || m.devices[1].any) {
    if (m.damper_pre_yield_hz > 0)
      fmt::print("  rocking, devices at rest lowest mode f = {:.3f} Hz\n", m.damper_pre_yield_hz);
    else
      fmt::print("  rocking, devices at rest unstable (their stiffness does not outweigh gravity)\n");
    if (m.damper_post_yield_p > 0)
      fmt::print("  rocking, devices yielded rocking mode p = {:.3f} rad/s\n", m.damper_post_yield_p);
    else
      fmt::print("  rocking, devices yielded stable (post-yield stiffness outweighs gravity)\n");
    fmt::print("\nDevices linearised at theta = 0 (MODEL.md 11), about the right / left pivot\n");
    fmt::print("  k_theta   {:<11.4g} / {:<11.4g} N m/rad  sum k (de/dth)^2, at rest\n", m.devices[1].at_rest,
               m.devices[0].at_rest);
    fmt::print("  k_theta   {:<11.4g} / {:<11.4g} N m/rad  yielded\n", m.devices[1].yielded, m.devices[0].yielded);
    fmt::print("  held      {:<11.4g} / {:<11.4g} N m      sum F(e = 0) l: uplift needs this much more moment\n",
               m.devices[1].held_moment, m.devices[0].held_moment);
  } else {
    fmt::print("  (the scene has no device)\n");
  }
  fmt::print("\nReference forces at uplift, first-mode push, no damper\n");
  fmt::print("  M_ref     {:<12.4g} N m     base moment\n", m.reference.base_moment);
  fmt::print("  V_ref     {:<12.4g} N       base shear\n", m.reference.base_shear);
}

// A rigid block has no elastic modes: what it has is its geometry, its
// frequency parameter p = sqrt(m g R / J_p) (Housner 1963; the linearised
// rocking motion grows as e^(pt)) and the restitution of Eq. 10.
int rigid_block(const Scene& scene, bool json) {
  const Structure& s = scene.structure;
  const double J_p = pivot_inertia(s), H_cg = centre_of_gravity_height(s), alpha = slenderness(s);
  const double R = std::hypot(s.half_width, H_cg), m = total_mass(s);
  const double p = std::sqrt(m * gravity * R / J_p), r = restitution_eq10(s);
  // Uplift about the right pivot when m a_g H_cg = m g B + the devices' held moment (MODEL.md 11).
  const std::vector<Device> devices = scene_devices(scene);
  const RockingStiffness right = rocking_stiffness(devices, s.half_width, +1);
  const double uplift_g = (m * gravity * s.half_width + right.held_moment) / (m * H_cg * gravity);
  if (json) {
    std::cout << nlohmann::json{{"rigid", true}, {"mass", m},   {"J_p", J_p}, {"H_cg", H_cg},
                                {"alpha_cg", alpha}, {"R", R}, {"p", p},     {"r_eq10", r},
                                {"uplift_g", uplift_g},
                                {"k_theta", {{"at_rest", right.at_rest}, {"yielded", right.yielded}}},
                                {"device_held_moment", right.held_moment}}
                     .dump(2)
              << '\n';
    return 0;
  }
  fmt::print("{} ({}): a rigid block, no elastic modes\n\n", scene.name, scene.source);
  fmt::print("  mass      {:<12.5g} kg      total, base included\n", m);
  fmt::print("  J_p       {:<12.5g} kg m^2  moment of inertia about a pivot\n", J_p);
  fmt::print("  H_cg      {:<12.4f} m       height of the centre of gravity\n", H_cg);
  fmt::print("  alpha_cg  {:<12.4f} rad     slenderness, atan(B / H_cg); alone it lifts at a_g = g tan(alpha) = {:.3f} g\n",
             alpha, std::tan(alpha));
  fmt::print("  R         {:<12.4f} m       pivot to centre of gravity\n", R);
  fmt::print("  p         {:<12.4f} rad/s   frequency parameter sqrt(m g R / J_p) (Housner 1963)\n", p);
  fmt::print("  r         {:<12.4f} -       restitution from the geometry (Eq. 10)\n", r);
  if (right.any) {
    fmt::print("  k_theta   {:<12.4g} N m/rad devices, sum k (de/dth)^2 at rest (right pivot); yielded {:.4g}\n",
               right.at_rest, right.yielded);
    fmt::print("  held      {:<12.4g} N m     devices' force at rest x lever arm: uplift at a_g = {:.3f} g\n",
               right.held_moment, uplift_g);
  }
  return 0;
}

}  // namespace

Command add_modal_command(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "modal",
      "Linearised modal analysis: fixed-base modes, the rocking phase about\n"
      "theta = 0 (free, with the devices at rest, with them yielded), the devices'\n"
      "rocking stiffness sum k (de/dth)^2 and the moment their prestress holds, the\n"
      "geometric restitution r of Eq. 10, and the reference forces M_ref, V_ref. For a rigid\n"
      "block (structure.rigid = true): its geometry, p and r.");
  auto opts = std::make_shared<SceneOptions>();
  auto json = std::make_shared<bool>(false);
  add_scene_options(*cmd, *opts);
  cmd->add_flag("--json", *json, "Print one JSON object (SI units) instead of a table");
  cmd->footer("Example: rocking modal --set structure.EI_scale=0.5 --json");
  return [opts, json]() {
    const Scene scene = load_scene(*opts);
    if (scene.structure.rigid) return rigid_block(scene, *json);
    spdlog::debug("modal analysis of '{}' from {}", scene.name, scene.source);
    const ModalSummary m = modal_analysis(scene.structure, scene_devices(scene));
    if (*json) std::cout << to_json(m).dump(2) << '\n';
    else print_table(scene, m);
    return 0;
  };
}

}  // namespace rocking::app
