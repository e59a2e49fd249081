// rocking.run: one run of a scene as every front end describes it (MODEL.md
// 6-7 for what a run is; the command line's simulate, plot, animate and
// tradeoff and the Python module's simulate all describe runs this way): the
// scene, its ground motion (the scene's [excitation], or a record file or an
// in-memory record, scaled; with a vertical motion when one is given, MODEL.md
// 14), the integrator and its limits, and the history
// (columns and interval, else the scene's [output]). prepare_run checks every
// choice and makes the motion, the model, the run options, the history's
// columns and the run's label once, so that no front end assembles a run of
// its own. Messages name each choice as the front end spells it: `prefix`
// "--" gives "--rtol 2: ...", "" gives Python's "rtol 2: ...".
module;
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.run;
export import rocking.report;

export namespace rocking {

// How a record file is read: --format, --component, --units, --dt.
struct RecordFileChoice {
  std::string format = "auto";
  std::string component;
  std::string units;  // empty: the file's own (g where a file states none)
  double dt = 0;      // one-column files [s]
  std::string process;  // Processing's text (parse_processing); empty: as recorded
  bool given() const { return format != "auto" || !component.empty() || !units.empty() || dt != 0 || !process.empty(); }
};
RecordOptions record_options(const RecordFileChoice& c, std::string_view prefix = "--");

// The ground motion of a run: the scene's [excitation], a record file, or a
// record already in memory, with its vertical motion when one is given
// (GroundMotion::vertical); times `scale`.
struct MotionChoice {
  std::string record;  // a file; empty: the scene's [excitation] (or `given`)
  RecordFileChoice file;
  double scale = 1;
  std::shared_ptr<const GroundMotion> given;  // an in-memory record (Python's Record), unscaled
  std::string given_path;                      // where `given` was read from, for the label ("" if from arrays)
  // The vertical motion (MODEL.md 14), upward, scaled as the horizontal: a
  // record file, or a component of the record file's own (a GeoNet file's
  // "Up"), read as vertical_file says (its component and units; the format
  // from its content); or a record in memory. None: the scene's
  // [excitation] vertical, when the run uses the scene's excitation.
  std::string vertical;
  RecordFileChoice vertical_file;
  std::shared_ptr<const GroundMotion> given_vertical;
  // The plane's azimuth [degrees] from the record's component toward its
  // other horizontal one (the record file's other, or `second`'s): the run
  // sees their projection a1 cos phi + a2 sin phi (MODEL.md 14). None: the
  // record's component as it is.
  std::optional<double> azimuth;
  std::string second;                              // a file: the other horizontal component (a PEER pair)
  std::shared_ptr<const GroundMotion> given_second;  // or one in memory
  bool scene_excitation() const { return record.empty() && !given; }
};

// The factors a run's ground motion is scaled by: the scene's [excitation]
// scale (its own motion only) times the caller's.
struct ScaleFactors {
  double scene = 1, option = 1;
  double total() const { return scene * option; }
  std::string describe() const;  // "x3", or "x6 (scene 2 x --scale 3)"
};
ScaleFactors motion_scale(const Scene& scene, const MotionChoice& c);
GroundMotion load_motion(const Scene& scene, const MotionChoice& c, std::string_view prefix = "--");

// How the run is integrated.
struct SolverChoice {
  std::string integrator = "auto";
  double rtol = 1e-4, atol = 1e-7;  // RunOptions' defaults: the measured knee
  std::optional<double> duration;   // none: the motion's (the scene's excitation.duration for its own)
  long max_events = 100000;
  long max_steps = 10'000'000;
  bool integrate_contact = false;  // full contact by the backend, not exact steps
};
// scene_excitation: the run uses the scene's [excitation] (and its duration).
RunOptions run_options(const Scene& scene, const SolverChoice& c, bool scene_excitation, std::string_view prefix = "--");

// The history: chosen columns (empty: the scene's [output] history, else
// the default) every `every` seconds (none: the scene's [output] interval,
// else 0.01 s); at most max_history_rows rows.
struct HistoryChoice {
  std::vector<std::string> columns;
  std::optional<double> every;
};
inline constexpr double max_history_rows = 1e7;  // about 1.5 GB of history.csv: a mistake, not a study

struct RunSpec {
  Scene scene;
  MotionChoice motion;
  SolverChoice solver;
  HistoryChoice history;
  std::string prefix = "--";           // how messages spell a choice's name
  std::string columns_name = "history";  // ... and the history's columns ("columns" in Python)
  // The model integrates its energy balance (the run summary's); a figure or
  // a timing that reads no energy leaves it out.
  bool track_energy = true;
};

// Everything a run needs, checked: InputError of one line otherwise.
struct PreparedRun {
  GroundMotion motion;  // with its vertical motion, if any (the model then reports a_v)
  ScaleFactors scale;
  RunOptions options;  // with the history interval; `stop` is the caller's to set
  ContactModel model;  // energy tracked
  HistoryColumns columns;
  RunLabel label;
};
PreparedRun prepare_run(const RunSpec& spec);
// The same under a motion already loaded from spec.motion (load_motion with
// the same scene's excitation): runs of several variants of one scene under
// one record read it once.
PreparedRun prepare_run(const RunSpec& spec, GroundMotion motion);

}  // namespace rocking
