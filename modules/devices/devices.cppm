// rocking.devices: devices joining the foundation to the rocking base
// (MODEL.md 11): post-tensioned tendons, viscous dampers, yielding metallic
// dampers. A device is an anchor on the base at x (-B <= x <= B from the
// centre line), a kinematics that turns the tilt into an elongation, a force
// law F(e, e', z) with an optional internal state z, and optionally a
// capacity e_u at which it fractures.
// Kinematics, rocking about pivot p (s = sign(p)) with lever arm l = B - s x:
//   chord (the paper's damper):  e = 2 l sin(|th| / 2),  de/d|th| = l cos(th / 2);
//   vertical (free length L):    e = sqrt((L + l sin|th|)^2 + (l (1 - cos th))^2) - L,
//                                de/d|th| = l ((L + l sin|th|) cos th + l (1 - cos th) sin|th|) / (e + L);
//   in both e' = (de/d|th|) s th', and the device adds -F de/dth = -s F de/d|th|
//   to the rocking equation. The paper's edge damper is a chord device at
//   x = -s B (l = 2B): e = 4B sin(|th|/2).
// Laws, one file each (law_NAME.cppm, a partition of this module) and one
// entry in DeviceLaw below (`rocking fit --help` lists them). Each says its scene
// keys (LawParameter), so that the scene reader reads any law without
// knowing it. The physics knows no I/O: parameters arrive as numbers.
module;
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>
export module rocking.devices;
export import rocking.geometry;
export import rocking.hysteresis;
export import :parameters;
export import :bouc_wen;
export import :elastic;
export import :viscous;
export import :friction;
export import :gap;
export import :kelvin;

export namespace rocking {

// The registered laws. A new law: its file law_NAME.cppm, its
// `export import :NAME;` above and its type here.
using DeviceLaw = std::variant<BoucWenLaw, ElasticLaw, ViscousLaw, FrictionLaw, GapLaw, KelvinLaw>;

// beam: a device between the ground and the cap beam of a structure on
// rocking columns (MODEL.md 16; rocking.columns' beam_device_stretch), which
// the columns' run takes; a rocking base of its own has none.
enum class Kinematics { chord, vertical, beam };

struct DeviceGeometry {
  double x = 0;                          // anchor on the base [m], -B..B (beam: the ground anchor's x from the frame's centre line)
  Kinematics kinematics = Kinematics::chord;
  double free_length = 0;                // L of a vertical device [m]
  double beam_x = 0;                     // beam: the anchor on the beam's underside [m] from the centre line
  double ground_y = 0;                   // beam: the ground anchor's height above the columns' bottoms [m]
};

struct Device {
  std::string name;                      // names its outputs
  DeviceGeometry geometry;
  DeviceLaw law;
  double capacity = 0;                   // e_u [m]: fractures there; 0: never
  bool edge_damper = false;              // one of the paper's [damper] pair: reported also as damper_d, damper_F
  // The scene's name for it, by which studies, the lab and Python list and
  // remove devices: its [[device]] table's name (one table at = "edges" makes
  // two devices of one group), or "damper" for the paper's pair; empty: its name.
  std::string group;
};

// The elongation of a device and its derivative with respect to |theta|
// while rocking about pivot p.
struct Stretch {
  double e = 0;          // [m]
  double de_dtheta = 0;  // de / d|theta| [m]
};
inline double lever_arm(const DeviceGeometry& g, double half_width, Pivot p) { return half_width - sign(p) * g.x; }
// Inline: it runs in every rocking right-hand side.
inline Stretch stretch(const DeviceGeometry& g, double half_width, Pivot p, const Tilt& tilt) {
  const double l = lever_arm(g, half_width, p);
  if (g.kinematics == Kinematics::chord) return {2.0 * l * std::abs(tilt.sin_half), l * tilt.cos_half};
  const double L = g.free_length, sin_abs = std::abs(tilt.sin()), cos_th = tilt.cos();
  const double rise = L + l * sin_abs, slide = l * (1.0 - cos_th);
  const double length = std::sqrt(rise * rise + slide * slide);
  return {length - L, l * (rise * cos_th + slide * sin_abs) / length};
}

// The law's numbers (see each law's file); inline, for the right-hand side.
inline int law_states(const DeviceLaw& law) {
  return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::states; }, law);
}
inline double law_force(const DeviceLaw& law, double e, double e_dot, double z) {
  return std::visit([&](const auto& l) { return l.force(e, e_dot, z); }, law);
}
inline double law_rate(const DeviceLaw& law, double e, double e_dot, double z) {  // z'
  return std::visit([&](const auto& l) { return l.rate(e, e_dot, z); }, law);
}
// Force and z' together: one dispatch on the law where the right-hand side
// needs both.
struct LawResponse {
  double F = 0, rate = 0;
};
inline LawResponse law_force_and_rate(const DeviceLaw& law, double e, double e_dot, double z) {
  return std::visit([&](const auto& l) { return LawResponse{l.force(e, e_dot, z), l.rate(e, e_dot, z)}; }, law);
}
inline double law_stored_energy(const DeviceLaw& law, double e, double z) {
  return std::visit([&](const auto& l) { return l.stored_energy(e, z); }, law);
}
inline const char* law_name(const DeviceLaw& law) {
  return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::name; }, law);
}
// A law's declared traits, which the studies (a scene's default variants),
// the lab (its device list) and the figures read instead of the law's name:
// whether it dissipates energy (a damper: a study's variant runs without it),
// and the scene key of its prestress, the force it holds at zero elongation
// (a tendon: the lab's prestress slider), or nullptr.
inline bool law_dissipates(const DeviceLaw& law) {
  return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::dissipates; }, law);
}
inline const char* law_prestress_key(const DeviceLaw& law) {
  return std::visit([](const auto& l) { return std::decay_t<decltype(l)>::prestress_key; }, law);
}
inline double law_force_at_rest(const DeviceLaw& law, double z) {
  return std::visit([&](const auto& l) { return l.force_at_rest(z); }, law);
}
inline double law_stiffness(const DeviceLaw& law) {  // dF/de at rest, pre-yield
  return std::visit([](const auto& l) { return l.stiffness(); }, law);
}
inline double law_yielded_stiffness(const DeviceLaw& law) {  // dF/de once yielded (the same for a law that does not yield)
  return std::visit([](const auto& l) { return l.yielded_stiffness(); }, law);
}

