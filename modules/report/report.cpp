module;
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <algorithm>
#include <optional>
#include <span>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>
module rocking.report;
import rocking.errors;

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

json run_summary(const RunLabel& label, const RunResult& r) {
  json peaks = json::object();
  for (Quantity q : peak_quantities)
    if (r.reports(q)) peaks[std::string(info(q).name)] = r.peak(q);
  for (const DeviceResult& d : r.devices) {
    peaks[device_quantity_name(d.name, DeviceQuantity::elongation)] = d.peak_elongation;
    peaks[device_quantity_name(d.name, DeviceQuantity::force)] = d.peak_force;
  }
  json out = {
      {"scene", label.scene},
      {"scene_source", label.scene_source},
      {"motion", label.motion},
      {"record", label.record.empty() ? json(nullptr) : json(label.record)},
      {"vertical_motion", label.vertical.empty() ? json(nullptr) : json(label.vertical)},
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
  // A stated end under the key that names it: separation, sliding, undecided.
  if (is_stated(r.outcome)) out[r.outcome == Outcome::separated ? "separation" : std::string(outcome_name(r.outcome))] = r.stated;
  if (r.separated_joint) out["separated_joint"] = *r.separated_joint;
  json devices = json::array();
  for (const DeviceResult& d : r.devices)
    devices.push_back({{"name", d.name},
                       {"law", d.law},
                       {"force_at_rest_N", d.force_at_rest},
                       {"peak_elongation_m", d.peak_elongation},
                       {"peak_force_N", d.peak_force},
                       {"work_J", finite_or_null(d.work)},
                       {"fracture_s", finite_or_null(d.fracture_time)},
                       {"state", std::isfinite(d.fracture_time) ? "broken" : "intact"}});
  out["devices"] = devices;
  if (!r.joints.empty()) {  // a structure with joints (MODEL.md 15): the base first
    json joints = json::array();
    for (std::size_t j = 0; j < r.joints.size(); ++j) {
      const JointResult& k = r.joints[j];
      joints.push_back({{"joint", j},
                        {"first_uplift_s", finite_or_null(k.first_uplift)},
                        {"first_impact_s", finite_or_null(k.first_impact)},
                        {"uplifts", k.uplifts},
                        {"impacts", k.impacts},
                        {"peak_theta", k.peak_theta},
                        {"peak_theta_over_alpha", k.peak_theta_over_alpha},
                        {"peak_friction_demand", finite_or_null(k.peak_friction)}});
    }
    out["joints"] = joints;
  }
  if (r.columns) {  // a structure on rocking columns (MODEL.md 16): their uplifts and impacts are the run's
    const ColumnsResult& c = *r.columns;
    out["columns"] = {{"first_uplift_s", finite_or_null(r.first_uplift)},
                      {"first_impact_s", finite_or_null(r.first_impact)},
                      {"uplifts", r.counts.uplifts},
                      {"impacts", r.counts.impacts},
                      {"peak_theta", r.peak(Quantity::columns_theta)},
                      {"peak_theta_over_alpha", r.peak(Quantity::columns_theta_over_alpha)},
                      {"peak_beam_x_m", r.peak(Quantity::beam_x)},
                      {"smallest_top_force_N", finite_or_null(c.smallest_top_force)},
                      {"smallest_top_force_s", finite_or_null(c.smallest_top_force_time)}};
  }
  if (r.energy_tracked) {
    const EnergyBalance& e = r.energy;
    out["energy_J"] = {{"initial", e.initial}, {"final", e.final}, {"ground_input", e.ground},
                       {"viscous", e.viscous}, {"damper", e.damper}, {"impacts", e.impacts},
                       {"balance_residual", e.residual()}};
  }
  return out;
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

HistoryColumns history_columns(const ContactModel& m) {
  const Presence has = presence(m);
  HistoryColumns c;
  for (Quantity q : history_quantities)
    if (has.has(info(q).needs) && !(m.jointed && q == Quantity::device_moment))
      c.columns.push_back({.quantity = q, .member = std::nullopt});
  for (std::size_t k = 0; k < m.devices.size(); ++k) {
    c.device_names.push_back(m.devices[k].name);
    for (const DeviceQuantityInfo& dq : device_quantity_table)
      if (dq.is(Role::history))
        c.columns.push_back({.quantity = std::nullopt, .member = std::nullopt, .device = k, .of = dq.id});
  }
  // Each joint above the base: its angle, rate and phase (joint 0's are theta, theta_dot, phase).
  const int joints = m.jointed ? m.jointed->chain.joints : 1;
  for (int j = 1; j < joints; ++j)
    for (std::size_t q = 0; q < joint_quantity_count; ++q)
      if (joint_quantity_table[q].is(Role::history))
        c.columns.push_back({.quantity = std::nullopt, .member = std::nullopt,
                             .joint = JointQuantityName{j, static_cast<JointQuantity>(q)}});
  return c;
}

HistoryColumns history_columns(const ContactModel& m, const std::vector<std::string>& chosen, std::string_view option) {
  const Presence has = presence(m);
  const int nodes = static_cast<int>(m.body.structure.heights.size());
  HistoryColumns c;
  for (const Device& d : m.devices) c.device_names.push_back(d.name);
  c.columns.push_back({.quantity = Quantity::t, .member = std::nullopt});
  for (const std::string& text : chosen) {
    HistoryColumns::Column col;
    const std::optional<QuantityName> q = parse_quantity_name(text);
    if (q && q->scalar) {
      const QuantityInfo& i = info(*q->scalar);
      if (!i.is(Role::history) && !i.is(Role::on_request))
        throw InputError(fmt::format("{} {}: not a history quantity", option, text));
      if (!has.has(i.needs) || (m.jointed && *q->scalar == Quantity::device_moment))
        throw InputError(fmt::format("{} {}: this scene does not report it", option, text));
      if (*q->scalar == Quantity::t) continue;  // always first
      col.quantity = q->scalar;
    } else if (const std::optional<JointQuantityName> joint = parse_joint_quantity(text)) {
      const int above = m.jointed ? m.jointed->chain.joints - 1 : 0;
      if (joint->joint > above)
        throw InputError(fmt::format("{} {}: no joint {} ({})", option, text, joint->joint,
                                     above == 0 ? "this scene has no [[joint]] above its base"
                                                : fmt::format("this scene's joints above the base are 1 to {}", above)));
      col.joint = joint;
    } else if (const std::optional<MemberQuantityName> member = parse_member_quantity(text)) {
      std::vector<std::string> joint_names;
      for (const JointQuantityInfo& q : joint_quantity_table) joint_names.push_back(fmt::format("jointK.{}", q.name));
      if (m.jointed)
        throw InputError(fmt::format("{} {}: node and element quantities of a structure with joints are not reported "
                                     "(its joints' are: {})",
                                     option, text, fmt::join(joint_names, ", ")));
      if (m.on_columns && member->of == MemberQuantityName::Of::node && member->node_quantity() != NodeQuantity::u &&
          member->node_quantity() != NodeQuantity::a_abs)
        throw InputError(fmt::format("{} {}: a node's displacement from the ground is not reported for a structure on "
                                     "rocking columns (beam.x plus nodeK.u is)", option, text));
      const char* what = member->of == MemberQuantityName::Of::node ? "node" : "element";
      if (member->index < 1 || member->index > nodes)
        throw InputError(fmt::format("{} {}: no {} {} (this structure's {}s are 1 to {})", option, text, what,
                                     member->index, what, nodes));
      if (!has.has(member->info().needs))
        throw InputError(fmt::format("{} {}: this scene does not report it (a rigid structure has no elastic {})",
                                     option, text, member->of == MemberQuantityName::Of::node ? "displacement" : "forces"));
      col.member = member;
    } else if (q) {
      const auto at = std::ranges::find(c.device_names, q->device);
      if (at == c.device_names.end())
        throw InputError(fmt::format("{} {}: no device '{}' in this scene (devices: {})", option, text, q->device,
                                     c.device_names.empty() ? "none" : fmt::format("{}", fmt::join(c.device_names, ", "))));
      if (q->of == DeviceQuantity::work && !has.energy)
        throw InputError(fmt::format("{} {}: this run does not track its energy balance", option, text));
      col.device = static_cast<std::size_t>(at - c.device_names.begin());
      col.of = q->of;
    } else {
      throw InputError(fmt::format("{} {}: unknown quantity (rocking simulate --list-quantities lists them)", option, text));
    }
    const bool again = std::ranges::any_of(c.columns, [&](const HistoryColumns::Column& o) {
      return o.quantity == col.quantity && o.member == col.member && o.joint == col.joint &&
             (col.quantity || col.member || col.joint || (o.device == col.device && o.of == col.of));
    });
    if (again) throw InputError(fmt::format("{} {}: named twice", option, text));
    c.columns.push_back(col);
  }
  return c;
}

HistoryColumns history_columns(const Scene& scene, const ContactModel& m, const std::vector<std::string>& chosen,
                               std::string_view option) {
  if (!chosen.empty()) return history_columns(m, chosen, option);
  if (!scene.output.history.empty()) return history_columns(m, scene.output.history, scene.output.origin);
  return history_columns(m);
}

double history_interval(const Scene& scene, std::optional<double> given) {
  return given ? *given : scene.output.interval > 0 ? scene.output.interval : default_history_interval;
}

std::vector<std::string> HistoryColumns::names() const {
  std::vector<std::string> out;
  for (const Column& c : columns)
    out.push_back(c.quantity ? std::string(info(*c.quantity).name)
                  : c.member ? c.member->name()
                  : c.joint  ? c.joint->name()
                             : device_quantity_name(device_names[c.device], c.of));
  return out;
}

std::vector<std::string> HistoryColumns::headers() const {
  std::vector<std::string> out;
  const std::vector<std::string> n = names();
  for (std::size_t k = 0; k < columns.size(); ++k) {
    const Column& c = columns[k];
    out.push_back(column_header(n[k], c.quantity ? info(*c.quantity).unit
                                      : c.member ? c.member->info().unit
                                      : c.joint  ? info(c.joint->which).unit
                                                 : info(c.of).unit));
  }
  return out;
}

bool HistoryColumns::has_members() const {
  return std::ranges::any_of(columns, [](const Column& c) { return c.member.has_value(); });
}

namespace {
// A device column's value.
double device_value(const DeviceSample& s, DeviceQuantity q) {
  switch (q) {
    case DeviceQuantity::elongation: return s.e;
    case DeviceQuantity::force: return s.F;
    case DeviceQuantity::work: return s.work;
    case DeviceQuantity::count_: break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// A joint column's value: NaN when the run handed over no sample for that
// joint (it ended before its first row). theta_over_alpha is theta over the
// joint's overturning angle (the slenderness of everything above it).
double joint_value(const ContactModel& m, std::span<const JointSample> joints, const JointQuantityName& q) {
  const auto j = static_cast<std::size_t>(q.joint);
  if (j >= joints.size()) return std::numeric_limits<double>::quiet_NaN();
  const JointSample& s = joints[j];
  switch (q.which) {
    case JointQuantity::theta: return s.theta;
    case JointQuantity::theta_dot: return s.theta_dot;
    case JointQuantity::phase: return s.phase.is_rocking() ? sign(*s.phase.pivot()) : 0.0;
    case JointQuantity::friction: return s.friction();
    case JointQuantity::theta_over_alpha: return s.theta / m.jointed->overturn_angle[j];
    case JointQuantity::count_: break;
  }
  return std::numeric_limits<double>::quiet_NaN();
}
}  // namespace

void HistoryColumns::values(const ContactModel& m, const Response& r, const std::vector<DeviceSample>& samples,
                            Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot,
                            std::vector<double>& out, std::span<const JointSample> joints) const {
  out.clear();
  for (const Column& c : columns) {
    if (c.quantity) out.push_back(r[*c.quantity]);
    else if (c.joint) out.push_back(joint_value(m, joints, *c.joint));
    else if (c.member && c.member->of == MemberQuantityName::Of::node)
      out.push_back(node_value(m, c.member->node_quantity(), c.member->index, r, u, u_dot));
    else if (c.member) out.push_back(element_value(m, c.member->element_quantity(), c.member->index, u));
    else out.push_back(device_value(samples[c.device], c.of));
  }
}

HistoryObserver::HistoryObserver(const ContactModel& m, HistoryColumns columns)
    : model_(&m), columns_(std::move(columns)), members_(columns_.has_members()), devices_(m.devices.size()) {}

void HistoryObserver::nodal(Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot) {
  if (!members_) return;
  u_ = u;
  u_dot_ = u_dot;
}

void HistoryObserver::record(const Response& r) {
  columns_.values(*model_, r, devices_, u_, u_dot_, values_, joints_);
  row(r, values_);
}

std::vector<QuantityRow> quantity_rows(const ContactModel& m) {
  const Presence has = presence(m);
  std::vector<QuantityRow> rows;
  for (const QuantityInfo& q : quantity_table)
    rows.push_back({std::string(q.name), std::string(q.unit), std::string(q.words), q.is(Role::history),
                    q.is(Role::peak), q.is(Role::study), has.has(q.needs), q.is(Role::on_request)});
  for (const Device& d : m.devices)
    for (const DeviceQuantityInfo& q : device_quantity_table)
      rows.push_back({device_quantity_name(d.name, q.id), std::string(q.unit),
                      fmt::format("{} of {} ({})", q.words, d.name, law_name(d.law)), q.is(Role::history),
                      q.is(Role::peak), q.is(Role::study), !q.is(Role::on_request) || has.energy,
                      q.is(Role::on_request)});
  if (m.jointed)
    for (const JointQuantityInfo& q : joint_quantity_table)
      rows.push_back({fmt::format("jointK.{}", q.name), std::string(q.unit),
                      fmt::format("{} K (K = 1 to {})", q.words, m.jointed->chain.joints - 1), q.is(Role::history),
                      q.is(Role::peak), q.is(Role::study), true, q.is(Role::on_request)});
  const std::size_t n = static_cast<std::size_t>(m.body.structure.heights.size());
  using Members = std::pair<const char*, std::span<const MemberQuantityInfo>>;
  for (const auto& [word, table] : {Members{"node", node_quantity_table}, Members{"element", element_quantity_table}})
    for (const MemberQuantityInfo& q : table)
      rows.push_back({fmt::format("{}K.{}", word, q.name), std::string(q.unit),
                      fmt::format("{} of {} K (K = 1 to {})", q.words, word, n), false, false, false, has.has(q.needs),
                      true});
  return rows;
}

std::string quantity_table_text(const ContactModel& m) {
  std::string out = fmt::format("{:<28} {:<7} {:<20} {}\n", "quantity", "unit", "reported as", "what");
  for (const QuantityRow& q : quantity_rows(m)) {
    std::string roles;
    for (const auto& [on, word] : {std::pair{q.history, "history"}, std::pair{q.peak, "peak"},
                                   std::pair{q.study, "study"}, std::pair{q.on_request, "on request"}})
      if (on) roles += (roles.empty() ? "" : ",") + std::string(word);
    out += fmt::format("{:<28} {:<7} {:<20} {}{}\n", q.name, q.unit.empty() ? "-" : q.unit, roles, q.words,
                       q.reported ? "" : " (not in this scene)");
  }
  out += "history: a column of history.csv; peak: in summary.json's peaks; study: an ida/sweep CSV column and a "
         "--limit; on request: a column of history.csv when chosen (--history, a scene's [output] history).\n";
  return out;
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
  b.devices = rocking_stiffness(scene_devices(scene), s.half_width, Pivot::right);
  b.uplift_g = (b.mass * gravity * s.half_width + b.devices.held_moment) / (b.mass * b.H_cg * gravity);
  return b;
}

// A structure on rocking columns (MODEL.md 16): the columns rock as one
// column of their slenderness with the frame's p-hat (a rigid deck lifts them
// at a_g = g tan alpha, and its impacts keep 16's r); the structure on the
// beam, while they stand, is on a fixed base (MODEL.md 8).
json columns_modal(const Scene& scene) {
  const Columns c = make_columns(*scene.columns, scene.structure);
  // The devices at the columns' bases hold n sum F(e = 0) l at rest about
  // each side (MODEL.md 11), those between the ground and the beam
  // F(e = 0) de/d|theta| each; the frame lifts about the side where that is
  // least, at a_g / g = b / h + D_0 / (g h (n m_c + 2 m_d)) for a rigid deck
  // (MODEL.md 16's uplift condition).
  const ContactModel model = make_contact_model(scene, false);
  double held = model.devices.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (Pivot p : pivots) {
    double about = 0;
    for (const ContactModel::Acting& a : model.acting[index(p)]) about += law_force_at_rest(a.law, 0.0) * a.lever;
    about *= c.group.count;
    for (const ColumnsModel::BeamDevice& d : model.on_columns->beam_devices)
      about += law_force_at_rest(model.devices[static_cast<std::size_t>(d.device)].law, 0.0) * d.lever[index(p)];
    if (!model.devices.empty()) held = std::min(held, about);
  }
  const double b = c.group.half_width, h = c.group.half_height;
  const double uplift_g = b / h + held / (c.g * h * (c.columns_mass + 2.0 * c.deck_mass));
  json out = {{"columns",
               {{"count", c.group.count},
                {"half_width_m", c.group.half_width},
                {"half_height_m", c.group.half_height},
                {"mass_kg", c.group.mass},
                {"spacing_m", c.group.spacing},
                {"alpha", c.alpha},
                {"R_m", c.R},
                {"gamma", frame_gamma(c)},
                {"p", std::sqrt(3 * c.g / (4 * c.R))},
                {"p_hat", std::sqrt(frame_p2(c))},
                {"r_rigid_deck", frame_restitution(c)},
                {"held_moment_N_m", held},
                {"uplift_g", uplift_g}}}};
  if (!scene.structure.rigid) out["fixed_base_hz"] = modal_analysis(scene.structure, {}).fixed_base_hz;
  return out;
}

// A structure with joints (MODEL.md 15): at each joint, everything above it
// taken as one rigid body rocking about the joint's corner, with the joints
// above closed: its mass, the height of its centre of mass above the joint,
// its slenderness alpha_j, its moment of inertia about the corner (its
// lumped masses and slabs on the centre line), its frequency parameter p_j =
// sqrt(m g R / J_p) and its momentum-law restitution 1 - 2 m B_j^2 / J_p
// (Eq. 10); and the static uplift threshold of a rigid stack, the a_g / g
// at which the joint's reaction reaches its corner: (B_j + D_0,j / (m g)) /
// H_j, where D_0,j is the least over the two pivots of sum P0 (B_j - s x)
// over the tendons across the joint at rest (vertical there, MODEL.md 11)
// plus sum F(e = 0) l_s over the devices across it (at the base or above).
// Under a slow push the smallest lifts first. The
// structure's fixed-base modes (every joint closed) when it is flexible.
json joints_modal(const Scene& scene) {
  const ContactModel model = make_contact_model(scene, false);
  const ChainData& d = model.jointed->chain.data;
  json joints = json::array();
  int first = 0;
  double lowest = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < d.segments.size(); ++j) {
    const ChainSegment& at = d.segments[j];
    const double h = at.base_height, B = at.half_width;
    double m = 0, mz = 0, J = 0;
    for (std::size_t k = j; k < d.segments.size(); ++k) {
      const ChainSegment& sg = d.segments[k];
      const auto add = [&](double mass, double z) {
        m += mass;
        mz += mass * (z - h);
        J += mass * (B * B + (z - h) * (z - h));
      };
      add(sg.base_mass, sg.base_height);
      for (Eigen::Index i = 0; i < sg.masses.size(); ++i) add(sg.masses[i], sg.heights[i]);
    }
    const double H = mz / m, R = std::hypot(B, H);
    // The tendons across the joint hold sum P0 (B - s x) about pivot s, and
    // the devices across it sum F(e = 0) l: the push lifts the joint about
    // the pivot where that is least.
    double held = std::numeric_limits<double>::infinity();
    for (Pivot p : pivots) {
      double about = 0;
      for (const ChainTendon& t : d.tendons)
        if (t.from.segment < static_cast<int>(j) && t.to.segment >= static_cast<int>(j))
          about += std::max(0.0, t.prestress) * (B - sign(p) * t.to.x);
      if (j == 0)
        for (const ContactModel::Acting& a : model.acting[index(p)]) about += law_force_at_rest(a.law, 0.0) * a.lever;
      for (const JointedModel::UpperDevices& u : model.jointed->upper)
        if (u.joint == static_cast<int>(j))
          for (const ContactModel::Acting& a : u.block->acting[index(p)]) about += law_force_at_rest(a.law, 0.0) * a.lever;
      held = std::min(held, about);
    }
    const double uplift_g = (B + held / (m * d.g)) / H;
    if (uplift_g < lowest && (j > 0 || model.jointed->base_rocks())) {  // a fixed base never lifts
      lowest = uplift_g;
      first = static_cast<int>(j);
    }
    joints.push_back({{"joint", j},
                      {"height_m", h},
                      {"half_width_m", B},
                      {"mass_above_kg", m},
                      {"cg_above_joint_m", H},
                      {"alpha", std::atan2(B, H)},
                      {"J_p_kg_m2", J},
                      {"R_m", R},
                      {"p", std::sqrt(m * d.g * R / J)},
                      {"r_momentum", 1.0 - 2.0 * m * B * B / J},
                      {"held_moment_N_m", held},
                      {"uplift_g", uplift_g}});
  }
  json out = {{"joints", joints}, {"lifts_first", first}};
  if (!scene.structure.rigid) out["fixed_base_hz"] = modal_analysis(scene.structure, {}).fixed_base_hz;
  return out;
}

json modal_summary(const Scene& scene) {
  if (scene.columns) return columns_modal(scene);
  if (scene.jointed()) return joints_modal(scene);
  if (scene.structure.rigid) return block_modal(block_summary(scene));
  return flexible_modal(modal_analysis(scene.structure, scene_devices(scene)));
}

nlohmann::json record_summary(const std::string& id, const std::string& file, const GroundMotion& motion,
                              const RecordMeasures& m) {
  const RecordInfo& i = motion.info();
  auto text = [](const std::string& s) { return s.empty() ? nlohmann::json(nullptr) : nlohmann::json(s); };
  std::vector<double> psa_g;
  for (double v : m.psa) psa_g.push_back(v / gravity);
  return {{"id", id},
          {"file", text(file)},
          {"format", text(i.format)},
          {"event", text(i.event)},
          {"date", text(i.date)},
          {"station", text(i.station)},
          {"component", text(i.component)},
          {"units", text(i.units)},
          {"dt_s", i.dt > 0 ? nlohmann::json(i.dt) : nlohmann::json(nullptr)},
          {"npts", motion.sample_count()},
          {"duration_s", motion.duration()},
          {"stated_peak_g", i.stated_peak ? nlohmann::json(*i.stated_peak / gravity) : nlohmann::json(nullptr)},
          {"processing", text(i.processing)},
          {"pga_g", m.pga / gravity},
          {"pga_time_s", m.pga_time},
          {"pgv_m_s", m.pgv},
          {"pgd_m", m.pgd},
          {"arias_m_s", m.arias},
          {"d5_95_s", m.d5_95},
          {"cav_m_s", m.cav},
          {"damping", m.damping},
          {"periods_s", m.periods},
          {"psa_g", psa_g}};
}

}  // namespace rocking
