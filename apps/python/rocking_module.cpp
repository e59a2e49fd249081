// The Python module `rocking` (pybind11): the library the command line uses,
// with NumPy arrays in and out and no physics of its own. Scenes are read and
// overridden by rocking.scene (the keys and errors of --set), records by
// rocking.ground_motion, runs by rocking.simulation, summaries by
// rocking.report (summary.json and `rocking modal --json`, the same text
// parsed by Python's json), studies by rocking.study. Long calls run with the
// GIL released, and Ctrl-C stops them (RunOptions::stop, polled between
// steps) with a KeyboardInterrupt. InputError
// becomes ValueError with the same one-line message; a run that cannot finish
// raises rocking.RunError carrying what was reached (.result).
#include <pybind11/pybind11.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <rocking/eigen.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <numeric>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <csignal>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>
#include <signal.h>
import rocking.errors;
import rocking.scene;
import rocking.ground_motion;
import rocking.geometry;
import rocking.intensity;
import rocking.report;
import rocking.simulation;
import rocking.study_files;
import rocking.run;
import rocking.lab;
import rocking.study_run;
import rocking.records;

namespace py = pybind11;
using namespace pybind11::literals;

namespace {

PyObject* run_error_type = nullptr;  // rocking.RunError, owned by the module

// ---- running C++ with Ctrl-C honoured ---------------------------------------

// Ctrl-C during a long call: while the call runs with the GIL released, a
// SIGINT handler of our own sets the call's stop flag (polled between steps
// and jobs) and then calls the handler it replaced (Python's, which marks the
// KeyboardInterrupt pending). Installed only on the main thread (where Python
// handles signals) and only over a handler Python installed.
std::atomic<std::atomic<bool>*> sigint_stop{nullptr};
struct sigaction replaced_sigint {};

extern "C" void on_sigint(int signal, siginfo_t* info, void* context) {
  if (std::atomic<bool>* stop = sigint_stop.load()) stop->store(true);
  if ((replaced_sigint.sa_flags & SA_SIGINFO) != 0) replaced_sigint.sa_sigaction(signal, info, context);
  else replaced_sigint.sa_handler(signal);
}

class SigintStops {
 public:
  explicit SigintStops(std::atomic<bool>& stop) {
    if (PyThread_get_thread_ident() != main_thread) return;
    struct sigaction current {};
    if (sigaction(SIGINT, nullptr, &current) != 0) return;
    const bool python_handles = (current.sa_flags & SA_SIGINFO) != 0
                                    ? current.sa_sigaction != nullptr && current.sa_sigaction != on_sigint
                                    : current.sa_handler != SIG_DFL && current.sa_handler != SIG_IGN;
    if (!python_handles) return;
    replaced_sigint = current;
    sigint_stop.store(&stop);
    struct sigaction ours = current;
    ours.sa_flags = (current.sa_flags | SA_SIGINFO) & ~SA_RESETHAND;
    ours.sa_sigaction = on_sigint;
    installed_ = sigaction(SIGINT, &ours, nullptr) == 0;
  }
  ~SigintStops() {
    if (installed_) sigaction(SIGINT, &replaced_sigint, nullptr);
    sigint_stop.store(nullptr);
  }
  SigintStops(const SigintStops&) = delete;
  SigintStops& operator=(const SigintStops&) = delete;
  static inline unsigned long main_thread = 0;  // set when the module is imported

 private:
  bool installed_ = false;
};

// Runs work() on the calling thread with the GIL released and Ctrl-C setting
// stop; a KeyboardInterrupt pending afterwards is raised.
template <class F>
auto interruptible(std::atomic<bool>& stop, F work) -> decltype(work()) {
  std::optional<decltype(work())> result;
  {
    SigintStops guard(stop);
    py::gil_scoped_release release;
    result.emplace(work());
  }
  if (stop && PyErr_CheckSignals() != 0) throw py::error_already_set();
  return std::move(*result);
}

// A JSON value as the Python objects json.loads would give, built directly.
py::object to_python(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<long long>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<unsigned long long>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get_ref<const std::string&>());
    case nlohmann::json::value_t::array: {
      py::list out;
      for (const nlohmann::json& v : j) out.append(to_python(v));
      return out;
    }
    case nlohmann::json::value_t::object: {
      py::dict out;
      for (const auto& [key, v] : j.items()) out[py::str(key)] = to_python(v);
      return out;
    }
    default: return py::none();
  }
}

// A NumPy array that owns the vector's storage (no copy).
py::array_t<double> to_numpy(std::vector<double>&& v) {
  auto* owned = new std::vector<double>(std::move(v));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>(static_cast<py::ssize_t>(owned->size()), owned->data(), free);
}

// The same, read-only: a fresh copy of what an object holds, where a write
// would change nothing the object keeps.
py::array_t<double> read_only(std::vector<double>&& v) {
  py::array_t<double> a = to_numpy(std::move(v));
  a.attr("setflags")("write"_a = false);
  return a;
}

std::string path_text(const std::filesystem::path& p) { return p.string(); }

// ---- scenes -----------------------------------------------------------------

// A scene file (or the embedded chimney) and the overrides applied to it, in
// order: what `rocking SCENE --set K=V ...` runs.
struct PyScene {
  std::string path;  // empty: the embedded chimney
  std::vector<std::string> overrides;
  std::shared_ptr<const rocking::Scene> scene;

  void reload() {
    scene = std::make_shared<const rocking::Scene>(path.empty() ? rocking::load_default_scene(overrides)
                                                                : rocking::load_scene(path, overrides));
  }
};

PyScene loaded_scene(std::string path, std::optional<std::vector<std::string>> overrides) {
  PyScene s{std::move(path), overrides.value_or(std::vector<std::string>{}), nullptr};
  s.reload();
  return s;
}

// A Python argument as T, or TypeError naming the argument, what it takes
// and what it was given (not pybind11's "Unable to cast").
template <class T>
T argument(const py::handle& v, const char* name, const char* takes) {
  try {
    return v.cast<T>();
  } catch (const py::cast_error&) {
    throw py::type_error(fmt::format("{}: expected {}, got {}", name, takes,
                                     py::str(v.get_type().attr("__name__")).cast<std::string>()));
  }
}

// The scene argument: a Scene, or None for the embedded chimney.
PyScene scene_of(const py::object& o) {
  return o.is_none() ? loaded_scene("", {}) : argument<PyScene>(o, "scene", "a rocking.Scene or None");
}

