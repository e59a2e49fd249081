module;
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <fmt/format.h>
module rocking.run;
import rocking.errors;
import rocking.records;

namespace rocking {

RecordOptions record_options(const RecordFileChoice& c, std::string_view prefix) {
  RecordOptions ro;
  ro.format = c.format;
  ro.component = c.component;
  if (!c.units.empty()) ro.unit = parse_acceleration_unit(c.units);
  // A record's time step: 1 us (records sampled finer are not records) to 10 s.
  if (c.dt != 0 && !(c.dt >= 1e-6 && c.dt <= 10))
    throw InputError(fmt::format("{}dt {:g}: must be in [1e-06, 10] s", prefix, c.dt));
  ro.dt = c.dt;
  if (!c.process.empty()) try {
      ro.process = parse_processing(c.process);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}process {}: {}", prefix, c.process, e.what()));
    }
  return ro;
}

std::string ScaleFactors::describe() const {
  if (scene == 1) return fmt::format("x{:g}", total());
  return fmt::format("x{:g} (scene {:g} x --scale {:g})", total(), scene, option);
}

ScaleFactors motion_scale(const Scene& scene, const MotionChoice& c) {
  return {c.scene_excitation() ? excitation_scale(scene) : 1.0, c.scale};
}

namespace {

// The vertical motion a choice names besides the horizontal one, scaled; none
// when it names none (the scene's own comes with its excitation).
std::optional<GroundMotion> vertical_motion(const MotionChoice& c, std::string_view prefix) {
  if (c.given_vertical) {
    const RecordInfo& i = c.given_vertical->info();
    if (component_orientation(i.component) == Orientation::horizontal)
      throw InputError(fmt::format("{}vertical: {} is component {}, a horizontal one", prefix,
                                   c.given_vertical->name(), i.component));
    return c.given_vertical->scaled(c.scale);
  }
  if (c.vertical.empty()) {
    if (c.vertical_file.given())
      throw InputError(fmt::format("{0}vertical-component and {0}vertical-units describe a {0}vertical file; none was given",
                                   prefix));
    return std::nullopt;
  }
  RecordOptions ro = record_options(c.vertical_file, prefix);
  ro.process = record_options(c.file, prefix).process;  // the components processed alike
  ro.scale = c.scale;
  ro.read_as = ReadAs::vertical;
  std::error_code ec;
  if (std::filesystem::exists(c.vertical, ec)) return read_record(c.vertical, ro);
  // A component of the horizontal record's own file.
  const std::string file = !c.record.empty() ? c.record : c.given ? c.given_path : std::string();
  if (file.empty())
    throw InputError(fmt::format("{}vertical {}: no such file (a component name needs the {}record file it is a "
                                 "component of)", prefix, c.vertical, prefix));
  if (!c.vertical_file.component.empty())
    throw InputError(fmt::format("{}vertical {}: not a file, and {}vertical-component applies to a vertical file",
                                 prefix, c.vertical, prefix));
  RecordOptions same = record_options(c.file, prefix);
  same.scale = c.scale;
  same.read_as = ReadAs::vertical;
  same.component = c.vertical;
  return read_record(file, same);
}

GroundMotion horizontal_motion(const Scene& scene, const MotionChoice& c, std::string_view prefix) {
  if (c.given) {
    const RecordInfo& i = c.given->info();
    if (component_orientation(i.component) == Orientation::vertical)
      throw InputError(fmt::format("{}record: {} is component {}, a vertical one: give it as the vertical motion "
                                   "({}vertical) and a horizontal component as the record",
                                   prefix, c.given->name(), i.component, prefix));
    return c.given->scaled(c.scale);
  }
  if (c.record.empty()) {
    if (c.file.given())
      throw InputError(fmt::format("{0}format, {0}component, {0}units, {0}dt and {0}process describe a {0}record file; "
                                   "none was given", prefix));
    return default_ground_motion(scene).scaled(c.scale);
  }
  RecordOptions ro = record_options(c.file, prefix);
  ro.scale = c.scale;
  ro.other_horizontal = c.azimuth && c.second.empty() && !c.given_second;
  return read_record(c.record, ro);
}

// The motion on the plane at c.azimuth: the projection of the record's
// component and its other horizontal one.
GroundMotion on_the_plane(const GroundMotion& h, const MotionChoice& c, std::string_view prefix) {
  const bool given_other = !c.second.empty() || c.given_second;
  if (!c.azimuth) {
    if (given_other)
      throw InputError(fmt::format("{}second: the other horizontal component is for {}azimuth; none was given", prefix,
                                   prefix));
    return h;
  }
  if (!std::isfinite(*c.azimuth) || std::abs(*c.azimuth) > 360)
    throw InputError(fmt::format("{}azimuth {}: must be an angle in degrees, -360 to 360", prefix, *c.azimuth));
  std::optional<GroundMotion> other;
  if (c.given_second) other = c.given_second->scaled(c.scale);
  if (!c.second.empty()) {
    RecordOptions ro = record_options(c.file, prefix);
    ro.component.clear();
    ro.scale = c.scale;
    other = read_record(c.second, ro);
  }
  if (!other && !h.other_horizontal())
    throw InputError(fmt::format("{}azimuth {:g}: {} has no other horizontal component to project with (a file that "
                                 "holds both, or {}second FILE)", prefix, *c.azimuth, h.name(), prefix));
  return project(h, other ? *other : *h.other_horizontal(), *c.azimuth);
}

}  // namespace

