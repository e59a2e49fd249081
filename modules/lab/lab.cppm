// rocking.lab: the browser lab's API (`rocking serve`), without the HTTP. A
// request is a JSON object naming a scene and a record by the ids the lab
// lists (never a path), the scene's overrides as `--set` takes them, a scale,
// and a twin to compare with (a variant of rocking.study: fixed-base,
// no-damper, no-devices, without:NAME); it is read into the run
// specification of rocking.run, so that a run from the page is the run
// `rocking simulate` makes of the same choices (MODEL.md 6-7) and its summary
// is `rocking simulate --json`'s. The modal endpoint answers `rocking modal
// --json` (MODEL.md 8), the IDA endpoint a small ladder of scales as `rocking
// ida` runs it (MODEL.md 13). Every request is bounded (body size, duration,
// nodes, history rows, IDA runs) and checked as the command line checks it:
// an InputError of one line becomes a 4xx answer with that line.
module;
#include <nlohmann/json.hpp>
#include <cstddef>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>
export module rocking.lab;
export import rocking.run;
export import rocking.study;

export namespace rocking {

// The work one request may ask for.
struct LabLimits {
  std::size_t request_bytes = 64 * 1024;  // a request's body
  std::size_t upload_bytes = 4 << 20;     // an uploaded record's request (its text in JSON)
  std::size_t uploads = 16;               // uploaded records kept (the oldest goes first)
  double duration = 200;                  // simulated time of a run [s]
  std::size_t nodes = 64;                 // nodes of a structure
  std::size_t history_rows = 20000;       // rows of a run's history
  std::size_t overrides = 32;             // --set texts of a request
  std::size_t ida_levels = 20;            // levels of an IDA (each run for the scene and its twin)
  double seconds = 30;                    // computing time of a request's runs [s]
};

// Where the lab's scenes and records are: every *.toml under `scenes` (its
// subfolders too) and every record file under `records` are listed, by
// their path relative to the folder ("towers/tower_8", "elcentro_1940_ns.at2").
struct LabFolders {
  std::filesystem::path scenes, records;
};

// An answer: an HTTP status and a JSON body ({"error": "one line"} when not 200).
struct LabAnswer {
  int status = 200;
  std::string body;
};

// A simulate request read and checked: the run it asks for and, when it
// asks for a twin (a variant of rocking.study), the twin's run.
struct LabRun {
  RunSpec spec;
  std::string twin;                 // the variant's name; empty: no twin
  std::optional<RunSpec> twin_spec;
};

class Lab {
 public:
  explicit Lab(LabFolders folders, LabLimits limits = {});
  const LabLimits& limits() const { return limits_; }

  // GET /api/scenes: [{id, name, description, rigid, nodes, damper, devices: [{index, name, law, P0}],
  // excitation (in words), pulse: {amplitude_g, period} (null when its excitation is no pulse), usable}]
  nlohmann::json scenes() const;
  // GET /api/records: [{id, name, pga_g, duration_s, dt_s}] (read once)
  nlohmann::json records() const;
  // POST /api/simulate: {scene, record, component, scale, set, duration, every, compare} ->
  // {summary, history, structure, twin: {variant, label, summary, history} | null}, as JSON text.
  std::string simulate(const nlohmann::json& request) const;
  // POST /api/upload: {name, text, component} -> {id, name, pga_g, duration_s}: a record file's text,
  // read by the same readers as a file of the records folder (its format from its content); its id
  // ("upload/N/NAME") names it in later requests.
  nlohmann::json upload(const nlohmann::json& request) const;
  // POST /api/modal: {scene, set} -> `rocking modal --json`.
  nlohmann::json modal(const nlohmann::json& request) const;
  // POST /api/ida: {scene, record, component, set, scales, compare} -> {columns, rows: [{variant, level, outcome, peaks}]}.
  nlohmann::json ida(const nlohmann::json& request) const;

  // Reads a simulate request (no run): InputError of one line otherwise.
  LabRun read_simulate(const nlohmann::json& request) const;

  // The dispatcher: a method and a path ("/api/simulate") with the body, to
  // an answer. 404 for an unknown path, 405 for a wrong method, 413 for a
  // body over the limit, 400 for bad JSON or input, 422 for a run that failed.

  LabAnswer answer(std::string_view method, std::string_view path, std::string_view body) const;

 private:
  struct SceneEntry {
    std::string id, path;
  };
  struct RecordEntry {
    std::string id, path;
  };
  const SceneEntry& scene_entry(const nlohmann::json& request) const;
  Scene scene_of(const nlohmann::json& request, const std::vector<std::string>& overrides) const;
  std::shared_ptr<const GroundMotion> motion(const std::string& record_id, const std::string& component) const;
  std::string record_path(const std::string& id) const;

  LabFolders folders_;
  LabLimits limits_;
  std::vector<SceneEntry> scenes_;
  std::vector<RecordEntry> records_;
  mutable std::mutex mutex_;  // guards the caches below
  mutable std::map<std::string, std::shared_ptr<const GroundMotion>> motions_;
  mutable std::shared_ptr<const nlohmann::json> record_list_;
  mutable std::vector<std::string> uploads_;  // the uploads' ids, oldest first
  mutable std::size_t upload_count_ = 0;
};

}  // namespace rocking