// A Python value as the TOML text an override takes.
std::string toml_value(const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(v)) return py::str(v).cast<std::string>();
  if (py::isinstance<py::float_>(v)) return py::repr(v).cast<std::string>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  if (py::isinstance<py::dict>(v)) {
    std::string out;
    for (const auto& [k, x] : v.cast<py::dict>()) {
      std::string item = toml_value(x);
      if (py::isinstance<py::str>(x)) item = py::repr(x).cast<std::string>();
      out += fmt::format("{}{} = {}", out.empty() ? "" : ", ", py::str(k).cast<std::string>(), item);
    }
    return "{" + out + "}";
  }
  if (py::isinstance<py::sequence>(v) || py::isinstance<py::array>(v)) {
    std::string out;
    for (const auto& x : py::iter(v)) {
      std::string item = toml_value(x);
      if (py::isinstance<py::str>(x)) item = py::repr(x).cast<std::string>();
      out += (out.empty() ? "" : ", ") + item;
    }
    return "[" + out + "]";
  }
  if (py::hasattr(v, "__float__")) return py::repr(py::float_(v.cast<py::object>())).cast<std::string>();
  throw rocking::InputError(fmt::format("set: cannot write a {} as a scene value",
                                        py::str(v.get_type().attr("__name__")).cast<std::string>()));
}

void scene_set(PyScene& s, const std::string& key, const py::object& value) {
  const std::string text = value.is_none() ? key : key + "=" + toml_value(value);
  const std::string name = text.substr(0, text.find('='));
  std::vector<std::string> before = s.overrides;
  // A key set again replaces its earlier value; device+= and device-= add up.
  if (!name.ends_with("+") && !name.ends_with("-"))
    std::erase_if(s.overrides, [&](const std::string& o) { return o.substr(0, o.find('=')) == name; });
  s.overrides.push_back(text);
  try {
    s.reload();
  } catch (...) {
    s.overrides = std::move(before);
    throw;
  }
}

// ---- records ----------------------------------------------------------------

struct PyRecord {
  std::shared_ptr<const rocking::GroundMotion> motion;
  std::string path;  // the file it was read from ("" when built from an array)
};

PyRecord record_load(const std::filesystem::path& file, std::optional<std::string> component,
                     std::optional<std::string> units, const std::string& format, std::optional<double> dt,
                     std::optional<std::string> process) {
  rocking::RecordOptions ro;
  if (process) try {
      ro.process = rocking::parse_processing(*process);
    } catch (const rocking::InputError& e) {
      throw rocking::InputError(fmt::format("process {}: {}", *process, e.what()));
    }
  ro.format = format;
  ro.read_as = rocking::ReadAs::any;  // checked where it is used (simulate's record and vertical)
  if (component) ro.component = *component;
  if (units) ro.unit = rocking::parse_acceleration_unit(*units);
  if (dt) {
    if (!(*dt > 0) || !std::isfinite(*dt)) throw rocking::InputError(fmt::format("dt {}: must be positive", *dt));
    ro.dt = *dt;
  }
  return {std::make_shared<const rocking::GroundMotion>(rocking::read_record(path_text(file), ro)), path_text(file)};
}

PyRecord record_from_array(const py::array_t<double, py::array::c_style | py::array::forcecast>& acc, double dt,
                           const std::string& units, const std::string& name) {
  if (acc.ndim() != 1) throw rocking::InputError(fmt::format("Record: acc has {} dimensions; give one", acc.ndim()));
  if (!(dt > 0) || !std::isfinite(dt)) throw rocking::InputError(fmt::format("Record: dt {}: must be positive", dt));
  const auto n = static_cast<std::size_t>(acc.shape(0));
  // The bounds every record file is read within (rocking.ground_motion).
  if (!(dt >= rocking::min_record_dt) || !(dt * static_cast<double>(n) <= rocking::max_record_duration))
    throw rocking::InputError(fmt::format("Record: dt {:g}: must be at least {:g} s, and dt x {} samples at most {:g} s",
                                          dt, rocking::min_record_dt, n, rocking::max_record_duration));
  const double si = rocking::to_si(rocking::parse_acceleration_unit(units));
  std::vector<double> times(n), values(n);
  const double* a = acc.data();
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(a[i])) throw rocking::InputError(fmt::format("Record: acc[{}] is {}: not a number", i, a[i]));
    if (!(std::abs(a[i] * si) <= rocking::max_acceleration_g * rocking::gravity))
      throw rocking::InputError(fmt::format("Record: acc[{}] = {:g} {}: beyond {:g} g, not a ground motion", i, a[i],
                                            units, rocking::max_acceleration_g));
    times[i] = static_cast<double>(i) * dt;
    values[i] = a[i] * si;
  }
  return {std::make_shared<const rocking::GroundMotion>(
              rocking::GroundMotion::from_samples(name, std::move(times), std::move(values))),
          ""};
}

py::object record_measures(const PyRecord& r, std::optional<std::vector<double>> periods, double damping) {
  const rocking::RecordMeasures m =
      rocking::measure_record(*r.motion, periods ? *periods : rocking::standard_periods(), damping);
  return to_python(rocking::record_summary(r.path.empty() ? r.motion->name() : r.path, r.path, *r.motion, m));
}

// ---- runs -------------------------------------------------------------------

// Keeps the history as columns and the events as they come.
class Collector : public rocking::HistoryObserver {
 public:
  Collector(const rocking::ContactModel& model, rocking::HistoryColumns layout, bool keep_history)
      : HistoryObserver(model, std::move(layout)), keep_(keep_history) {
    names = columns().names();
    history.resize(names.size());
  }
  void record(const rocking::Response& r) override {
    if (keep_) HistoryObserver::record(r);
  }
  void event(const rocking::Event& e) override { events.push_back(e); }

  std::vector<std::string> names;
  std::vector<std::vector<double>> history;
  std::vector<rocking::Event> events;

 protected:
  void row(const rocking::Response&, const std::vector<double>& values) override {
    for (std::size_t i = 0; i < values.size(); ++i) history[i].push_back(values[i]);
  }

 private:
  bool keep_;
};

struct PyResult {
  py::dict summary;
  py::dict history;  // column name -> ndarray, in the order of history.csv
  py::list events;
  std::string outcome;
};

py::module_ import_pandas() {
  try {
    return py::module_::import("pandas");
  } catch (const py::error_already_set&) {
    throw py::import_error("to_pandas needs pandas (Debian: python3-pandas); the same data are in plain Python and "
                           "NumPy objects");
  }
}

py::object to_pandas_rows(const py::list& rows) { return import_pandas().attr("DataFrame")(rows); }

py::object to_pandas(const py::dict& columns) {
  return import_pandas().attr("DataFrame")(columns);
}

