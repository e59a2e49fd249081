// rocking.quantities: the schema of what a run reports (MODEL.md 7 and 11).
// Each quantity is declared once, here: its name (history.csv's column,
// summary.json's peak key, an IDA/sweep CSV column, a `--limit` and a Python
// key), its unit, its words and symbol for figures and the text summary, what
// a model must have for it to mean something, and whether it is a history
// column, a tracked peak and a study quantity (IDA columns, limit states,
// fractiles). How each is computed lives beside the response it belongs to
// (rocking.simulation's evaluate); every output lists quantities from this
// table, never by hand. Devices report under their own scene names:
// NAME.elongation [m] and NAME.force [N] (DeviceQuantity). The energy
// balance's terms (MODEL.md 7 and 11: E(t) - E(0) = W_ground - W_viscous -
// W_devices - W_impacts, each W from the start) are history columns on
// request, filled by the run's drivers (rocking.simulation) at each row.
// A new quantity: its entry in Quantity and in quantity_table (the same
// order), and its computation.
module;
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>
export module rocking.quantities;

export namespace rocking {

// Every scalar quantity of a run's response, in the order of history.csv.
enum class Quantity : unsigned char {
  t, phase, u_top, theta, theta_over_alpha, theta_dot, delta_t, delta_e, damper_d, damper_F,
  base_shear, base_moment, mid_shear, mid_moment, a_top, a_g, a_v, device_moment, x_g,
  energy, work_ground, work_viscous, work_devices, work_impacts,
  columns_theta, columns_theta_over_alpha, columns_theta_dot, beam_x, columns_top_force,
  count_
};
inline constexpr std::size_t quantity_count = static_cast<std::size_t>(Quantity::count_);

// What a model must have for a quantity to mean something.
enum class Needs : unsigned char {
  always,
  rocking,     // the model can rock (theta)
  elasticity,  // a flexible structure (elastic displacements and section forces)
  dampers,     // the paper's [damper] pair (MODEL.md 5)
  devices,     // any device at the rocking interface
  vertical,    // the run shakes the ground vertically too (MODEL.md 14)
  energy,      // the run integrates its energy balance (MODEL.md 7 and 11)
  columns,     // the structure stands on rocking columns (MODEL.md 16)
};

// What a model has, for Needs.
struct Presence {
  bool rocking = true, elasticity = true, dampers = true, devices = true, vertical = true, energy = true;
  bool columns = false;
  constexpr bool has(Needs n) const {
    switch (n) {
      case Needs::always: return true;
      case Needs::rocking: return rocking;
      case Needs::elasticity: return elasticity;
      case Needs::dampers: return dampers;
      case Needs::devices: return devices;
      case Needs::vertical: return vertical;
      case Needs::energy: return energy;
      case Needs::columns: return columns;
    }
    return false;
  }
};

enum Role : unsigned char {
  history = 1,  // a column of history.csv (and of Python's history)
  peak = 2,     // its absolute peak is tracked on the dense output (summary.json's peaks)
  study = 4,    // a column of IDA and sweep results, a limit state, a fractile
  on_request = 8,  // a column of history.csv when asked for (--history, [output] history), not by default
};

// How the response figure (rocking.plot's render_response) draws a quantity
// that a run's history holds; its panels are these, in the order of their
// rank, each drawn when some run's history has the quantity's column.
enum class FigureRole : unsigned char {
  none,        // not drawn
  excitation,  // a panel against time, the first run's curve only (in grey), when it is not zero throughout
  response,    // a panel against time, one curve per run
  loop,        // a hysteresis loop against its figure_x quantity, one curve per run, broken where either is zero
  joints,      // a joint's quantity (jointK.NAME): one panel against time, one curve per joint and run
};
struct FigureUse {
  FigureRole role = FigureRole::none;
  unsigned char rank = 0;  // the panel's place, top to bottom
};

// How the browser lab (rocking.lab's answer, drawn by lab/lab.js) uses a
// quantity a run's history holds: not at all; in its drawing (the structure
// moved, the devices' loops, the energy bars); or also charted against time,
// the quantities of one chart number sharing a chart, the charts in the order
// of their numbers. The lab sends the columns of the quantities it uses, each
// with its name, unit, words, plain-text symbol, display unit and factor
// (figure_unit, figure_factor) and chart, and draws its charts from those.
enum class LabRole : unsigned char { none, drawn, chart };
struct LabUse {
  LabRole role = LabRole::none;
  unsigned char chart = 0;  // a charted quantity's chart
  bool ground = false;      // the ground's, the same for a run's twin: drawn once
};

struct QuantityInfo {
  Quantity id;
  std::string_view name;    // "delta_t"
  std::string_view unit;    // "m", "rad", "-", "V_ref", "M_ref", ...
  std::string_view words;   // "total top drift"
  std::string_view symbol;  // gnuplot enhanced text, "{/Symbol d}_t"
  double figure_factor;     // figures draw value x factor ...
  std::string_view figure_unit;  // ... in this unit ("%")
  Needs needs;
  unsigned char roles;      // Role bits
  FigureUse figure;         // its panel in the response figure
  Quantity figure_x;        // a loop's x quantity (t otherwise)
  LabUse lab;               // its use in the browser lab
  constexpr bool is(Role r) const { return (roles & r) != 0; }
};

inline constexpr std::array<QuantityInfo, quantity_count> quantity_table = {{
    {Quantity::t, "t", "s", "time", "t", 1, "s", Needs::always, history, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::phase, "phase", "", "phase (pivot: -1 left, 0 full contact, +1 right)", "phase", 1, "", Needs::always,
     history, {}, Quantity::t, {}},
    {Quantity::u_top, "u_N", "m", "elastic top displacement", "u_N", 1000, "mm", Needs::elasticity, history, {}, Quantity::t, {}},
    {Quantity::theta, "theta", "rad", "rocking angle", "{/Symbol q}", 1, "rad", Needs::rocking, history | peak, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::theta_over_alpha, "theta_over_alpha", "-", "rocking angle over slenderness",
     "{/Symbol q}/{/Symbol a}_{cg}", 1, "-", Needs::rocking, history | peak | study, {FigureRole::response, 4}, Quantity::t, {LabRole::chart, 2}},
    {Quantity::theta_dot, "theta_dot", "rad/s", "rocking velocity", "d{/Symbol q}/dt", 1, "rad/s", Needs::rocking,
     history | peak | study, {}, Quantity::t, {}},
    {Quantity::delta_t, "delta_t", "-", "total top drift", "{/Symbol d}_t", 100, "%", Needs::always,
     history | peak | study, {FigureRole::response, 2}, Quantity::t, {LabRole::chart, 3}},
    {Quantity::delta_e, "delta_e", "-", "elastic top drift", "{/Symbol d}_e", 100, "%", Needs::elasticity,
     history | peak | study, {FigureRole::response, 3}, Quantity::t, {LabRole::chart, 3}},
    {Quantity::damper_d, "damper_d", "m", "damper elongation (signed by the pivot)", "d", 1000, "mm", Needs::dampers,
     history | peak | study, {}, Quantity::t, {}},
    {Quantity::damper_F, "damper_F", "N", "damper force (signed by the pivot)", "F_{hd}", 1e-3, "kN", Needs::dampers,
     history | peak, {FigureRole::loop, 9}, Quantity::damper_d, {}},
    {Quantity::base_shear, "base_shear", "V_ref", "base shear", "V/V_{ref}", 1, "-", Needs::elasticity,
     history | peak | study, {}, Quantity::t, {}},
    {Quantity::base_moment, "base_moment", "M_ref", "base moment", "M/M_{ref}", 1, "-", Needs::elasticity,
     history | peak | study, {}, Quantity::t, {LabRole::chart, 4}},
    {Quantity::mid_shear, "mid_shear", "V_ref", "mid-height shear", "V/V_{ref}", 1, "-", Needs::elasticity,
     history | peak | study, {}, Quantity::t, {}},
    {Quantity::mid_moment, "mid_moment", "M_ref", "mid-height moment", "M/M_{ref}", 1, "-", Needs::elasticity,
     history | peak | study, {}, Quantity::t, {}},
    {Quantity::a_top, "a_N", "m/s2", "top absolute acceleration (along the structure's width)", "a_N", 1 / 9.81, "g",
     Needs::elasticity, history | peak | study, {}, Quantity::t, {}},
    {Quantity::a_g, "a_g", "m/s2", "ground acceleration", "a_g", 1 / 9.81, "g", Needs::always, history,
     {FigureRole::excitation, 1}, Quantity::t, {LabRole::chart, 1, true}},
    {Quantity::a_v, "a_v", "m/s2", "vertical ground acceleration (upward)", "a_v", 1 / 9.81, "g", Needs::vertical,
     history, {}, Quantity::t, {LabRole::chart, 1, true}},
    {Quantity::device_moment, "M_dev", "N m", "devices' moment (signed as theta)", "M_{dev}", 1e-6, "MN m",
     Needs::devices, history, {FigureRole::loop, 8}, Quantity::theta, {LabRole::drawn, 0}},
    {Quantity::x_g, "x_g", "m", "ground displacement (a_g integrated from rest, no baseline correction)", "x_g", 1000,
     "mm", Needs::always, on_request, {}, Quantity::t, {LabRole::drawn, 0, true}},
    {Quantity::energy, "E", "J", "mechanical energy (kinetic + gravity + elastic)", "E", 1, "J", Needs::energy,
     on_request, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::work_ground, "W_ground", "J", "work done by the ground since the start", "W_{ground}", 1, "J",
     Needs::energy, on_request, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::work_viscous, "W_viscous", "J", "energy dissipated by viscous damping since the start", "W_{viscous}", 1,
     "J", Needs::energy, on_request, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::work_devices, "W_devices", "J", "work done on the devices since the start (stored + dissipated)",
     "W_{devices}", 1, "J", Needs::energy, on_request, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::work_impacts, "W_impacts", "J", "energy lost at impacts since the start", "W_{impacts}", 1, "J",
     Needs::energy, on_request, {}, Quantity::t, {LabRole::drawn, 0}},
    // A structure on rocking columns (MODEL.md 16): the columns' common
    // rocking angle (signed as theta), over their slenderness alpha, its rate, the cap
    // beam's horizontal displacement relative to the ground, and the smallest
    // of the columns' normal forces on the deck (compression > 0).
    {Quantity::columns_theta, "columns.theta", "rad", "columns' rocking angle", "{/Symbol q}_c", 1, "rad",
     Needs::columns, history | peak | study, {}, Quantity::t, {LabRole::drawn, 0}},
    {Quantity::columns_theta_over_alpha, "columns.theta_over_alpha", "-", "columns' rocking angle over their slenderness",
     "{/Symbol q}_c/{/Symbol a}_c", 1, "-", Needs::columns, history | peak | study, {FigureRole::response, 4},
     Quantity::t, {LabRole::chart, 2}},
    {Quantity::columns_theta_dot, "columns.theta_dot", "rad/s", "columns' rocking velocity", "d{/Symbol q}_c/dt", 1,
     "rad/s", Needs::columns, history | peak, {}, Quantity::t, {}},
    {Quantity::beam_x, "beam.x", "m", "cap beam's horizontal displacement (relative to the ground)", "x_b", 1000, "mm",
     Needs::columns, history | peak, {}, Quantity::t, {}},
    {Quantity::columns_top_force, "columns.top_force_min", "N", "smallest column-top contact force (compression > 0)",
     "N_{min}", 1e-3, "kN", Needs::columns, history, {}, Quantity::t, {}},
}};

constexpr const QuantityInfo& info(Quantity q) { return quantity_table[static_cast<std::size_t>(q)]; }
constexpr std::size_t index(Quantity q) { return static_cast<std::size_t>(q); }

namespace detail {
constexpr bool table_in_order() {
  for (std::size_t i = 0; i < quantity_count; ++i)
    if (static_cast<std::size_t>(quantity_table[i].id) != i) return false;
  return true;
}
static_assert(table_in_order(), "quantity_table must list the quantities in the order of Quantity");
template <Role R>
constexpr std::size_t count_with() {
  std::size_t n = 0;
  for (const QuantityInfo& q : quantity_table) n += q.is(R) ? 1 : 0;
  return n;
}
template <Role R>
constexpr auto list_with() {
  std::array<Quantity, count_with<R>()> out{};
  std::size_t k = 0;
  for (const QuantityInfo& q : quantity_table)
    if (q.is(R)) out[k++] = q.id;
  return out;
}
}  // namespace detail

// The quantities with a role, in the table's order.
inline constexpr auto peak_quantities = detail::list_with<peak>();
inline constexpr auto study_quantities = detail::list_with<study>();
inline constexpr auto history_quantities = detail::list_with<history>();

// A quantity by its name; the names of those with a role, for messages ("delta_t, delta_e, ...").
std::optional<Quantity> find_quantity(std::string_view name);
std::string quantity_names(Role role);

// What each device reports, under its scene name: "plates.elongation". Its
// work is int F de since the start, stored plus dissipated (MODEL.md 11's
// energy), the device's share of W_devices: on request, where the run tracks
// the energy balance.
enum class DeviceQuantity : unsigned char { elongation, force, work, count_ };
inline constexpr std::size_t device_quantity_count = static_cast<std::size_t>(DeviceQuantity::count_);
struct DeviceQuantityInfo {
  DeviceQuantity id;
  std::string_view name, unit, words, symbol;
  double figure_factor;
  std::string_view figure_unit;
  FigureUse figure;            // its panel in the response figure (every device's curves in one)
  DeviceQuantity figure_x;     // a loop's x quantity (of the same device)
  LabUse lab;                  // its use in the browser lab (each device's loop)
  unsigned char roles;         // Role bits
  constexpr bool is(Role r) const { return (roles & r) != 0; }
};
inline constexpr std::array<DeviceQuantityInfo, device_quantity_count> device_quantity_table = {{
    {DeviceQuantity::elongation, "elongation", "m", "elongation", "e", 1000, "mm", {}, DeviceQuantity::elongation,
     {LabRole::drawn, 0}, history | peak | study},
    {DeviceQuantity::force, "force", "N", "force", "F", 1e-3, "kN", {FigureRole::loop, 7}, DeviceQuantity::elongation,
     {LabRole::drawn, 0}, history | peak | study},
    {DeviceQuantity::work, "work", "J", "work done on it since the start", "W", 1, "J", {}, DeviceQuantity::elongation,
     {LabRole::drawn, 0}, on_request},
}};
// How many of a device's quantities a study reports (Role::study), and where
// one of them stands among those (its column within the device's group).
inline constexpr std::size_t device_study_count = [] {
  std::size_t n = 0;
  for (const DeviceQuantityInfo& d : device_quantity_table) n += d.is(study) ? 1 : 0;
  return n;
}();
constexpr std::size_t device_study_position(DeviceQuantity q) {
  std::size_t k = 0;
  for (const DeviceQuantityInfo& d : device_quantity_table) {
    if (d.id == q) return k;
    k += d.is(study) ? 1 : 0;
  }
  return k;
}
constexpr const DeviceQuantityInfo& info(DeviceQuantity q) { return device_quantity_table[static_cast<std::size_t>(q)]; }
std::string device_quantity_name(std::string_view device, DeviceQuantity q);  // "plates.elongation"

// What each node of the structure reports (nodes 1..N of MODEL.md 1), under "nodeK.NAME": recorders a user chooses, history
// columns on request. x and y are the node's displacement from its place at
// rest, horizontal and vertical (MODEL.md 7's delta_t H_N at the top):
//   x = s B (1 - cos th) + u_K cos th + H_K sin th,
//   y = -H_K (1 - cos th) - u_K sin th + s B sin th;
// x_abs adds the ground's displacement x_g (as OpenSees' absolute
// displacement adds its time series' integral); a_abs is the absolute
// acceleration along the structure's width (a_N's law at node K).
enum class NodeQuantity : unsigned char { u, x, y, x_abs, a_abs, count_ };
inline constexpr std::size_t node_quantity_count = static_cast<std::size_t>(NodeQuantity::count_);
// What each element reports (element E spans node E-1 to node E), under
// "elementE.NAME": its shear and its end moments from the elastic nodal forces
// f = K u (MODEL.md 7: V = sum of f_i above, M = sum f_i (H_i - h)), in N and
// N m as OpenSees' element recorders give them (base_shear and base_moment
// are element1's V and M_bottom over V_ref and M_ref).
enum class ElementQuantity : unsigned char { V, M_bottom, M_top, count_ };
inline constexpr std::size_t element_quantity_count = static_cast<std::size_t>(ElementQuantity::count_);

struct MemberQuantityInfo {
  std::string_view name, unit, words, symbol;
  double figure_factor;
  std::string_view figure_unit;
  Needs needs;
  LabUse lab;  // its use in the browser lab (for a node's: the lab chooses which nodes it sends)
};
inline constexpr std::array<MemberQuantityInfo, node_quantity_count> node_quantity_table = {{
    {"u", "m", "elastic displacement (in the foundation's frame)", "u", 1000, "mm", Needs::elasticity,
     {LabRole::drawn, 0}},
    {"x", "m", "horizontal displacement (from rest, relative to the ground)", "x", 1000, "mm", Needs::always, {}},
    {"y", "m", "vertical displacement (from rest)", "y", 1000, "mm", Needs::always, {}},
    {"x_abs", "m", "absolute horizontal displacement (x + x_g)", "x_{abs}", 1000, "mm", Needs::always, {}},
    {"a_abs", "m/s2", "absolute acceleration (along the structure's width)", "a", 1 / 9.81, "g", Needs::elasticity, {}},
}};
inline constexpr std::array<MemberQuantityInfo, element_quantity_count> element_quantity_table = {{
    {"V", "N", "shear", "V", 1e-3, "kN", Needs::elasticity, {}},
    {"M_bottom", "N m", "lower-end moment", "M_{bottom}", 1e-3, "kN m", Needs::elasticity, {}},
    {"M_top", "N m", "upper-end moment", "M_{top}", 1e-3, "kN m", Needs::elasticity, {}},
}};
constexpr const MemberQuantityInfo& info(NodeQuantity q) { return node_quantity_table[static_cast<std::size_t>(q)]; }
constexpr const MemberQuantityInfo& info(ElementQuantity q) {
  return element_quantity_table[static_cast<std::size_t>(q)];
}

// A node's or an element's quantity by name: "node3.x", "element1.V". The
// index is not checked against a structure here (1 .. 1000 parse).
struct MemberQuantityName {
  enum class Of : unsigned char { node, element } of = Of::node;
  int index = 1;
  unsigned char which = 0;  // a NodeQuantity or an ElementQuantity
  NodeQuantity node_quantity() const { return static_cast<NodeQuantity>(which); }
  ElementQuantity element_quantity() const { return static_cast<ElementQuantity>(which); }
  const MemberQuantityInfo& info() const;
  std::string name() const;  // "node3.x"
  bool operator==(const MemberQuantityName&) const = default;
};
std::optional<MemberQuantityName> parse_member_quantity(std::string_view text);

// What each joint above the base reports (a structure that rocks at more
// than one level, MODEL.md 15), under "jointK.NAME" for K = 1 .. J (joint 0,
// the base, keeps the scalar names theta, theta_dot, phase, theta_over_alpha):
// its rocking angle and rate relative to the face below, its phase, its
// friction demand |V| / N (the coefficient it needs not to slide; a rocking
// joint's N and V are its pivot's), and its angle over the slenderness of
// everything above it (the angle at which that part overturns about the
// joint's corner, alpha_j of MODEL.md 15). Roles as Role's; a peak is the
// run's absolute peak (summary.json's joints list), a study quantity an IDA
// and sweep column and a --limit.
enum class JointQuantity : unsigned char { theta, theta_dot, phase, friction, theta_over_alpha, count_ };
inline constexpr std::size_t joint_quantity_count = static_cast<std::size_t>(JointQuantity::count_);
struct JointQuantityInfo {
  std::string_view name, unit, words, symbol;
  double figure_factor;
  std::string_view figure_unit;
  unsigned char roles;  // Role bits
  FigureUse figure;     // its panel in the response figure
  LabUse lab;           // its use in the browser lab (every joint's curve in one chart)
  constexpr bool is(Role r) const { return (roles & r) != 0; }
};
inline constexpr std::array<JointQuantityInfo, joint_quantity_count> joint_quantity_table = {{
    {"theta", "rad", "rocking angle at the joint (relative to the face below)", "{/Symbol q}", 1, "rad",
     history | peak | study, {FigureRole::joints, 5}, {LabRole::chart, 5}},
    {"theta_dot", "rad/s", "rocking velocity at the joint", "d{/Symbol q}/dt", 1, "rad/s", history, {}, {}},
    {"phase", "", "phase at the joint (pivot: -1 left, 0 full contact, +1 right)", "phase", 1, "", history, {}, {}},
    {"friction", "-", "friction demand |V|/N at the joint", "|V|/N", 1, "-", on_request | peak | study, {}, {}},
    {"theta_over_alpha", "-", "rocking angle at the joint over the slenderness above it",
     "{/Symbol q}/{/Symbol a}", 1, "-", on_request | peak | study, {}, {}},
}};
constexpr const JointQuantityInfo& info(JointQuantity q) { return joint_quantity_table[static_cast<std::size_t>(q)]; }
struct JointQuantityName {
  int joint = 1;  // 1 .. J
  JointQuantity which = JointQuantity::theta;
  std::string name() const;  // "joint2.theta"
  bool operator==(const JointQuantityName&) const = default;
};
// "joint2.theta_dot"; nothing for another text (the joint is not checked
// against a scene here: 1 .. 1000 parse).
std::optional<JointQuantityName> parse_joint_quantity(std::string_view text);

// A reported quantity by name: a scalar one, a joint's above the base, or
// one of a named device's.
struct QuantityName {
  QuantityName(Quantity q) : scalar(q) {}  // NOLINT: a scalar quantity is its own name
  QuantityName(JointQuantityName j) : joint(j) {}  // NOLINT: so is a joint's
  QuantityName(std::string device_name, DeviceQuantity which) : device(std::move(device_name)), of(which) {}
  std::optional<Quantity> scalar;  // set for a scalar quantity
  std::optional<JointQuantityName> joint;  // set for a joint's
  std::string device;              // else the device's name ...
  DeviceQuantity of = DeviceQuantity::elongation;  // ... and which of its quantities
  std::string name() const;
  std::string_view unit() const;
};
// A figure's axis for the quantity, in gnuplot's enhanced text: its words
// without their note in parentheses, symbol and figure unit ("total top
// drift {/Symbol d}_t [%]", "damper elongation d [mm]"; a device's prefixed
// by its name), and the factor from its unit to the figure's.
std::string_view axis_words(std::string_view words);  // "damper force (signed by the pivot)" -> "damper force"
std::string axis_label(const QuantityName& q);
double figure_factor(const QuantityName& q);

// The same for a page that shows plain text (the browser lab): gnuplot's
// enhanced text as Unicode ("{/Symbol q}/{/Symbol a}_{cg}" -> "θ/α_cg");
// a quantity's symbol so ("θ_2" for joint 2's theta, "dampers F" for a
// device's force), its words without their note, its figure's unit, and its
// use in the lab.
std::string plain_text(std::string_view enhanced);
std::string plain_symbol(const QuantityName& q);
std::string_view plain_words(const QuantityName& q);
std::string_view figure_unit(const QuantityName& q);
LabUse lab_use(const QuantityName& q);

// "delta_t", "joint2.theta" or "NAME.elongation" / "NAME.force" (the joint
// and the device are not checked here: a scene's are not known); nothing
// for another text.
std::optional<QuantityName> parse_quantity_name(std::string_view text);

// The word a categorical quantity's value stands for ("contact", "rock+",
// "rock-" for the phase), empty for a number: history.csv writes it.
std::string_view value_label(Quantity q, double v);

// "name [unit]" (a history header field; "phase" alone).
std::string column_header(std::string_view name, std::string_view unit);

}  // namespace rocking
