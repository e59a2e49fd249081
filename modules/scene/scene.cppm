// rocking.scene: what a scene file says, read from TOML (toml++) into the plain
// constant data the physics modules take. A scene names the structure
// ([structure]: geometry, masses, sections, damping), how it meets the ground
// ([contact]), the paper's dampers ([damper]), any other devices at the
// rocking interface ([[device]] tables: kind = a law of rocking.devices, at =
// x [m] or "edges", kinematics, free_length, capacity, name, and the law's
// keys), the rocking columns it may stand on ([columns], MODEL.md 16: count,
// half_width, half_height, mass, spacing; structure.base_mass is then the cap
// beam) and its default excitation ([excitation]:
// an analytic pulse, a record file, or none), its initial state
// ([initial]: a release from a tilt, initial velocities and displacements)
// and what a run reports ([output]: the history's columns and interval);
// see data/scenes/*.toml for the keys,
// which are SI throughout. Any key can be overridden with `--set table.key=value`
// (the value is read as TOML, or as a bare string such as eq10); devices with
// `--set device+={...}` (add one), `--set device[I].key=value`, `--set device=[]`.
// Every error is an InputError of one line: where (file:line, or the --set
// text), which key, what is wrong.
module;
#include <rocking/eigen.hpp>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.scene;
export import rocking.geometry;
export import rocking.hysteresis;
export import rocking.devices;
export import rocking.columns;
export import rocking.contact;
export import rocking.ground_motion;
export import rocking.quantities;