PyResult simulate(const py::object& scene_arg, const py::object& record, double scale, double rtol, double atol,
                  const std::string& integrator, std::optional<double> every_given, std::optional<double> duration, long max_events,
                  long max_steps, bool integrate_contact, bool history,
                  const std::optional<std::vector<std::string>>& columns, const py::object& vertical,
                  std::optional<double> azimuth, const py::object& second) {
  const PyScene s = scene_of(scene_arg);
  // The run as `rocking simulate` describes it (rocking.run), its choices named as here.
  rocking::RunSpec spec{.scene = *s.scene, .motion = {}, .solver = {}, .history = {}, .prefix = "", .columns_name = "columns"};
  spec.motion.scale = scale;
  if (!record.is_none()) {
    const PyRecord r =
        py::isinstance<PyRecord>(record)
            ? record.cast<PyRecord>()
            : record_load(argument<std::filesystem::path>(record, "record", "a rocking.Record, a path or None"), {}, {},
                          "auto", {}, {});
    spec.motion.given = r.motion;
    spec.motion.given_path = r.path;
  }
  spec.motion.azimuth = azimuth;
  if (py::isinstance<PyRecord>(second)) spec.motion.given_second = second.cast<PyRecord>().motion;
  else if (!second.is_none())
    spec.motion.second = path_text(argument<std::filesystem::path>(second, "second", "a rocking.Record, a path or None"));
  if (py::isinstance<PyRecord>(vertical)) spec.motion.given_vertical = vertical.cast<PyRecord>().motion;
  else if (!vertical.is_none())  // a file, or a component of the record's file
    spec.motion.vertical = path_text(argument<std::filesystem::path>(
        vertical, "vertical", "a rocking.Record, a path, a component name of record's file, or None"));
  spec.solver = {.integrator = integrator, .rtol = rtol, .atol = atol, .duration = duration, .max_events = max_events,
                 .max_steps = max_steps, .integrate_contact = integrate_contact};
  // Without a history no rows are kept, so none bounds the interval.
  spec.history = {.columns = columns.value_or(std::vector<std::string>{}), .every = history ? every_given : std::nullopt};
  const rocking::PreparedRun run = rocking::prepare_run(spec);
  rocking::RunOptions ro = run.options;
  if (!history) ro.output_interval = std::numeric_limits<double>::infinity();
  auto stop = std::make_shared<std::atomic<bool>>(false);
  ro.stop = [stop] { return stop->load(); };
  Collector collect(run.model, run.columns, history);
  const rocking::RunResult result =
      interruptible(*stop, [&] { return rocking::simulate(run.model, run.motion, ro, &collect); });

  PyResult out;
  out.summary = to_python(rocking::run_summary(run.label, result)).cast<py::dict>();
  out.outcome = std::string(rocking::outcome_name(result.outcome));
  for (std::size_t i = 0; i < collect.names.size(); ++i)
    out.history[py::str(collect.names[i])] = to_numpy(std::move(collect.history[i]));
  // A run has hundreds of events: their keys, kinds and device names are
  // made once, not once per event.
  const py::str kind_key("kind"), t_key("t"), pivot_key("pivot"), device_key("device"), joint_key("joint");
  std::vector<py::object> kinds;  // by EventKind, each made when first met
  std::vector<py::str> device_names;
  for (const rocking::Device& dev : run.model.devices) device_names.emplace_back(dev.name);
  for (const rocking::Event& e : collect.events) {
    const auto k = static_cast<std::size_t>(e.kind);
    if (k >= kinds.size()) kinds.resize(k + 1);
    if (!kinds[k]) kinds[k] = py::str(std::string(rocking::event_name(e.kind)));
    py::dict d;
    d[kind_key] = kinds[k];
    d[t_key] = py::float_(e.t);
    d[pivot_key] = py::int_(rocking::sign(e.pivot));
    if (e.device) d[device_key] = device_names[static_cast<std::size_t>(*e.device)];
    if (run.model.jointed) d[joint_key] = py::int_(e.joint);  // where: 0 the base, K joint K above it
    out.events.append(std::move(d));
  }
  if (result.outcome == rocking::Outcome::failed) {
    py::object exc = py::reinterpret_borrow<py::object>(run_error_type)(result.failure);
    exc.attr("result") = py::cast(std::move(out));
    PyErr_SetObject(run_error_type, exc.ptr());
    throw py::error_already_set();
  }
  return out;
}

// ---- studies ----------------------------------------------------------------

struct PyIda {
  std::shared_ptr<const rocking::Study> study;
  py::list rows;
  std::vector<std::string> variants;
  std::vector<std::string> records;
  std::vector<std::string> limits;
  std::shared_ptr<rocking::StudySummary> summary;  // a ladder's (null for a hunt)
  // A hunt's: one result per (record, variant), record-major, and its rows.
  std::vector<rocking::HuntResult> hunts;
  py::list hunt_rows;
  bool hunt = false;
  rocking::HuntOptions hunt_options;
  // A ladder's jobs and the results of those that ran (rocking.study_files writes them).
  std::vector<rocking::Job> jobs;
  std::vector<rocking::JobResult> results;
  int threads = 1;
};

rocking::FragilityOptions fragility_options(long bootstrap, unsigned long seed, double beta_modelling) {
  if (bootstrap < 0) throw rocking::InputError(fmt::format("bootstrap {}: must be 0 (none) or a number of resamples", bootstrap));
  rocking::FragilityOptions o;
  o.bootstrap.draws = static_cast<std::size_t>(bootstrap);
  o.bootstrap.seed = seed;
  o.beta_modelling = beta_modelling;
  rocking::check_fragility_options(o);
  return o;
}

// The report `rocking ida` writes beside its rows (rocking.study_files), its
// records named by `ids` (rocking::record_ids of the study's records).
rocking::StudyReport ida_report(const PyIda& r, const rocking::FragilityOptions& o, const std::vector<std::string>& ids) {
  py::gil_scoped_release unlocked;
  if (r.hunt) return rocking::hunt_report(*r.study, r.hunts, ids, o);
  return rocking::ladder_report(*r.study, *r.summary, rocking::suite_fragility(*r.study, *r.summary, o, r.threads), ids);
}

