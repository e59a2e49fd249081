module;
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <cmath>
#include <string>
#include <vector>
module rocking.report;

namespace rocking {

namespace {

using nlohmann::json;

json finite_or_null(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json positive_or_null(double v) { return v > 0 ? json(v) : json(nullptr); }

json flexible_modal(const ModalSummary& m) {
  return {{"fixed_base_hz", m.fixed_base_hz},
          {"rocking_hz", m.rocking_hz},
          {"rocking_p", positive_or_null(m.rocking_p)},
          {"damper_pre_yield_hz", positive_or_null(m.damper_pre_yield_hz)},
          {"damper_post_yield_p", positive_or_null(m.damper_post_yield_p)},
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

json block_modal(const BlockSummary& b) {
  return {{"rigid", true},
          {"mass", b.mass},
          {"J_p", b.J_p},
          {"H_cg", b.H_cg},
          {"alpha_cg", b.alpha_cg},
          {"R", b.R},
          {"p", b.p},
          {"r_eq10", b.r_eq10},
          {"uplift_g", b.uplift_g},
          {"k_theta", {{"at_rest", b.devices.at_rest}, {"yielded", b.devices.yielded}}},
          {"device_held_moment", b.devices.held_moment}};
}

}  // namespace

std::string summary_json(const RunLabel& label, const RunResult& r, int indent) {
  json peaks = json::object();
  for (std::size_t i = 0; i < quantity_count; ++i) {
    const auto q = static_cast<Quantity>(i);
    const bool absent = (is_force(q) && !r.has_forces) ||
                        ((q == Quantity::damper_d || q == Quantity::damper_F) && !r.has_damper);
    peaks[std::string(quantity_name(q))] = absent ? json(nullptr) : json(r.peaks[i]);
  }
  json out = {
      {"scene", label.scene},
      {"scene_source", label.scene_source},
      {"motion", label.motion},
      {"record", label.record.empty() ? json(nullptr) : json(label.record)},
      {"scale", label.scale},
      {"scale_factors", {{"scene", label.scene_scale}, {"option", label.option_scale}}},
      {"integrator", r.integrator},
      {"rtol", label.rtol},
      {"atol", label.atol},
      {"peaks", peaks},
      {"top_total_mm", r.top_total_mm},
      {"counts", {{"uplifts", r.counts.uplifts}, {"impacts", r.counts.impacts}}},
      {"first_uplift_s", finite_or_null(r.first_uplift)},
      {"first_impact_s", finite_or_null(r.first_impact)},
      {"outcome", std::string(outcome_name(r.outcome))},
      {"t_end", r.t_end},
      {"final_theta", r.final_theta},
      {"stats", {{"rhs", r.stats.rhs}, {"steps", r.stats.steps}, {"rejected", r.stats.rejected},
                 {"events", r.stats.events}}},
      {"wall_s", r.wall_s},
  };
  if (r.outcome == Outcome::failed) out["failure"] = r.failure;
  json devices = json::array();
  for (const DeviceResult& d : r.devices)
    devices.push_back({{"name", d.name},
                       {"peak_elongation_m", d.peak_elongation},
                       {"peak_force_N", d.peak_force},
                       {"work_J", finite_or_null(d.work)},
                       {"fracture_s", finite_or_null(d.fracture_time)}});
  out["devices"] = devices;
  if (r.energy_tracked) {
    const EnergyBalance& e = r.energy;
    out["energy_J"] = {{"initial", e.initial}, {"final", e.final}, {"ground_input", e.ground},
                       {"viscous", e.viscous}, {"damper", e.damper}, {"impacts", e.impacts},
                       {"balance_residual", e.residual()}};
  }
  return out.dump(indent);
}

std::string describe_motion(const std::string& name) {
  if (name.find("pphs_s57e") != std::string::npos)
    return name + " (Papanui, stand-in for the Canterbury Aero Club record)";
  return name;
}

std::string describe_motion(const GroundMotion& motion) {
  const std::string name = describe_motion(motion.name());
  return motion.description().empty() ? name : fmt::format("{}: {}", name, motion.description());
}

std::vector<HistoryColumn> history_columns(const std::vector<Device>& devices) {
  std::vector<HistoryColumn> c = {
      {"t", "s"},          {"phase", ""},           {"u_N", "m"},          {"theta", "rad"},
      {"theta/alpha_cg", "-"}, {"delta_t", "-"},    {"delta_e", "-"},      {"d", "m"},
      {"F_hd", "N"},       {"base_shear", "V_ref"}, {"base_moment", "M_ref"}, {"mid_shear", "V_ref"},
      {"mid_moment", "M_ref"}, {"a_g", "m/s2"}};
  if (!devices.empty()) c.push_back({"M_dev", "N m"});
  for (const Device& d : devices) {
    c.push_back({d.name + " e", "m"});
    c.push_back({d.name + " F", "N"});
  }
  return c;
}

void history_values(const Response& r, double a_g, const std::vector<DeviceSample>& devices, std::vector<double>& out) {
  using Q = Quantity;
  out.assign({r.t, static_cast<double>(r.pivot), r.u_top, r[Q::theta], r[Q::theta_over_alpha], r[Q::delta_t],
              r[Q::delta_e], r[Q::damper_d], r[Q::damper_F], r[Q::base_shear], r[Q::base_moment], r[Q::mid_shear],
              r[Q::mid_moment], a_g});
  if (devices.empty()) return;
  double moment = 0;
  for (const DeviceSample& d : devices) moment += d.moment;
  out.push_back(moment);
  for (const DeviceSample& d : devices) {
    out.push_back(d.e);
    out.push_back(d.F);
  }
}

BlockSummary block_summary(const Scene& scene) {
  const Structure& s = scene.structure;
  BlockSummary b;
  b.J_p = pivot_inertia(s);
  b.H_cg = centre_of_gravity_height(s);
  b.alpha_cg = slenderness(s);
  b.R = std::hypot(s.half_width, b.H_cg);
  b.mass = total_mass(s);
  b.p = std::sqrt(b.mass * gravity * b.R / b.J_p);
  b.r_eq10 = restitution_eq10(s);
  // Uplift about the right pivot when m a_g H_cg = m g B + the devices' held moment (MODEL.md 11).
  b.devices = rocking_stiffness(scene_devices(scene), s.half_width, +1);
  b.uplift_g = (b.mass * gravity * s.half_width + b.devices.held_moment) / (b.mass * b.H_cg * gravity);
  return b;
}

std::string modal_json(const Scene& scene, int indent) {
  if (scene.structure.rigid) return block_modal(block_summary(scene)).dump(indent);
  return flexible_modal(modal_analysis(scene.structure, scene_devices(scene))).dump(indent);
}

}  // namespace rocking
