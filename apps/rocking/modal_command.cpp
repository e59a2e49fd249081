// `rocking modal`: linearised modal analysis of a scene (MODEL.md 8).
#include <rocking/eigen.hpp>
#include "log.hpp"
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>
#include <cmath>
#include <iostream>
#include "commands.hpp"
import rocking.errors;

namespace rocking::app {

namespace {

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
      fmt::print("  rocking, devices yielded stable (their yielded stiffness outweighs gravity)\n");
    fmt::print("\nDevices linearised at theta = 0 (MODEL.md 11), about the right / left pivot\n");
    fmt::print("  k_theta   {:<11.4g} / {:<11.4g} N m/rad  sum k (de/dth)^2, at rest\n", m.devices[1].at_rest,
               m.devices[0].at_rest);
    fmt::print("  k_theta   {:<11.4g} / {:<11.4g} N m/rad  yielded (a gap: engaged; friction, viscous: none)\n",
               m.devices[1].yielded, m.devices[0].yielded);
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
// frequency parameter p (Housner 1963; the linearised rocking motion grows
// as e^(pt)) and the restitution of Eq. 10 (rocking.report).
int rigid_block(const Scene& scene) {
  const BlockSummary b = block_summary(scene);
  const RockingStiffness& right = b.devices;
  fmt::print("{} ({}): a rigid block, no elastic modes\n\n", scene.name, scene.source);
  fmt::print("  mass      {:<12.5g} kg      total, base included\n", b.mass);
  fmt::print("  J_p       {:<12.5g} kg m^2  moment of inertia about a pivot\n", b.J_p);
  fmt::print("  H_cg      {:<12.4f} m       height of the centre of gravity\n", b.H_cg);
  fmt::print("  alpha_cg  {:<12.4f} rad     slenderness, atan(B / H_cg); alone it lifts at a_g = g tan(alpha) = {:.3f} g\n",
             b.alpha_cg, std::tan(b.alpha_cg));
  fmt::print("  R         {:<12.4f} m       pivot to centre of gravity\n", b.R);
  fmt::print("  p         {:<12.4f} rad/s   frequency parameter sqrt(m g R / J_p) (Housner 1963)\n", b.p);
  fmt::print("  r         {:<12.4f} -       restitution from the geometry (Eq. 10)\n", b.r_eq10);
  if (right.any) {
    fmt::print("  k_theta   {:<12.4g} N m/rad devices, sum k (de/dth)^2 at rest (right pivot); yielded {:.4g}\n",
               right.at_rest, right.yielded);
    fmt::print("  held      {:<12.4g} N m     devices' force at rest x lever arm: uplift at a_g = {:.3f} g\n",
               right.held_moment, b.uplift_g);
  }
  return 0;
}

// A structure on rocking columns: the columns' frame (MODEL.md 16) and the
// structure on the beam as on a fixed base, as rocking.report's modal_summary
// gives them.
int on_columns(const Scene& scene) {
  const nlohmann::json m = modal_summary(scene);
  const nlohmann::json& c = m["columns"];
  const auto v = [&](const char* key) { return c[key].get<double>(); };
  fmt::print("{} ({}): a structure on {} rocking columns (MODEL.md 16)\n\n", scene.name, scene.source,
             c["count"].get<int>());
  fmt::print("Columns (each), rocking together while the beam translates\n");
  fmt::print("  b         {:<12.4f} m       half-width\n", v("half_width_m"));
  fmt::print("  h         {:<12.4f} m       half-height ({:.4g} m tall)\n", v("half_height_m"), 2 * v("half_height_m"));
  fmt::print("  mass      {:<12.5g} kg      one column\n", v("mass_kg"));
  fmt::print("  alpha     {:<12.4f} rad     slenderness, atan(b / h)\n", v("alpha"));
  if (v("held_moment_N_m") > 0)
    fmt::print("  held      {:<12.4g} N m     the devices' force at rest x lever arm, all columns', about the weaker "
               "side\n",
               v("held_moment_N_m"));
  fmt::print("  uplift    {:<12.4f} g       a rigid deck lifts them at a_g / g = b / h + D_0 / (g h (n m_c + 2 m_d))\n",
             v("uplift_g"));
  fmt::print("  R         {:<12.4f} m       corner to centre\n", v("R_m"));
  fmt::print("  p         {:<12.4f} rad/s   one column alone, sqrt(3 g / 4R)\n", v("p"));
  fmt::print("  gamma     {:<12.4f} -       the deck's mass (beam and structure) over the columns'\n", v("gamma"));
  fmt::print("  p-hat     {:<12.4f} rad/s   the frame's, p sqrt((1 + 2 gamma) / (1 + 3 gamma)): it rocks as one "
             "column\n",
             v("p_hat"));
  fmt::print("  r         {:<12.4f} -       a rigid deck's impacts by the momentum law\n", v("r_rigid_deck"));
  if (m.contains("fixed_base_hz"))
    fmt::print("\nThe structure on the beam while the columns stand (a fixed base)\n  f = {} Hz\n",
               hz_list(m["fixed_base_hz"].get<std::vector<double>>()));
  return 0;
}

// A structure with joints: at each joint, everything above it as one rigid
// body about the joint's corner, as rocking.report's modal_summary gives it.
int with_joints(const Scene& scene) {
  const nlohmann::json m = modal_summary(scene);
  fmt::print("{} ({}): {} joints, the base's among them (MODEL.md 15)\n\n", scene.name, scene.source,
             m["joints"].size());
  fmt::print("At each joint, everything above it as one rigid body rocking about the joint's corner\n");
  fmt::print("  {:>5} {:>8} {:>7} {:>11} {:>8} {:>8} {:>8} {:>8} {:>9}\n", "joint", "h [m]", "B [m]", "mass [kg]",
             "H [m]", "alpha", "p [1/s]", "r", "uplift");
  for (const nlohmann::json& j : m["joints"])
    fmt::print("  {:>5} {:>8.3f} {:>7.3f} {:>11.5g} {:>8.3f} {:>8.4f} {:>8.4f} {:>8.4f} {:>7.3f} g\n",
               j["joint"].get<int>(), j["height_m"].get<double>(), j["half_width_m"].get<double>(),
               j["mass_above_kg"].get<double>(), j["cg_above_joint_m"].get<double>(), j["alpha"].get<double>(),
               j["p"].get<double>(), j["r_momentum"].get<double>(), j["uplift_g"].get<double>());
  fmt::print("  H: the centre of mass above the joint; p = sqrt(m g R / J_p); r = 1 - 2 m B^2 / J_p (the momentum\n"
             "  law); uplift: the a_g / g at which a rigid stack's joint lifts, (B + D_0 / (m g)) / H, D_0 the\n"
             "  moment the tendons across it (and at the base its devices) hold at rest.\n");
  fmt::print("Under a slow push joint {} lifts first.\n", m["lifts_first"].get<int>());
  if (m.contains("fixed_base_hz"))
    fmt::print("\nThe structure with every joint closed, on a fixed base\n  f = {} Hz\n",
               hz_list(m["fixed_base_hz"].get<std::vector<double>>()));
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
      "block (structure.rigid = true): its geometry, p and r. For a structure on rocking\n"
      "columns ([columns]): the columns' alpha, p, the frame's gamma, p-hat and r, and the\n"
      "structure's modes on the beam while the columns stand. For a structure with joints\n"
      "([[joint]]): at each joint, everything above it as one rigid body (its slenderness,\n"
      "p, r, and the push that lifts it), and which joint lifts first.");
  auto opts = std::make_shared<SceneOptions>();
  auto json = std::make_shared<bool>(false);
  add_scene_options(*cmd, *opts);
  cmd->add_flag("--json", *json, "Print one JSON object (SI units) instead of a table");
  cmd->footer("Example: rocking modal --set structure.EI_scale=0.5 --json");
  return [opts, json]() {
    const Scene scene = load_scene(*opts);
    if (*json) {
      std::cout << modal_summary(scene).dump(2) << '\n';
      return 0;
    }
    if (scene.columns) return on_columns(scene);
    if (scene.jointed()) return with_joints(scene);
    if (scene.structure.rigid) return rigid_block(scene);
    log::debug("modal analysis of '{}' from {}", scene.name, scene.source);
    const ModalSummary m = modal_analysis(scene.structure, scene_devices(scene));
    print_table(scene, m);
    return 0;
  };
}

}  // namespace rocking::app