// The files of `rocking ida --out DIR --no-plot` (no inputs.txt or timing.csv).
py::list ida_write(const PyIda& r, const std::filesystem::path& dir, const rocking::FragilityOptions& o) {
  const rocking::Study& st = *r.study;
  const std::vector<std::string> ids = rocking::record_ids(st.records());
  const rocking::StudyReport report = ida_report(r, o, ids);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw rocking::InputError(fmt::format("{}: cannot create the output folder: {}", dir.string(), ec ? ec.message() : "not a folder"));
  std::vector<std::filesystem::path> written;
  auto write = [&](const char* name, const std::string& text) {
    rocking::write_text(dir / name, text);
    written.push_back(dir / name);
  };
  if (r.hunt) {
    const std::size_t nv = st.variants().size();
    std::string rows = rocking::hunt_csv_header, points = rocking::hunt_points_header;
    for (std::size_t k = 0; k < r.hunts.size(); ++k) {
      const std::string& record = ids[k / nv];
      const std::string& variant = st.variants()[k % nv].name;
      rows += rocking::hunt_csv_row(r.hunts[k], record, variant, st.intensity_measure(), r.hunt_options);
      points += rocking::hunt_points_rows(r.hunts[k], record, variant, st.intensity_measure());
    }
    write("hunt.csv", rows);
    write("hunt_points.csv", points);
  } else {
    const rocking::StudyColumns columns = rocking::study_columns(st);
    std::string rows = rocking::study_csv_header(columns);
    for (std::size_t i = 0; i < r.results.size(); ++i)
      rows += rocking::study_csv_row(st, columns, ids, r.jobs[i], r.results[i]);
    write("ida.csv", rows);
  }
  write("records.csv", rocking::records_csv(st, ids));
  for (std::filesystem::path& f : rocking::write_report(dir, report)) written.push_back(std::move(f));
  py::list out;
  for (const std::filesystem::path& f : written) out.append(py::module_::import("pathlib").attr("Path")(f.string()));
  return out;
}

// A hunt's row: the columns of hunt.csv (rocking::hunt_json) and the levels
// it ran (hunt_points.csv).
py::dict hunt_row(const rocking::HuntResult& h, const std::string& record, const std::string& variant,
                  const rocking::IntensityMeasure& im, const rocking::HuntOptions& o) {
  py::dict row = to_python(rocking::hunt_json(h, record, variant, im, o)).cast<py::dict>();
  py::list points;
  for (const rocking::HuntPoint& p : h.points)
    points.append(py::dict("level"_a = p.level, "why"_a = std::string(rocking::hunt_reason(p.why)),
                           "overturned"_a = p.overturned));
  row["points"] = points;
  return row;
}

// A study's records: Record objects (kept as they are in memory) and paths of
// files, folders or list files (read as the program reads them), one or an
// iterable of them.
std::vector<rocking::StudyRecord> study_records(const py::object& records_arg) {
  std::vector<rocking::StudyRecord> records;
  auto add = [&](const py::handle& r) {
    if (py::isinstance<PyRecord>(r)) {
      const PyRecord rec = r.cast<PyRecord>();
      records.push_back({rec.path.empty() ? rec.motion->name() : rec.path, rec.motion});
      return;
    }
    const std::string g = path_text(
        argument<std::filesystem::path>(r, "records", "rocking.Record objects or paths of records, folders or lists"));
    for (std::string& p : rocking::record_paths(g)) records.push_back({std::move(p), nullptr});
  };
  if (py::isinstance<py::str>(records_arg) || py::hasattr(records_arg, "__fspath__") || py::isinstance<PyRecord>(records_arg))
    add(records_arg);
  else if (py::isinstance<py::iterable>(records_arg))
    for (const auto& r : py::iter(records_arg)) add(r);
  else
    add(records_arg);
  return records;
}

// One row of a ladder's rows as Python's dict: the columns of ida.csv by name
// (None where the run's model lacks one).
py::dict ladder_row(const rocking::Study& study, const rocking::IntensityMeasure& im,
                    const rocking::StudyColumns& columns, const std::vector<std::string>& names,
                    const rocking::Job& j, const rocking::JobResult& r) {
  const rocking::StudyRow study_row = rocking::study_row(columns, j, r);
  py::dict row("record"_a = study.records()[j.record], "variant"_a = study.variants()[j.variant].name,
               "im"_a = im.name(), "level"_a = study_row.level, "scale"_a = j.scale,
               "record_im"_a = study.record_intensity(j.record));
  if (!study_row.ran) {
    // A run the momentum law left undecided keeps its outcome; the others could not run.
    row["outcome"] = r.run.outcome == rocking::Outcome::undecided ? "undecided" : "error";
    row["error"] = r.error;
    return row;
  }
  row["outcome"] = std::string(rocking::outcome_name(study_row.outcome));
  if (study_row.outcome == rocking::Outcome::failed) row["error"] = r.run.failure;
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double v = study_row.values[k];
    row[py::str(names[k])] = std::isnan(v) ? py::object(py::none()) : py::object(py::float_(v));
  }
  row["t_end"] = r.run.t_end;
  return row;
}