export namespace rocking {

// The ground motion a scene runs under when no record is given on the command
// line: a record file (path relative to the scene file), an analytic pulse,
// or none (kind = "none": the ground stays still for `duration`, for free
// vibration and free rocking from the [initial] state; any pulse or record
// keys beside it are not used).
struct Excitation {
  bool none = false;                         // no ground motion
  std::string record;                        // empty: the pulse
  RecordOptions record_options;              // component, units, dt, scale of the record
  // The vertical motion (MODEL.md 14), upward, scaled as the record: a record
  // file (relative to the scene file), or a component of `record`'s own file
  // (vertical = "Up" beside record = "...V2A"); empty: none.
  std::string vertical;
  RecordOptions vertical_options;            // component, units
  PulseShape pulse = PulseShape::one_sine;
  double amplitude = 0;                      // pulse amplitude [m/s^2]
  double period = 0;                         // pulse period [s]; 0: no excitation
  double duration = 0;                       // simulated time [s]; 0: the motion's length
};

// The state at t = 0 ([initial]): a tilt theta about the pivot on its side
// (theta != 0 starts the run rocking), the rocking velocity, and the elastic
// displacements and velocities of nodes 1..N (empty: zero).
struct Initial {
  double theta = 0, theta_dot = 0;           // [rad], [rad/s]
  Eigen::VectorXd u, u_dot;                  // [m], [m/s]
};

// What a run of the scene reports ([output]): the history's columns by name
// (empty: the default columns; `simulate --history` replaces them) and the
// interval of its rows (0: the program's default; `--every` replaces it).
struct Output {
  std::vector<std::string> history;
  std::string origin;  // where history was given ("scene.toml:12: output.history"), for messages
  double interval = 0;  // [s]
};

// A joint above the base ([[joint]] tables, from the ground up; MODEL.md 15):
// the structure rocks there too. The segment above stands on node `node` of
// [structure] (1 .. N-1) with a slab of its own at that height.
struct JointTable {
  int node = 0;               // the node of [structure] it stands on
  double half_width = 0;      // B_j [m]
  double base_mass = 0;       // m0_j, the slab of the segment above [kg]
  double restitution = -1;    // r; < 0: "momentum", the momentum law of MODEL.md 15
  double initial_theta = 0;   // a release from a tilt [rad]
  double friction = std::numeric_limits<double>::infinity();  // the friction coefficient the run checks |V|/N against
  bool rigid = false;         // the segment above is rigid (default: as [structure])
};

struct Scene {
  std::string name;
  std::string description;
  std::string source;  // file path, or "embedded:christchurch_chimney.toml"
  Structure structure;
  Contact contact;
  Damper damper;       // damper.enabled = false when the scene has none
  std::vector<Device> devices;  // the [[device]] tables, in order
  // [columns]: the structure stands on rocking columns (MODEL.md 16;
  // checked as make_columns requires). [contact] then applies to the
  // columns: restitution "momentum" (or eq10, the same law: 16's r for a
  // rigid deck) or a number; contact.rocking = false holds them down.
  std::optional<ColumnGroup> columns;
  // Per device of `devices`: the segment its upper anchor is on with joints
  // ([[device]] segment, 0 .. J; -1: the top segment), and the segment its
  // lower anchor is on ([[device]] from_segment, 0 .. J-1; -1: the ground).
  std::vector<int> device_segments;
  std::vector<int> device_from_segments;
  // Per device of `devices`: the joint it stands across ([[device]] joint,
  // 0 .. J, 0 the base; -1: not given, the base for a device that is not a
  // tendon).
  std::vector<int> device_joints;
  std::vector<JointTable> joints;  // the [[joint]] tables, from the ground up
  bool momentum_base = false;      // [contact] restitution = "momentum"
  double base_friction = std::numeric_limits<double>::infinity();  // [contact] friction
  // The structure rocks by the chain's equations (MODEL.md 15): joints, or
  // the momentum law at its rocking base (not on columns, which take it as
  // their own; on a fixed base without joints it has no impacts to rule).
  bool jointed() const { return !columns && (!joints.empty() || (momentum_base && contact.rocking)); }
  Excitation excitation;
  Initial initial;
  Output output;
};

// Every device of the scene: the [damper]'s two (edge_dampers) then the
// [[device]] tables'.
std::vector<Device> scene_devices(const Scene& scene);

// A device as the scene names it (Device::group): a [[device]] table's one
// device, or two for at = "edges", or the [damper]'s pair, named "damper".
// Studies, the lab and Python list devices by these names and run without
// one by `removal`, the --set text `device-=NAME` (which takes the
// [damper] too).
struct DeviceGroup {
  std::string name;
  std::vector<Device> devices;
  std::string law;                  // its law's name
  bool dissipates = false;          // its law's trait (rocking.devices)
  const char* prestress_key = nullptr;  // its law's prestress key, or nullptr
  double prestress = 0;             // that key's value [N]
  std::optional<std::size_t> table; // its [[device]] index (device[I].KEY=VALUE); none for the [damper]
  std::string removal;              // "device-=NAME"
};
std::vector<DeviceGroup> device_groups(const Scene& scene);

// The chain of a scene with joints (MODEL.md 15, rocking.chain): [structure]
// split at the joints' nodes, each device a tendon from the ground at x to
// the top of its segment (an elastic law, vertical kinematics), each joint's
// restitution, initial tilt, friction limit and overturning angle (the
// slenderness about its corner of everything above it). InputError for what
// the chain does not model (a flexible segment on a flexible one, the
// [damper], a device other than an elastic vertical one, eq9, initial u).
JointedModel jointed_model(const Scene& scene);

// The model the scene describes (rocking.contact), with energy accumulators
// when asked; `extra` devices act after the scene's own. A scene with joints
// carries its chain (ContactModel::jointed), a scene on [columns] its
// columns (ContactModel::on_columns, with its devices between the ground and
// the beam; InputError for eq9).
ContactModel make_contact_model(const Scene& scene, bool track_energy, std::vector<Device> extra = {});

// The scene's excitation as a ground motion (reads the record if it names
// one, and its vertical motion with it).
// InputError if the scene has none.
GroundMotion default_ground_motion(const Scene& scene);
// The factor [excitation] scale puts on that motion (1 for none).
double excitation_scale(const Scene& scene);

// Reads a scene file and applies overrides ("table.key=value") in order.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

// The scene file (path; empty: the embedded chimney) with the overrides
// applied, as TOML text: what load_scene reads. InputError as load_scene.
// A record named by a relative path stays relative to the scene file's folder.
std::string scene_toml(const std::string& path, const std::vector<std::string>& overrides = {});

// The Christchurch chimney, embedded in the program at build time.
Scene load_default_scene(const std::vector<std::string>& overrides = {});
std::string_view default_scene_text();

}  // namespace rocking