// The devices linearised about theta = 0 while rocking about pivot p
// (MODEL.md 8 and 11): the rocking stiffness they add, sum_k k_k (de_k/dth)^2
// (de/d|th| = l at theta = 0 for both kinematics), with each law's stiffness
// at rest and once yielded; and the moment their forces at rest hold against
// uplift, sum_k F_k(e = 0) l_k (a tendon's P0 l). States z at 0.
struct RockingStiffness {
  double at_rest = 0, yielded = 0;  // [N m/rad]
  double held_moment = 0;           // [N m]
  bool any = false;                 // some device acts about this pivot
};
RockingStiffness rocking_stiffness(const std::vector<Device>& devices, double half_width, Pivot p);

// The paper's [damper] (MODEL.md 5) as devices: a Bouc-Wen chord device at
// each edge, "damper_left" at x = -B (stretched about pivot +1, l = 2B) and
// "damper_right" at x = +B.
std::vector<Device> edge_dampers(const Damper& damper, double half_width);

// The registered laws: their names, summaries and parameters.
struct LawInfo {
  std::string name, summary;
  std::vector<LawParameter> parameters;
};
std::vector<LawInfo> device_laws();
// Whether a law parameter takes v (finite, within its bounds), and its bounds
// in words: "> 0 and <= 1e+13 [N/m]".
bool within(const LawParameter& p, double v);
std::string bounds_text(const LawParameter& p);
// A law by name from its parameters: value(key) gives a parameter's value, or
// nothing for its default. InputError for an unknown law (listing the laws)
// or a value out of range (naming the key and its bound).
DeviceLaw make_law(std::string_view name, const std::function<std::optional<double>(std::string_view)>& value);

}  // namespace rocking