PyIda ida(const py::object& scene_arg, const py::object& records_arg, const std::string& im_text, std::vector<double> levels,
          std::optional<std::vector<std::string>> variant_names, int threads, double rtol, double atol,
          const std::string& integrator, double damping, std::optional<std::vector<std::string>> limit_texts,
          const std::string& resurrection, bool hunt, std::optional<double> hunt_step, double hunt_growth,
          std::optional<double> hunt_max, std::optional<double> precision, std::optional<double> fill_step) {
  const PyScene s = scene_of(scene_arg);
  std::vector<rocking::Limit> limits;  // refused before the records are read
  for (const std::string& l : limit_texts.value_or(std::vector<std::string>{})) limits.push_back(rocking::parse_limit(l));
  const std::vector<rocking::StudyRecord> records = study_records(records_arg);
  if (records.empty()) throw rocking::InputError("ida: records: give at least one ground-motion file");
  if (levels.empty()) throw rocking::InputError("ida: levels: give at least one level");
  for (double l : levels)
    if (!(l > 0) || !std::isfinite(l)) throw rocking::InputError(fmt::format("ida: level {}: must be positive", l));
  const rocking::WorkerThreads workers = rocking::worker_threads(threads, "ida: threads");
  if (workers.capped) {
    const std::string note = fmt::format("ida: threads {}: this machine has {} cores; running {} threads", threads,
                                         workers.cores, workers.threads);
    if (PyErr_WarnEx(PyExc_RuntimeWarning, note.c_str(), 1) != 0) throw py::error_already_set();
  }
  threads = workers.threads;
  if (!(damping >= 0 && damping < 1)) throw rocking::InputError(fmt::format("ida: damping {}: must be in [0, 1)", damping));

  const rocking::Scene& scene = *s.scene;
  std::vector<rocking::Variant> variants;
  if (!variant_names) variants = rocking::default_variants(scene);
  else
    for (const std::string& v : *variant_names)
      variants.push_back(v.find('=') != std::string::npos ? rocking::Variant{v, {v}} : rocking::named_variant(v));
  const double t1 =
      scene.structure.rigid ? 0.0 : 1.0 / rocking::modal_analysis(scene.structure, rocking::scene_devices(scene)).fixed_base_hz[0];
  const rocking::IntensityMeasure im = rocking::parse_intensity_measure(im_text, damping, t1);
  // The runs as `rocking ida` describes them (rocking.run).
  rocking::SolverChoice solver;
  solver.integrator = integrator;
  solver.rtol = rtol;
  solver.atol = atol;
  rocking::RunOptions ro = rocking::run_options(scene, solver, false, "");
  auto stop = std::make_shared<std::atomic<bool>>(false);
  ro.stop = [stop] { return stop->load(); };
  auto shared_study = std::make_shared<const rocking::Study>(s.path, s.overrides, records, rocking::RecordOptions{},
                                                            std::move(variants), ro, im);
  const rocking::Study& study = *shared_study;
  std::sort(levels.begin(), levels.end());
  const rocking::Resurrection convention = rocking::parse_resurrection(resurrection);
  PyIda out;
  out.study = shared_study;
  out.threads = threads;
  out.hunt = hunt;
  for (const rocking::Variant& v : study.variants()) out.variants.push_back(v.name);
  out.records = study.records();
  // The runs as `rocking ida` runs them (rocking.study_run), a Ctrl-C their stop.
  const rocking::StudyCallbacks callbacks{.progress = {}, .stop = [stop] { return stop->load(); }};
  if (hunt) {
    // `rocking ida --hunt`: the hunt from the lowest level for each (record, variant).
    if (!limits.empty()) throw rocking::InputError("ida: limits: a hunt looks for overturning only; run a ladder for limits");
    out.limits.push_back(rocking::overturning_limit().name);
    const rocking::HuntOptions o = rocking::hunt_options(levels.front(), hunt_step, hunt_growth, hunt_max, precision, fill_step);
    study.check_level(o.max, "hunt_max");
    out.hunt_options = o;
    const std::size_t nv = study.variants().size();
    interruptible(*stop, [&] {
      return rocking::run_hunts(study, o, 0, threads,
                                [&](std::size_t, const rocking::HuntResult& h) { out.hunts.push_back(h); }, callbacks);
    });
    for (std::size_t k = 0; k < out.hunts.size(); ++k)  // with the GIL held again
      out.hunt_rows.append(hunt_row(out.hunts[k], study.records()[k / nv], study.variants()[k % nv].name, im, o));
    return out;
  }
  const rocking::Ladder ladder = rocking::plan_ladder(study, levels, limits);
  for (const rocking::Limit& l : ladder.limits) out.limits.push_back(l.name);
  const std::vector<rocking::Job>& jobs = ladder.jobs;
  auto summary = std::make_shared<rocking::StudySummary>(study, levels, ladder.limits, convention);
  std::vector<rocking::JobResult> results(jobs.size());
  const rocking::StudyColumns& columns = ladder.columns;
  std::vector<std::size_t> all(jobs.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  const std::size_t done = interruptible(*stop, [&] {
    return rocking::run_ladder(study, ladder, all, threads, summary.get(),
                               [&](std::size_t i, const rocking::JobResult& r) { results[i] = r; }, callbacks);
  });
  out.summary = summary;
  out.jobs.assign(jobs.begin(), jobs.begin() + static_cast<long>(done));
  out.results.assign(results.begin(), results.begin() + static_cast<long>(done));
  const std::vector<std::string> names = columns.names();
  for (std::size_t i = 0; i < done; ++i) out.rows.append(ladder_row(study, im, columns, names, jobs[i], results[i]));
  return out;
}

std::size_t variant_index(const PyIda& r, const std::string& variant) {
  if (variant.empty()) return 0;
  const auto it = std::find(r.variants.begin(), r.variants.end(), variant);
  if (it == r.variants.end()) throw rocking::InputError(fmt::format("variant '{}' is not one of this study's", variant));
  return static_cast<std::size_t>(it - r.variants.begin());
}

// rocking.RunError, and InputError as ValueError.
void bind_errors(py::module_& m) {
  run_error_type = PyErr_NewException("rocking.RunError", PyExc_RuntimeError, nullptr);
  PyObject_SetAttrString(run_error_type, "__doc__",
                         py::str("A run that could not finish (step size underflow, step or event limit). Its "
                                 "message says when and why; .result holds what the run reached.").ptr());
  PyObject_SetAttrString(run_error_type, "result", Py_None);
  m.add_object("RunError", py::handle(run_error_type));
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const rocking::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const rocking::RunError& e) {
      PyErr_SetString(run_error_type, e.what());
    }
  });
}

// rocking.Scene: a scene file, or the built-in chimney, with overrides.
void bind_scene(py::module_& m) {
  py::class_<PyScene>(m, "Scene",
                      "A scene: a structure, its contact with the ground, its devices, its default\n"
                      "excitation and initial state (data/scenes/*.toml), with overrides.")
      .def_static(
          "load",
          [](const std::filesystem::path& path, std::optional<std::vector<std::string>> overrides) {
            return loaded_scene(path_text(path), std::move(overrides));
          },
          "path"_a, "overrides"_a = py::none(),
          "Reads a scene file; overrides are --set texts (\"damper.enabled=false\"). ValueError\n"
          "with the command line's message when the file or a value is wrong.")
      .def_static(
          "default",
          [](std::optional<std::vector<std::string>> overrides) { return loaded_scene("", std::move(overrides)); },
          "overrides"_a = py::none(), "The Christchurch chimney built into the library (the paper's case).")
      .def(
          "set",
          [](PyScene& s, const std::string& key, const py::object& value) -> PyScene& {
            scene_set(s, key, value);
            return s;
          },
          "key"_a, "value"_a = py::none(), py::return_value_policy::reference_internal,
          "Overrides one value as --set does: scene.set(\"damper.thickness\", 1.5), or\n"
          "scene.set(\"damper.enabled=false\"). Python values are written as TOML (bool,\n"
          "number, string, list, dict). A key set again replaces its value. Returns the\n"
          "scene; ValueError (the scene unchanged) when the key or value is wrong.")
      .def("to_toml", [](const PyScene& s) { return rocking::scene_toml(s.path, s.overrides); },
           "The scene file with the overrides applied, as TOML text.")
      .def("copy", [](const PyScene& s) { return s; }, "An independent copy (set() on it leaves this one alone).")
      .def_property_readonly("name", [](const PyScene& s) { return s.scene->name; }, "The scene's name (its name key).")
      .def_property_readonly("description", [](const PyScene& s) { return s.scene->description; },
                             "What the scene models, in words (its description key).")
      .def_property_readonly("source", [](const PyScene& s) { return s.scene->source; },
                             "Where the scene came from: its file, or the embedded default.")
      .def_property_readonly("path", [](const PyScene& s) -> py::object {
        return s.path.empty() ? py::object(py::none()) : py::object(py::str(s.path));
      }, "The scene file; None for the embedded chimney.")
      .def_property_readonly("overrides", [](const PyScene& s) { return s.overrides; },
                             "The KEY=VALUE overrides applied to the file, in order (as --set).")
      .def_property_readonly("rigid", [](const PyScene& s) { return s.scene->structure.rigid; },
                             "Whether the structure is a rigid block (no elastic modes).")
      .def_property_readonly("devices", [](const PyScene& s) {
        std::vector<std::string> names;
        for (const rocking::Device& d : rocking::scene_devices(*s.scene)) names.push_back(d.name);
        return names;
      }, "The names of the scene's devices, in the order of the history's columns.")
      .def_property_readonly("device_groups", [](const PyScene& s) {
        py::list out;
        for (const rocking::DeviceGroup& g : rocking::device_groups(*s.scene)) {
          py::list members;
          for (const rocking::Device& d : g.devices) members.append(d.name);
          out.append(py::dict("name"_a = g.name, "law"_a = g.law, "dissipates"_a = g.dissipates,
                              "prestress"_a = g.prestress_key ? py::object(py::float_(g.prestress)) : py::object(py::none()),
                              "devices"_a = members, "removal"_a = g.removal));
        }
        return out;
      }, "The devices as the scene names them (a [[device]] table, or \"damper\" for the\n"
         "[damper] pair): name, law, dissipates (the law's trait), prestress [N] (None:\n"
         "the law has none), devices (their names in the history) and removal (the\n"
         "--set text that removes it; variant \"without:NAME\" runs without it).")
      .def("__repr__", [](const PyScene& s) {
        return fmt::format("<rocking.Scene '{}' from {}{}>", s.scene->name, s.scene->source,
                           s.overrides.empty() ? "" : fmt::format(" with {} override(s)", s.overrides.size()));
      });
}