GroundMotion load_motion(const Scene& scene, const MotionChoice& c, std::string_view prefix) {
  if (!std::isfinite(c.scale)) throw InputError(fmt::format("{}scale {}: must be a finite number", prefix, c.scale));
  const GroundMotion horizontal = on_the_plane(horizontal_motion(scene, c, prefix), c, prefix);
  const std::optional<GroundMotion> vertical = vertical_motion(c, prefix);
  return vertical ? horizontal.with_vertical(*vertical) : horizontal;
}

RunOptions run_options(const Scene& scene, const SolverChoice& c, bool scene_excitation, std::string_view prefix) {
  RunOptions ro;
  ro.backend = ode::parse_backend(c.integrator);
  if (c.duration && !(*c.duration > 0))
    throw InputError(fmt::format("{}duration {}: must be positive and at most 1e5 s (omit it for the whole motion)",
                                 prefix, *c.duration));
  ro.tolerances.rtol = c.rtol;
  ro.tolerances.atol = c.atol;
  ro.duration = c.duration ? *c.duration : scene_excitation ? scene.excitation.duration : 0.0;
  ro.max_events = c.max_events;
  ro.tolerances.max_steps = c.max_steps;
  check_run_options(ro, prefix);
  ro.exact_full_contact = !c.integrate_contact;
  ro.initial = {scene.initial.theta, scene.initial.theta_dot, scene.initial.u, scene.initial.u_dot};
  return ro;
}

PreparedRun prepare_run(const RunSpec& spec) { return prepare_run(spec, load_motion(spec.scene, spec.motion, spec.prefix)); }

PreparedRun prepare_run(const RunSpec& spec, GroundMotion motion) {
  const Scene& scene = spec.scene;
  RunOptions ro = run_options(scene, spec.solver, spec.motion.scene_excitation(), spec.prefix);
  const double every = history_interval(scene, spec.history.every);
  if (!(every > 0) || !std::isfinite(every))
    throw InputError(fmt::format("{}every {}: must be positive", spec.prefix, every));
  const double duration = ro.duration > 0 ? ro.duration : motion.duration();
  if (duration / every > max_history_rows)
    throw InputError(fmt::format("{}every {:g}: {:.3g} rows of history for {:g} s (at most {:g}); choose a larger "
                                 "interval",
                                 spec.prefix, every, duration / every, duration, max_history_rows));
  ro.output_interval = every;
  ContactModel model = make_contact_model(scene, spec.track_energy);
  model.vertical_shaking = motion.vertical() != nullptr;
  HistoryColumns columns =
      history_columns(scene, model, spec.history.columns, spec.prefix + spec.columns_name);
  const ScaleFactors scale = motion_scale(scene, spec.motion);
  RunLabel label{scene.name,
                 scene.source,
                 describe_motion(motion),
                 spec.motion.given ? spec.motion.given_path : spec.motion.record,
                 scale.total(),
                 scale.scene,
                 scale.option,
                 ro.tolerances.rtol,
                 ro.tolerances.atol,
                 motion.vertical() ? describe_motion(*motion.vertical()) : std::string()};
  return {std::move(motion), scale, std::move(ro), std::move(model), std::move(columns), std::move(label)};
}

}  // namespace rocking
