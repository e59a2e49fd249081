module;
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <fmt/format.h>
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cctype>
#include <cstdlib>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <variant>
#include <vector>
module rocking.lab;
import rocking.errors;
import rocking.records;

namespace rocking {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr std::string_view default_scene = "christchurch_chimney";

// nlohmann's message without its "[json.exception.KIND.ID] " prefix.
std::string json_message(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  const auto end = what.find("] ");
  return what.starts_with("[json.exception") && end != std::string::npos ? what.substr(end + 2) : what;
}

// JSON text, any invalid UTF-8 (a record's header, a cut name) replaced.
std::string text(const json& j) { return j.dump(-1, ' ', false, json::error_handler_t::replace); }

// The files under `dir` whose name passes `keep`, by their path relative to
// it (forward slashes), sorted; none when the folder is missing.
template <class Keep>
std::vector<std::pair<std::string, std::string>> files_under(const fs::path& dir, Keep keep) {
  std::vector<std::pair<std::string, std::string>> out;
  std::error_code ec;
  if (dir.empty() || !fs::is_directory(dir, ec)) return out;
  for (auto it = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file(ec) || !keep(it->path())) continue;
    out.emplace_back(it->path().lexically_relative(dir).generic_string(), it->path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The request is an object whose keys are all known to the endpoint.
void check_keys(const json& r, std::string_view endpoint, std::initializer_list<std::string_view> known) {
  if (!r.is_object()) throw InputError(fmt::format("{}: the request must be a JSON object", endpoint));
  for (const auto& [key, value] : r.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw InputError(fmt::format("{}: unknown key '{}' (known: {})", endpoint, key.substr(0, 40),
                                   fmt::join(known, ", ")));
}

// The key's value: a string (absent or null: `fallback`).
std::string text_of(const json& r, const char* key, std::string fallback = {}) {
  const auto it = r.find(key);
  if (it == r.end() || it->is_null()) return fallback;
  if (!it->is_string()) throw InputError(fmt::format("{}: must be a string", key));
  std::string s = it->get<std::string>();
  if (s.size() > 256) throw InputError(fmt::format("{}: {} characters (at most 256)", key, s.size()));
  return s;
}

std::optional<double> number_of(const json& r, const char* key) {
  const auto it = r.find(key);
  if (it == r.end() || it->is_null()) return std::nullopt;
  if (!it->is_number()) throw InputError(fmt::format("{}: must be a number", key));
  const double v = it->get<double>();
  if (!std::isfinite(v)) throw InputError(fmt::format("{}: must be a finite number", key));
  return v;
}

// "set": the scene's overrides exactly as --set takes them ("damper.thickness=1.5").
std::vector<std::string> overrides_of(const json& r, std::size_t limit) {
  const auto it = r.find("set");
  if (it == r.end() || it->is_null()) return {};
  if (!it->is_array()) throw InputError("set: must be a list of TABLE.KEY=VALUE texts, as --set takes them");
  if (it->size() > limit) throw InputError(fmt::format("set: {} overrides (at most {})", it->size(), limit));
  std::vector<std::string> out;
  for (const json& o : *it) {
    if (!o.is_string()) throw InputError("set: every item must be a TABLE.KEY=VALUE text, as --set takes it");
    std::string s = o.get<std::string>();
    if (s.size() > 256) throw InputError(fmt::format("set: an override of {} characters (at most 256)", s.size()));
    out.push_back(std::move(s));
  }
  return out;
}

// The history the page draws: the columns of the quantities the schema
// gives a use in the lab (rocking.quantities' LabUse) that the model reports:
// of its default history (a joint's, a device's among them), then those it
// gives on request (the ground's displacement, the energy balance's terms,
// each device's work),
// then the nodes' elastic displacements (to draw the structure bent; at
// most 16 of them).
std::vector<std::string> lab_columns(const ContactModel& model) {
  std::vector<std::string> out;
  for (const std::string& name : history_columns(model).names())
    if (const std::optional<QuantityName> q = parse_quantity_name(name); q && lab_use(*q).role != LabRole::none)
      out.push_back(name);
  const Presence has = presence(model);
  for (const QuantityInfo& q : quantity_table)
    if (q.is(Role::on_request) && !q.is(Role::history) && q.lab.role != LabRole::none && has.has(q.needs))
      out.emplace_back(q.name);
  // Each device's work, for the energy view's bar per device.
  for (const Device& d : model.devices)
    for (const DeviceQuantityInfo& q : device_quantity_table)
      if (q.is(Role::on_request) && q.lab.role != LabRole::none && has.energy) out.push_back(device_quantity_name(d.name, q.id));
  // The bending as the page draws it: every node up to 16, else 16 evenly
  // spaced up to the top (the page interpolates between them; a 64-node
  // tower's history is then a third of its size).
  constexpr Eigen::Index drawn_nodes = 16;
  const Eigen::Index n = model.body.structure.heights.size();
  const MemberQuantityInfo& u = info(NodeQuantity::u);
  if (!model.body.structure.rigid && !model.jointed && u.lab.role != LabRole::none && has.has(u.needs))
    for (Eigen::Index j = 1; j <= std::min(n, drawn_nodes); ++j)
      out.push_back(fmt::format("node{}.{}", n <= drawn_nodes ? j : (j * n + drawn_nodes - 1) / drawn_nodes, u.name));
  return out;
}

// What the page draws a column as, from the schema: its name, unit, words,
// plain-text symbol, display unit and the factor to it, and its use in the
// lab ("drawn" or "chart", with the chart's number).
json column_schema(const std::string& name) {
  json out{{"name", name}};
  const auto use = [](LabUse u) { return u.role == LabRole::chart ? "chart" : u.role == LabRole::drawn ? "drawn" : "none"; };
  if (const std::optional<QuantityName> q = parse_quantity_name(name)) {
    out.update({{"unit", q->unit()},
                {"words", plain_words(*q)},
                {"symbol", plain_symbol(*q)},
                {"display_unit", figure_unit(*q)},
                {"factor", figure_factor(*q)},
                {"use", use(lab_use(*q))},
                {"chart", lab_use(*q).chart},
                {"ground", lab_use(*q).ground}});
  } else if (const std::optional<MemberQuantityName> m = parse_member_quantity(name)) {
    const MemberQuantityInfo& i = m->info();
    out.update({{"unit", i.unit},
                {"words", axis_words(i.words)},
                {"symbol", fmt::format("{}_{}", plain_text(i.symbol), m->index)},
                {"display_unit", i.figure_unit},
                {"factor", i.figure_factor},
                {"use", use(i.lab)},
                {"chart", i.lab.chart},
                {"ground", i.lab.ground}});
  }
  return out;
}

// Keeps the history's columns in memory.
class Columns : public HistoryObserver {
 public:
  Columns(const ContactModel& model, HistoryColumns layout) : HistoryObserver(model, std::move(layout)) {
    values.resize(columns().size());
  }
  std::vector<std::vector<double>> values;

 protected:
  void row(const Response&, const std::vector<double>& v) override {
    for (std::size_t i = 0; i < v.size(); ++i) values[i].push_back(v[i]);
  }
};

// {"name": [v, ...], ...} with six significant digits, as %.6g (null where
// NaN: a broken device). std::to_chars: the history is most of an answer.
void append_history(std::string& out, const std::vector<std::string>& names,
                    const std::vector<std::vector<double>>& values) {
  std::size_t count = 0;
  for (const auto& c : values) count += c.size();
  out.reserve(out.size() + 14 * count + 32 * names.size());
  char number[32];
  out += '{';
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (c > 0) out += ',';
    out += text(json(names[c]));
    out += ":[";
    bool first = true;
    for (double v : values[c]) {
      if (!first) out += ',';
      first = false;
      if (std::isfinite(v)) {
        const auto end = std::to_chars(number, number + sizeof number, v, std::chars_format::general, 6).ptr;
        out.append(number, end);
      } else {
        out += "null";
      }
    }
    out += ']';
  }
  out += '}';
}

// What the page draws the structure from.
json structure_json(const Scene& scene, const ContactModel& model) {
  json devices = json::array();
  for (const Device& d : scene_devices(scene))
    devices.push_back({{"name", d.name},
                       {"law", law_name(d.law)},
                       {"x", d.geometry.x},
                       {"vertical", d.geometry.kinematics == Kinematics::vertical},
                       {"free_length", d.geometry.free_length},
                       {"beam", d.geometry.kinematics == Kinematics::beam},  // on columns: from the ground to the cap beam
                       {"beam_x", d.geometry.beam_x},
                       {"ground_y", d.geometry.ground_y}});
  json units = json::object();
  for (const QuantityRow& q : quantity_rows(model)) units[q.name] = q.unit;
  const Structure& s = model.body.structure;
  // A structure with joints (MODEL.md 15): each segment's base (the joint it
  // stands on: its height and half-width) and nodes, from the ground up; a
  // tendon's upper end is on a segment, at a height above the ground at
  // rest, and its lower end on the ground or on a segment (its from_segment,
  // at its base's height at rest); a device across joint j >= 1 joins
  // segment j-1 to segment j the same way (its joint, segment, from_segment).
  json segments = json::array();
  if (model.jointed) {
    const ChainData& chain = model.jointed->chain.data;
    for (const ChainSegment& g : chain.segments)
      segments.push_back({{"base_height", g.base_height},
                          {"half_width", g.half_width},
                          {"heights", std::vector<double>(g.heights.data(), g.heights.data() + g.heights.size())}});
    // A device across joint j >= 1: from the face below (segment j-1 at the
    // joint's height) to segment j's base, or to the height of its free
    // length above it (vertical), as a base device is drawn on a block.
    for (const JointedModel::UpperDevices& u : model.jointed->upper)
      for (std::size_t k : u.devices) {
        const Device& dev = model.devices[k];
        for (json& d : devices) {
          if (d["name"].get<std::string>() != dev.name) continue;
          const double h = chain.segments[static_cast<std::size_t>(u.joint)].base_height;
          d["joint"] = u.joint;
          d["segment"] = u.joint;
          d["top"] = h + (dev.geometry.kinematics == Kinematics::vertical ? dev.geometry.free_length : 0.0);
          d["from_segment"] = u.joint - 1;
          d["bottom"] = h;
        }
      }
    for (json& d : devices) {
      const auto& names = model.jointed->tendons;
      const auto at = std::find(names.begin(), names.end(), d["name"].get<std::string>());
      if (at == names.end()) continue;
      const ChainAnchor& to = chain.tendons[static_cast<std::size_t>(at - names.begin())].to;
      if (to.segment < 0) continue;
      d["segment"] = to.segment;
      d["top"] = chain.segments[static_cast<std::size_t>(to.segment)].base_height + to.z;
      const ChainAnchor& from = chain.tendons[static_cast<std::size_t>(at - names.begin())].from;
      if (from.segment >= 0) {
        d["from_segment"] = from.segment;
        d["bottom"] = chain.segments[static_cast<std::size_t>(from.segment)].base_height + from.z;
      }
    }
  }
  // A structure on rocking columns (MODEL.md 16): the columns, alike, and
  // the distance between the outer ones' axes; the structure stands on the
  // cap beam, which rests on the column tops.
  json columns = nullptr;
  if (scene.columns) {
    const ColumnGroup& c = *scene.columns;
    columns = {{"count", c.count}, {"half_width", c.half_width}, {"half_height", c.half_height}, {"spacing", c.spacing}};
  }
  return {{"name", scene.name},
          {"units", units},
          {"rigid", s.rigid},
          {"rocking", scene.contact.rocking},
          {"half_width", s.half_width},
          {"heights", std::vector<double>(s.heights.data(), s.heights.data() + s.heights.size())},
          {"segments", segments},
          {"columns", columns},
          {"devices", devices}};
}

struct Ran {
  RunResult result;
  RunLabel label;
  json structure;  // structure_json of the run's own model
  std::vector<std::string> names;
  std::vector<std::vector<double>> values;
};

// A deadline for a request's runs: RunOptions::stop, and the error it ends them with.
struct Deadline {
  std::chrono::steady_clock::time_point at;
  explicit Deadline(double seconds)
      : at(std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>(seconds))) {}
  bool passed() const { return std::chrono::steady_clock::now() > at; }
};

void check_result(const RunResult& r, const Deadline& deadline, const LabLimits& limits) {
  if (r.outcome != Outcome::failed) return;
  if (deadline.passed())
    throw RunError(fmt::format("the runs took more than {:g} s of computing (stopped at t = {:.3g} s): ask for "
                               "less (a shorter duration, fewer nodes, fewer levels)",
                               limits.seconds, r.t_end));
  throw RunError(r.failure);
}

Ran run_once(const RunSpec& spec, const LabLimits& limits, const Deadline& deadline) {
  PreparedRun prepared = prepare_run(spec);
  prepared.options.stop = [&deadline] { return deadline.passed(); };
  prepared.options.final_row = true;  // the energy bars' last frame is the summary's totals
  const double duration = prepared.options.duration > 0 ? prepared.options.duration : prepared.motion.duration();
  if (duration > limits.duration)
    throw InputError(fmt::format("the motion lasts {:g} s, longer than the {:g} s the lab simulates: choose a "
                                 "shorter record (or ask for a shorter duration)",
                                 duration, limits.duration));
  if (duration / prepared.options.output_interval > static_cast<double>(limits.history_rows))
    throw InputError(fmt::format("every {:g}: {:.0f} rows of history (at most {} here; choose a larger interval)",
                                 prepared.options.output_interval, duration / prepared.options.output_interval,
                                 limits.history_rows));
  Columns columns(prepared.model, prepared.columns);
  RunResult result = simulate(prepared.model, prepared.motion, prepared.options, &columns);
  check_result(result, deadline, limits);
  return {std::move(result), prepared.label, structure_json(spec.scene, prepared.model), columns.columns().names(),
          std::move(columns.values)};
}

}  // namespace

Lab::Lab(LabFolders folders, LabLimits limits) : folders_(std::move(folders)), limits_(limits) {
  for (auto& [id, path] : files_under(folders_.scenes, [](const fs::path& p) { return p.extension() == ".toml"; }))
    scenes_.push_back({id.substr(0, id.size() - 5), path});
  static constexpr std::string_view not_records[] = {".md", ".txt", ".json", ".toml", ".py", ".sh"};
  for (auto& [id, path] : files_under(folders_.records, [](const fs::path& p) {
         const std::string ext = lower(p.extension().string());
         return std::find(std::begin(not_records), std::end(not_records), ext) == std::end(not_records) &&
                !p.filename().string().starts_with(".");
       }))
    records_.push_back({id, path});
}

const Lab::SceneEntry& Lab::scene_entry(const json& r) const {
  const std::string id = text_of(r, "scene", std::string(default_scene));
  for (const SceneEntry& e : scenes_)
    if (e.id == id) return e;
  throw InputError(fmt::format("scene '{}': not one of the lab's scenes (GET /api/scenes lists them)", id));
}

Scene Lab::scene_of(const json& r, const std::vector<std::string>& overrides) const {
  Scene scene = load_scene(scene_entry(r).path, overrides);
  const auto nodes = static_cast<std::size_t>(scene.structure.heights.size());
  if (nodes > limits_.nodes)
    throw InputError(fmt::format("scene '{}': {} nodes (at most {} here)", scene.name, nodes, limits_.nodes));
  return scene;
}

std::string Lab::record_path(const std::string& id) const {
  for (const RecordEntry& e : records_)
    if (e.id == id) return e.path;
  if (id.starts_with("upload/")) {
    const std::lock_guard lock(mutex_);
    if (std::find(uploads_.begin(), uploads_.end(), id) != uploads_.end()) return id;  // read already: in memory
    throw InputError(fmt::format("record '{}': no such upload (uploads are kept while the server runs, the last {})",
                                 id, limits_.uploads));
  }
  throw InputError(fmt::format("record '{}': not one of the lab's records (GET /api/records lists them)", id));
}

std::shared_ptr<const GroundMotion> Lab::motion(const std::string& id, const std::string& component) const {
  const std::string path = record_path(id);
  if (id.starts_with("upload/")) {
    if (!component.empty())
      throw InputError(fmt::format("component: an upload's component is chosen when it is uploaded"));
    const std::lock_guard lock(mutex_);
    return motions_.at(id + '\n');
  }
  const std::string key = id + '\n' + component;
  {
    const std::lock_guard lock(mutex_);
    if (const auto it = motions_.find(key); it != motions_.end()) return it->second;
  }
  RecordOptions ro;
  ro.component = component;
  auto m = std::make_shared<const GroundMotion>(read_record(path, ro));
  const std::lock_guard lock(mutex_);
  return motions_.emplace(key, std::move(m)).first->second;
}

json Lab::scenes() const {
  json out = json::array();
  for (const SceneEntry& e : scenes_) {
    json item{{"id", e.id}};
    try {
      const Scene s = load_scene(e.path);
      // The devices as the scene names them, the [damper] among them: each
      // with its law's traits, the override that removes it, and the one
      // that sets its prestress (device[I].KEY=VALUE) when its law has one.
      json devices = json::array();
      for (const DeviceGroup& g : device_groups(s)) {
        json prestress = nullptr;
        if (g.prestress_key != nullptr && g.table)
          prestress = {{"value", g.prestress}, {"set", fmt::format("device[{}].{}", *g.table, g.prestress_key)}};
        json members = json::array();
        for (const Device& d : g.devices) members.push_back(d.name);
        devices.push_back({{"name", g.name}, {"law", g.law}, {"dissipates", g.dissipates}, {"prestress", prestress},
                           {"remove", g.removal}, {"members", members}});
      }
      // A fixed-base twin where the study has one (not for a rigid block, a
      // structure with joints or one on columns: rocking.study's default_variants).
      const std::vector<Variant> variants = default_variants(s);
      const bool fixed_base = std::ranges::any_of(variants, [](const Variant& v) { return v.name == "fixed-base"; });
      item.update({{"name", s.name},
                   {"description", s.description},
                   {"rigid", s.structure.rigid},
                   {"fixed_base", fixed_base},
                   {"nodes", s.structure.heights.size()},
                   {"damper", s.damper.enabled},
                   {"devices", devices},
                   {"excitation", s.excitation.none       ? "none"
                                  : s.excitation.record.empty() ? fmt::format("{} pulse, {:.3g} g, {:.3g} s",
                                                                              s.excitation.pulse == PulseShape::ricker ? "Ricker" : "one-sine",
                                                                              s.excitation.amplitude / gravity,
                                                                              s.excitation.period)
                                                                : "its record"},
                   {"pulse", s.excitation.none || !s.excitation.record.empty()
                                 ? json(nullptr)
                                 : json{{"amplitude_g", s.excitation.amplitude / gravity}, {"period", s.excitation.period}}},
                   {"usable", static_cast<std::size_t>(s.structure.heights.size()) <= limits_.nodes}});
    } catch (const InputError& err) {
      item.update({{"name", e.id}, {"error", err.what()}, {"usable", false}});
    }
    out.push_back(std::move(item));
  }
  return out;
}

json Lab::records() const {
  {
    const std::lock_guard lock(mutex_);
    if (record_list_) return *record_list_;
  }
  json out = json::array();
  for (const RecordEntry& e : records_) {
    json item{{"id", e.id}};
    try {
      const std::shared_ptr<const GroundMotion> m = motion(e.id, "");
      item.update({{"name", describe_motion(*m)},
                   {"pga_g", m->peak() / gravity},
                   {"duration_s", m->duration()}});
    } catch (const InputError& err) {
      item.update({{"error", err.what()}});
    }
    out.push_back(std::move(item));
  }
  const std::lock_guard lock(mutex_);
  record_list_ = std::make_shared<const json>(out);
  return out;
}

json Lab::upload(const json& r) const {
  check_keys(r, "upload", {"name", "text", "component"});
  // The name, kept to letters, digits and . _ - (it names a file of the lab's own, and the record in titles).
  std::string name;
  for (char c : text_of(r, "name", "record"))
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-') name += c;
  while (name.starts_with('.')) name.erase(0, 1);
  if (name.empty()) name = "record";
  name = name.substr(0, 80);
  const auto text = r.find("text");
  if (text == r.end() || !text->is_string()) throw InputError("upload: text: give the record file's text");
  const std::string component = text_of(r, "component");
  // The readers take a path: the text goes to a file in a folder of the lab's own, read and removed at once.
  std::string folder = (fs::temp_directory_path() / fmt::format("rocking-lab-upload-{}-XXXXXX", ::getpid())).string();
  if (::mkdtemp(folder.data()) == nullptr) throw RunError("upload: could not make a temporary folder");
  const fs::path file = fs::path(folder) / name;
  std::shared_ptr<const GroundMotion> m;
  try {
    {
      std::ofstream out(file, std::ios::binary);
      out << text->get_ref<const std::string&>();
      if (!out) throw RunError("upload: could not write the temporary file");
    }
    RecordOptions ro;
    ro.component = component;
    ro.read_as = ReadAs::any;  // a vertical component is refused below, in the lab's words
    m = std::make_shared<const GroundMotion>(read_record(file.string(), ro));
    if (component_orientation(m->info().component) == Orientation::vertical)
      throw InputError(fmt::format("{} is the vertical component ({}) of its record; the lab shakes a structure "
                                   "sideways: upload a horizontal component (such as N-S or E-W) instead",
                                   file.string(), m->info().component));
  } catch (const InputError& e) {
    std::error_code ec;
    fs::remove_all(folder, ec);
    std::string message = e.what();  // named as the user named it, not by the temporary path
    for (auto at = message.find(file.string()); at != std::string::npos; at = message.find(file.string()))
      message.replace(at, file.string().size(), name);
    throw InputError("upload: " + message);
  }
  std::error_code ec;
  fs::remove_all(folder, ec);
  const std::lock_guard lock(mutex_);
  const std::string id = fmt::format("upload/{}/{}", ++upload_count_, name);
  uploads_.push_back(id);
  motions_[id + '\n'] = m;
  if (uploads_.size() > limits_.uploads) {
    motions_.erase(uploads_.front() + '\n');
    uploads_.erase(uploads_.begin());
  }
  return {{"id", id}, {"name", describe_motion(*m)}, {"pga_g", m->peak() / gravity}, {"duration_s", m->duration()}};
}

LabRun Lab::read_simulate(const json& r) const {
  check_keys(r, "simulate", {"scene", "record", "component", "scale", "set", "duration", "every", "compare"});
  LabRun run;
  const std::vector<std::string> overrides = overrides_of(r, limits_.overrides);
  run.spec.scene = scene_of(r, overrides);
  run.spec.prefix = "";
  const std::string record = text_of(r, "record");
  const std::string component = text_of(r, "component");
  if (!record.empty()) {
    run.spec.motion.given = motion(record, component);
    run.spec.motion.given_path = record_path(record);
  } else if (!component.empty()) {
    throw InputError("component: names a component of a record; none was given");
  }
  run.spec.motion.scale = number_of(r, "scale").value_or(1.0);
  if (!(run.spec.motion.scale > 0) || run.spec.motion.scale > 100)
    throw InputError(fmt::format("scale {:g}: must be in (0, 100]", run.spec.motion.scale));
  run.spec.solver.duration = number_of(r, "duration");
  if (run.spec.solver.duration && *run.spec.solver.duration > limits_.duration)
    throw InputError(fmt::format("duration {:g}: at most {:g} s here", *run.spec.solver.duration, limits_.duration));
  run.spec.history.every = number_of(r, "every").value_or(0.02);
  run.spec.history.columns = lab_columns(make_contact_model(run.spec.scene, true));
  run.twin = text_of(r, "compare");
  if (!run.twin.empty()) {  // the same run of the scene with the variant's overrides after the request's
    std::vector<std::string> all = overrides;
    const std::vector<std::string> variant = named_variant(run.twin).overrides;
    all.insert(all.end(), variant.begin(), variant.end());
    run.twin_spec = run.spec;
    run.twin_spec->scene = scene_of(r, all);
    run.twin_spec->history.columns = lab_columns(make_contact_model(run.twin_spec->scene, true));
  }
  return run;
}

namespace {

// "summary": ..., "structure": ..., "history": ... of a run.
void append_run(std::string& out, const RunSpec& spec, const LabLimits& limits, const Deadline& deadline) {
  const Ran ran = run_once(spec, limits, deadline);
  out += R"("summary":)";
  out += text(run_summary(ran.label, ran.result));
  out += R"(,"structure":)";
  out += text(ran.structure);
  out += R"(,"columns":)";
  json columns = json::array();
  for (const std::string& name : ran.names) columns.push_back(column_schema(name));
  out += text(columns);
  out += R"(,"history":)";
  append_history(out, ran.names, ran.values);
}

}  // namespace

std::string Lab::simulate(const json& r) const {
  const LabRun run = read_simulate(r);
  const Deadline deadline(limits_.seconds);
  std::string out = "{";
  append_run(out, run.spec, limits_, deadline);
  out += R"(,"twin":)";
  if (run.twin_spec) {
    out += R"({"variant":)" + text(json(run.twin)) + ",";
    append_run(out, *run.twin_spec, limits_, deadline);
    out += '}';
  } else {
    out += "null";
  }
  out += '}';
  return out;
}

json Lab::modal(const json& r) const {
  check_keys(r, "modal", {"scene", "set"});
  return modal_summary(scene_of(r, overrides_of(r, limits_.overrides)));
}

json Lab::ida(const json& r) const {
  check_keys(r, "ida", {"scene", "record", "component", "set", "scales", "compare"});
  const SceneEntry& entry = scene_entry(r);
  const std::vector<std::string> overrides = overrides_of(r, limits_.overrides);
  const Scene scene = scene_of(r, overrides);
  const std::string record = text_of(r, "record");
  if (record.empty()) throw InputError("ida: record: give one of the lab's records to scale");
  const std::string component = text_of(r, "component");
  const auto scales = r.find("scales");
  if (scales == r.end() || !scales->is_array() || scales->empty())
    throw InputError("scales: give a list of scale factors, e.g. [0.5, 1, 2]");
  if (scales->size() > limits_.ida_levels)
    throw InputError(fmt::format("scales: {} levels (at most {} here)", scales->size(), limits_.ida_levels));
  std::vector<double> levels;
  for (const json& s : *scales) {
    if (!s.is_number() || !(s.get<double>() > 0) || !(s.get<double>() <= 100))
      throw InputError("scales: every scale factor must be a number in (0, 100]");
    levels.push_back(s.get<double>());
  }
  std::vector<Variant> variants{named_variant("scene")};
  if (const std::string twin = text_of(r, "compare"); !twin.empty()) variants.push_back(named_variant(twin));
  const std::shared_ptr<const GroundMotion> m = motion(record, component);
  const double duration = m->duration();
  if (duration > limits_.duration)
    throw InputError(fmt::format("record '{}': {:g} s to simulate (at most {:g} s here)", record, duration,
                                 limits_.duration));
  RecordOptions ro;
  ro.component = component;
  const Deadline deadline(limits_.seconds);
  RunOptions options = run_options(scene, SolverChoice{}, false, "");
  options.stop = [&deadline] { return deadline.passed(); };
  const Study study(entry.path, overrides, std::vector<StudyRecord>{{record_path(record), m}}, ro, variants, options);
  const StudyColumns columns = study_columns(study);
  const std::vector<std::string> names = columns.names();
  json rows = json::array();
  for (const Job& job : study.ladder(levels)) {
    const JobResult res = study.run(job);
    if (!res.error.empty()) throw InputError(res.error);
    check_result(res.run, deadline, limits_);
    const StudyRow row = study_row(columns, job, res);
    json peaks = json::object();
    for (std::size_t i = 0; i < names.size(); ++i)
      peaks[names[i]] = std::isfinite(row.values[i]) ? json(row.values[i]) : json(nullptr);
    rows.push_back({{"variant", study.variants()[job.variant].name},
                    {"level", row.level},
                    {"outcome", outcome_name(row.outcome)},
                    {"peaks", std::move(peaks)}});
  }
  return {{"columns", names}, {"rows", std::move(rows)}};
}

LabAnswer Lab::answer(std::string_view method, std::string_view path, std::string_view body) const {
  // An error names a scene or record file as the lab lists it, never by where it lies on this machine.
  const auto error = [this](int status, std::string_view message) {
    std::string m(message);
    for (const fs::path& folder : {folders_.scenes, folders_.records}) {
      std::error_code ec;
      for (const fs::path& form : {folder, fs::weakly_canonical(folder, ec), fs::absolute(folder, ec)}) {
        const std::string prefix = form.empty() ? std::string() : (form / "").string();
        if (prefix.size() < 2) continue;
        for (auto at = m.find(prefix); at != std::string::npos; at = m.find(prefix, at)) m.erase(at, prefix.size());
      }
    }
    return LabAnswer{status, text(json{{"error", m}})};
  };
  const bool get = path == "/api/scenes" || path == "/api/records";
  const bool post = path == "/api/simulate" || path == "/api/modal" || path == "/api/ida" || path == "/api/upload";
  if (!get && !post) return error(404, fmt::format("no such endpoint (GET /api/scenes, /api/records; POST "
                                                   "/api/simulate, /api/modal, /api/ida, /api/upload)"));
  if (get != (method == "GET") || post != (method == "POST"))
    return error(405, fmt::format("{} takes {}", path, get ? "GET" : "POST"));
  const std::size_t limit = path == "/api/upload" ? limits_.upload_bytes : limits_.request_bytes;
  if (body.size() > limit) return error(413, fmt::format("a request of {} bytes (at most {})", body.size(), limit));
  try {
    if (path == "/api/scenes") return {200, text(scenes())};
    if (path == "/api/records") return {200, text(records())};
    json request;
    try {
      request = json::parse(body);
    } catch (const json::exception& e) {  // a syntax error, or a number beyond a double (out_of_range.406)
      return error(400, "malformed JSON: " + json_message(e));
    }
    if (path == "/api/simulate") return {200, simulate(request)};
    if (path == "/api/modal") return {200, text(modal(request))};
    if (path == "/api/upload") return {200, text(upload(request))};
    return {200, text(ida(request))};
  } catch (const InputError& e) {
    return error(400, e.what());
  } catch (const RunError& e) {
    return error(422, e.what());
  } catch (const json::exception& e) {  // a value of a type the reading did not expect
    return error(400, "malformed request: " + json_message(e));
  }
}

}  // namespace rocking