// rocking.Record: a ground motion read from a file or given as samples.
void bind_record(py::module_& m) {
  py::class_<PyRecord>(m, "Record", "A ground-motion record: a(t) piecewise linear between evenly spaced samples.")
      .def(py::init(&record_from_array), "acc"_a, "dt"_a, "units"_a = "g", "name"_a = "array",
           "A record from memory: acc[i] at t = i dt, in units g, m/s2, cm/s2 (gal) or mm/s2.")
      .def_static("load", &record_load, "path"_a, "component"_a = py::none(), "units"_a = py::none(),
                  "format"_a = "auto", "dt"_a = py::none(), "process"_a = py::none(),
                  "Reads a record file in any format the command line reads (PEER .AT2, GeoNet,\n"
                  "K-NET, COSMOS, CSV, columns); the same options as --component, --units,\n"
                  "--format and --dt. Any component: simulate refuses one named vertical (Up,\n"
                  "U-D, HNZ) as its record, and one named horizontal as its vertical.\n"
                  "process: as --process, e.g. 'detrend=1,taper=0.05,highpass=0.1,lowpass=25'.")
      .def("scaled", [](const PyRecord& r, double f) {
        if (!std::isfinite(f)) throw rocking::InputError(fmt::format("scaled {}: must be a finite number", f));
        return PyRecord{std::make_shared<const rocking::GroundMotion>(r.motion->scaled(f)), r.path};
      }, "factor"_a, "The record with every acceleration times factor.")
      .def("measures", &record_measures, "periods"_a = py::none(), "damping"_a = 0.05,
           "The dict of `rocking record --json` for this record, each key naming its unit:\n"
           "pga_g and pga_time_s, pgv_m_s, pgd_m, arias_m_s, d5_95_s, cav_m_s, and psa_g\n"
           "at periods_s (default: the 21 NGA-West2 periods) for the damping ratio; and\n"
           "the file's metadata (id, file, format, event, station, component, units, dt_s,\n"
           "npts, duration_s; None where the file does not say).")
      .def_property_readonly("name", [](const PyRecord& r) { return r.motion->name(); },
                             "The record's name (its file's, or the one given).")
      .def_property_readonly("description", [](const PyRecord& r) { return r.motion->description(); },
                             "What the record is, in words (event, station, component when the file says).")
      .def_property_readonly("path", [](const PyRecord& r) -> py::object {
        return r.path.empty() ? py::object(py::none()) : py::object(py::str(r.path));
      }, "The file it was read from; None when it was built from an array.")
      .def_property_readonly("dt", [](const PyRecord& r) { return r.motion->sample_interval(); },
                             "The sample interval [s].")
      .def_property_readonly("duration", [](const PyRecord& r) { return r.motion->duration(); },
                             "From the first sample to the last [s].")
      .def_property_readonly("pga_g", [](const PyRecord& r) { return r.motion->peak() / rocking::gravity; },
                             "The peak ground acceleration, max |a| [g] (summary.json's and\n"
                             "`rocking record --json`'s pga_g).")
      .def_property_readonly("times", [](const PyRecord& r) { return read_only(r.motion->sample_times()); },
                             "The sample times [s] (a read-only copy).")
      .def_property_readonly("acceleration", [](const PyRecord& r) { return read_only(r.motion->sample_values()); },
                             "The samples [m/s2], as scaled (a read-only copy: build a new Record\n"
                             "to change them).")
      .def("__len__", [](const PyRecord& r) { return r.motion->sample_count(); })
      .def("__repr__", [](const PyRecord& r) {
        return fmt::format("<rocking.Record '{}': {} samples, dt {:g} s, PGA {:.3g} g>", r.motion->name(),
                           r.motion->sample_count(), r.motion->sample_interval(), r.motion->peak() / rocking::gravity);
      });
}

// rocking.Result and rocking.simulate: one run.
void bind_simulate(py::module_& m) {
  py::class_<PyResult>(m, "Result", "One run: its summary, history and events.")
      .def_readonly("summary", &PyResult::summary, "The dict of `rocking simulate`'s summary.json.")
      .def_property_readonly("peaks", [](const PyResult& r) { return r.summary["peaks"]; },
                             "Absolute peaks by quantity name (summary.json's peaks): the schema's peak\n"
                             "quantities the scene reports and each device's NAME.elongation and NAME.force\n"
                             "(`rocking simulate --list-quantities` lists them with units).")
      .def_readonly("history", &PyResult::history,
                    "Column name -> NumPy array, the columns of history.csv (units in MODEL.md 7);\n"
                    "'phase' is the pivot: 0 full contact, +1 / -1 rocking on the right / left.")
      .def_readonly("events", &PyResult::events,
                    "Phase changes in time order: dicts of kind (uplift, impact, overturn,\n"
                    "fracture), t [s], pivot, device for a fracture, and joint (0 the base, K\n"
                    "the joint K above it) on a structure with [[joint]]s.")
      .def_readonly("outcome", &PyResult::outcome, "completed, overturned, separated (a joint in tension: the part above would leave it), sliding (a joint's friction demand reached its scene's limit), undecided (an impact the momentum law does not decide; summary['undecided'] says which) or failed")
      .def("to_pandas", [](const PyResult& r) { return to_pandas(r.history); },
           "The history as a pandas DataFrame (needs pandas; the project does not).")
      .def("__repr__", [](const PyResult& r) {
        return fmt::format("<rocking.Result {}: {}>", r.outcome, py::str(r.summary["peaks"]).cast<std::string>());
      });

  m.def("simulate", &simulate, "scene"_a = py::none(), "record"_a = py::none(), "scale"_a = 1.0, "rtol"_a = 1e-4,
        "atol"_a = 1e-7, "integrator"_a = "auto", "every"_a = py::none(), "duration"_a = py::none(),
        "max_events"_a = 100000L, "max_steps"_a = 10'000'000L, "integrate_contact"_a = false, "history"_a = true,
        "columns"_a = py::none(), "vertical"_a = py::none(), "azimuth"_a = py::none(), "second"_a = py::none(),
        "Runs a scene under a record (a Record, or a file path; None: the scene's own\n"
        "excitation), scaled by scale, as `rocking simulate` does with the same defaults.\n"
        "vertical: the vertical motion (as --vertical: a Record of a vertical\n"
        "component, a file path, or a component name of record's file, e.g. 'Up';\n"
        "None: the scene's excitation.vertical when it runs its own excitation).\n"
        "azimuth: the plane's angle [degrees] from record toward second (its other\n"
        "horizontal component, a Record or a path), as --azimuth and --second.\n"
        "columns: the history's quantities by name (as --history: also node4.x_abs,\n"
        "element1.V, x_g; None: the scene's [output] history, else all it reports).\n"
        "every: the history interval [s] (None: the scene's [output] interval, else 0.01).\n"
        "Returns a Result; raises ValueError for bad input, rocking.RunError (with\n"
        ".result) when the run cannot finish, KeyboardInterrupt on Ctrl-C.");
}

// rocking.quantities, rotd and modal: the schema, spectra and the modes.
void bind_tables(py::module_& m) {
  m.def("quantities",
        [](const py::object& s) {
          py::list out;
          for (const rocking::QuantityRow& q : rocking::quantity_rows(rocking::make_contact_model(*scene_of(s).scene, true)))
            out.append(py::dict("name"_a = q.name, "unit"_a = q.unit, "words"_a = q.words, "history"_a = q.history,
                                "peak"_a = q.peak, "study"_a = q.study, "reported"_a = q.reported,
                                "on_request"_a = q.on_request));
          return out;
        },
        "scene"_a = py::none(),
        "What the scene reports (`rocking simulate --list-quantities`): one dict per\n"
        "quantity of the schema, then per quantity of each device (NAME.elongation,\n"
        "NAME.force): name, unit, words, whether it is a history column, a peak and a\n"
        "study quantity (ida columns, limits, fractiles), and whether this scene reports it.");

  m.def("rotd",
        [](const PyRecord& first, const PyRecord& second, std::optional<std::vector<double>> periods, double damping) {
          const std::vector<double> ts = periods.value_or(rocking::standard_periods());
          py::list r50, r100;
          for (const rocking::RotD& r : rocking::rotd_spectrum(*first.motion, *second.motion, ts, damping)) {
            r50.append(r.rotd50 / rocking::gravity);
            r100.append(r.rotd100 / rocking::gravity);
          }
          return py::dict("periods_s"_a = ts, "damping"_a = damping, "rotd50_g"_a = r50, "rotd100_g"_a = r100);
        },
        "first"_a, "second"_a, "periods"_a = py::none(), "damping"_a = 0.05,
        "RotD50 and RotD100 of two horizontal components recorded together (as\n"
        "`rocking record --rotd`; Boore 2010, MODEL.md 14): the median and the largest\n"
        "PSA [g] over the azimuths 0-179 degrees of a1 cos phi + a2 sin phi, at\n"
        "periods_s (default the 21 NGA-West2 periods): a dict of periods_s, damping,\n"
        "rotd50_g, rotd100_g.");

  m.def("modal", [](const py::object& s) { return to_python(rocking::modal_summary(*scene_of(s).scene)); },
        "scene"_a = py::none(),
        "The dict of `rocking modal --json`: fixed-base and rocking frequencies [Hz], p,\n"
        "the devices' rocking stiffness, r of Eq. 10, M_ref, V_ref; for a rigid block its\n"
        "geometry, p = sqrt(m g R / J_p) and uplift_g.");
}

// rocking.Ida and rocking.ida: a study.
void bind_ida(py::module_& m) {
  py::class_<PyIda>(m, "Ida", "An incremental dynamic analysis: one row per (record, level, variant).")
      .def_readonly("rows", &PyIda::rows,
                    "Dicts of record, variant, im, level, scale, record_im, outcome, the peaks and\n"
                    "t_end (error instead when the job could not run).")
      .def_readonly("variants", &PyIda::variants, "The variants' names, in the order of the rows.")
      .def_readonly("records", &PyIda::records, "The records' paths (or names, for Record objects from arrays).")
      .def_readonly("hunts", &PyIda::hunt_rows,
                    "With hunt=True: one dict per (record, variant), record-major, with hunt.csv's\n"
                    "columns (collapse_level None when no level up to hunt_max overturned; error\n"
                    "None unless the hunt could not run) and points, every level it ran and why\n"
                    "(hunt_points.csv's trace, bisect, fill).")
      .def(
          "fractiles",
          [](const PyIda& r, const std::string& quantity, const std::string& variant) {
            if (!r.summary) throw rocking::InputError("fractiles: a hunt has none; run a ladder (hunt=False)");
            py::list out;
            for (const auto& f : r.summary->fractiles(variant_index(r, variant), rocking::parse_study_quantity(quantity)))
              out.append(py::dict("level"_a = f.level, "runs"_a = f.runs, "collapsed"_a = f.collapsed,
                                  "p16"_a = f.edp[0], "p50"_a = f.edp[1], "p84"_a = f.edp[2]));
            return out;
          },
          "quantity"_a = "theta_over_alpha", "variant"_a = "",
          "At each level, the 16/50/84 % fractiles of a peak over the records (an overturned\n"
          "run counts as +inf), for a variant (default: the first); the peaks as ida.csv\n"
          "holds them (9 digits), so they are summary.csv's.")
      .def_readonly("limits", &PyIda::limits,
                    "The limit states' names for fragility(): overturning, then those given as\n"
                    "limits= (\"theta_over_alpha>=0.5\").")
      .def(
          "fragility",
          [](const PyIda& r, const std::string& limit, const std::string& variant, long bootstrap,
             unsigned long seed, double beta_modelling) {
            // By its name ("theta_over_alpha>=0.5") or as it was given ("theta_over_alpha=0.5").
            auto it = std::find(r.limits.begin(), r.limits.end(), limit);
            if (it == r.limits.end() && limit.find('=') != std::string::npos && limit.find(">=") == std::string::npos) {
              std::string name;
              try {
                name = rocking::parse_limit(limit).name;
              } catch (const rocking::InputError&) {
              }
              it = std::find(r.limits.begin(), r.limits.end(), name);
            }
            if (it == r.limits.end())
              throw rocking::InputError(fmt::format("limit '{}' is not one of this study's (give it to ida as limits=)", limit));
            const rocking::FragilityOptions o = fragility_options(bootstrap, seed, beta_modelling);
            const auto l = static_cast<std::size_t>(it - r.limits.begin());
            const std::size_t v = variant_index(r, variant);
            rocking::LimitFragility f;
            {
              py::gil_scoped_release unlocked;
              if (r.summary) {
                f = r.summary->fragility(v, l, o);
              } else {  // a hunt's capacities: each record's lowest overturning, or censored
                f = rocking::capacity_fragility(rocking::overturning_limit(),
                                                rocking::hunt_capacities(r.hunts, r.variants.size(), v), o);
              }
            }
            return to_python(rocking::fragility_json(f, r.records));
          },
          "limit"_a = "overturning", "variant"_a = "", "bootstrap"_a = 1000L, "seed"_a = 20020101UL,
          "beta_modelling"_a = 0.0,
          "MODEL.md 13 for a limit state (overturning, or one given to ida as limits=, by\n"
          "its name \"theta_over_alpha>=0.5\" or as given \"theta_over_alpha=0.5\") and a\n"
          "variant, as summary.json's fragility entries: each record's capacity (the lowest\n"
          "level that reached it, or the highest it ran to without, censored), the stripes\n"
          "(runs and how many reached it per level, counted by ida's resurrection=), and\n"
          "the lognormal fragility fitted to each (median, beta, their standard errors;\n"
          "the 90 % intervals of a bootstrap of `bootstrap` resamples of the records\n"
          "from `seed`, as --bootstrap and --seed; beta_total with beta_modelling, as\n"
          "--beta-modelling).")
      .def(
          "summary",
          [](const PyIda& r, long bootstrap, unsigned long seed, double beta_modelling) {
            return to_python(
                ida_report(r, fragility_options(bootstrap, seed, beta_modelling), rocking::record_ids(r.study->records()))
                    .summary);
          },
          "bootstrap"_a = 1000L, "seed"_a = 20020101UL, "beta_modelling"_a = 0.0,
          "The dict of summary.json, as `rocking ida` writes it: the intensity measure,\n"
          "levels, record ids, and per variant the fractile IDA curves, each limit state's\n"
          "fragility (as fragility()) and the records that stand again above their first\n"
          "overturning. bootstrap, seed, beta_modelling as fragility().")
      .def(
          "write",
          [](const PyIda& r, const py::object& folder, long bootstrap, unsigned long seed, double beta_modelling) {
            const auto dir = argument<std::filesystem::path>(folder, "folder", "a path");
            return ida_write(r, dir, fragility_options(bootstrap, seed, beta_modelling));
          },
          "folder"_a, "bootstrap"_a = 1000L, "seed"_a = 20020101UL, "beta_modelling"_a = 0.0,
          "Writes into folder (made if missing) the files `rocking ida --out folder --no-plot`\n"
          "writes, byte for byte: ida.csv (a hunt: hunt.csv and hunt_points.csv),\n"
          "records.csv, summary.csv (a ladder's fractiles), fragility.csv,\n"
          "fragility_points.csv and summary.json. Returns their paths.")
      .def("to_pandas", [](const PyIda& r) { return to_pandas_rows(r.rows); },
           "The rows as a pandas DataFrame (needs pandas; the project does not).");

  m.def("ida", &ida, "scene"_a, "records"_a, "im"_a = "sf", "levels"_a, "variants"_a = py::none(), "threads"_a = 0,
        "rtol"_a = 1e-4, "atol"_a = 1e-7, "integrator"_a = "auto", "damping"_a = 0.05,
        "limits"_a = py::none(), "resurrection"_a = "first", "hunt"_a = false, "hunt_step"_a = py::none(),
        "hunt_growth"_a = 1.5, "hunt_max"_a = py::none(), "precision"_a = py::none(), "fill_step"_a = py::none(),
        "Incremental dynamic analysis as `rocking ida`: every record (files, folders or\n"
        "list files) scaled to each level of the intensity measure im (sf, pga, pgv,\n"
        "sa:T, sa:T1, saavg:T1:T2) for each variant (scene, without:NAME, fixed-base,\n"
        "no-devices, damper, no-damper, or KEY=VALUE; None: the scene's own, as\n"
        "`rocking ida`: as built, without each energy-dissipating device, and on a\n"
        "fixed base when it rocks and is flexible). Runs on threads (0: every\n"
        "core); Ctrl-C stops it (KeyboardInterrupt). limits: limit states beside overturning\n"
        "for fragility(), as --limit takes them (\"theta_over_alpha=0.5\"). resurrection:\n"
        "first (a record counts as overturned from its first overturning on, Vamvatsikos\n"
        "& Cornell 2002) or keep (each level as it ran), as --resurrection.\n"
        "records: rocking.Record objects (from files or arrays) and paths of files,\n"
        "folders or list files. hunt=True: `rocking ida --hunt` from the lowest level\n"
        "(hunt_step, hunt_growth, hunt_max, precision, fill_step as --hunt-step ...;\n"
        "None: the program's defaults): .hunts has each record's and variant's first\n"
        "overturning, .fragility() their overturning fragility, .rows is empty.");
}

}  // namespace

PYBIND11_MODULE(rocking, m) {
  m.doc() =
      "rocking: earthquake response of flexible structures that rock on their base,\n"
      "with hysteretic dampers and tendons at the rocking interface (the library of\n"
      "the `rocking` command line; MODEL.md holds the equations).\n\n"
      "  scene = rocking.Scene.default()                  # the Christchurch chimney\n"
      "  rec = rocking.Record.load('elcentro_1940_ns.at2')\n"
      "  res = rocking.simulate(scene, rec)\n"
      "  res.peaks['theta_over_alpha'], res.history['theta'], res.events\n";
  m.attr("__version__") = ROCKING_VERSION;
  SigintStops::main_thread = py::module_::import("threading").attr("main_thread")().attr("ident").cast<unsigned long>();
  bind_errors(m);
  bind_scene(m);
  bind_record(m);
  bind_simulate(m);
  bind_tables(m);
  bind_ida(m);
}
