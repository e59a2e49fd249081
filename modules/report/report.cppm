// rocking.report: what a run or an analysis reports, in the forms every front
// end shares (the command line's files and --json, the Python module): the
// run's summary (summary.json: peaks, counts, outcome, energy balance,
// devices, cost), the columns of its history, the modal summary of a scene
// (MODEL.md 8; for a rigid block its geometry, p and r, Housner 1963) and the
// names records go by. JSON is handed over as nlohmann::json values (a run's
// summary) or as text.
module;
#include <rocking/eigen.hpp>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>
export module rocking.report;
export import rocking.simulation;
export import rocking.scene;
export import rocking.modal;
export import rocking.intensity;

export namespace rocking {

// What a run was: the scene, the motion, the factors the motion was scaled
// by (scale = scene_scale x option_scale) and the tolerances.
struct RunLabel {
  std::string scene, scene_source, motion, record;
  double scale = 1, scene_scale = 1, option_scale = 1;
  double rtol = 0, atol = 0;
  std::string vertical;  // the vertical motion's description; empty: none
};

// The run's summary (the keys of `rocking simulate --json` and
// summary.json), as a JSON value: front ends write it as text or build their
// own objects from it (Python's dict).
nlohmann::json run_summary(const RunLabel& label, const RunResult& r);

// A record's metadata and measures (`rocking record --json`, Python's
// Record.measures()), each key naming its unit: id, file, format, event, date,
// station, component, units, dt_s, npts, duration_s, stated_peak_g,
// processing (how the record was processed), pga_g, pga_time_s, pgv_m_s,
// pgd_m, arias_m_s, d5_95_s, cav_m_s, damping, periods_s, psa_g (null where
// the file does not say).
nlohmann::json record_summary(const std::string& id, const std::string& file, const GroundMotion& motion,
                              const RecordMeasures& m);

// A record's name for titles and summaries (the stand-in record says so),
// and the same with what its header says it is (event, station, PGA).
std::string describe_motion(const std::string& name);
std::string describe_motion(const GroundMotion& motion);

// The history's columns. By default the history quantities of
// rocking.quantities that the model reports, in the schema's order, then each
// device's quantities under its name ("damper_left.elongation"); or the
// quantities a user chose (`simulate --history`, a scene's [output] history,
// Python's columns=): any history or on-request quantity, a device's, a
// node's or an element's ("node4.x_abs", "element1.M_bottom"), t always first.
struct HistoryColumns {
  struct Column {
    std::optional<Quantity> quantity;                // a scalar quantity, or ...
    std::optional<MemberQuantityName> member;        // ... a node's or an element's, or ...
    std::optional<JointQuantityName> joint;          // ... a joint's above the base, or ...
    std::size_t device = 0;                          // ... the model's device (index) ...
    DeviceQuantity of = DeviceQuantity::elongation;  // ... and which of its quantities
  };
  std::vector<Column> columns;
  std::vector<std::string> device_names;  // the model's devices, by index
  std::vector<std::string> names() const;    // "delta_t", ..., "damper_left.elongation", ...
  std::vector<std::string> headers() const;  // the same with units: "delta_t [-]"
  std::size_t size() const { return columns.size(); }
  bool has_members() const;  // some column is a node's or an element's
  // One row's values in the columns' order (out is resized): a broken
  // device's are NaN. u, u_dot: the nodal elastic displacements and
  // velocities (Observer::nodal), read by node and element columns only.
  // joints: every joint's sample (Observer::joints), read by joint columns only.
  void values(const ContactModel& m, const Response& r, const std::vector<DeviceSample>& devices,
              Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot,
              std::vector<double>& out, std::span<const JointSample> joints = {}) const;
};
HistoryColumns history_columns(const ContactModel& m);
// The chosen quantities by name, t first whether named or not; InputError
// naming a quantity that is unknown, not a history quantity, that this model
// does not report or a node or element it does not have (the message names
// the choice after `option`).
HistoryColumns history_columns(const ContactModel& m, const std::vector<std::string>& chosen,
                               std::string_view option = "--history");

// A run's history as the scene and the caller choose it: the columns the
// caller names (`option`: "--history", "columns"), else the scene's [output]
// history, else the default; the row interval given, else the scene's
// [output] interval, else 0.01 s.
HistoryColumns history_columns(const Scene& scene, const ContactModel& m, const std::vector<std::string>& chosen,
                               std::string_view option);
inline constexpr double default_history_interval = 0.01;  // [s]
double history_interval(const Scene& scene, std::optional<double> given);

// An observer that turns each response into its history columns' values
// (with the devices' samples and nodal displacements handed over before the
// row) and hands them to row(): what history.csv and Python's arrays share.
class HistoryObserver : public Observer {
 public:
  HistoryObserver(const ContactModel& m, HistoryColumns columns);
  const HistoryColumns& columns() const { return columns_; }
  void record(const Response& r) override;
  void devices(const std::vector<DeviceSample>& samples) override { devices_ = samples; }
  void nodal(Eigen::Ref<const Eigen::VectorXd> u, Eigen::Ref<const Eigen::VectorXd> u_dot) override;
  bool wants_velocities() const override { return members_; }
  void joints(std::span<const JointSample> samples) override { joints_.assign(samples.begin(), samples.end()); }

 protected:
  virtual void row(const Response& r, const std::vector<double>& values) = 0;

 private:
  const ContactModel* model_;
  HistoryColumns columns_;
  bool members_ = false;
  std::vector<DeviceSample> devices_;
  Eigen::VectorXd u_, u_dot_;
  std::vector<double> values_;
  std::vector<JointSample> joints_;
};

// The schema as this model reports it: each quantity's name, unit, roles
// (history, peak, study: an IDA column and a --limit; on request), words and
// whether the model has it; then the model's devices' quantities by name,
// then its nodes' and elements' ("nodeK.x" for K = 1 .. N, on request). As rows (the
// Python module's dicts) and as a table for people (`rocking simulate
// --list-quantities`).
struct QuantityRow {
  std::string name, unit, words;
  bool history = false, peak = false, study = false, reported = false;
  bool on_request = false;  // a history column when chosen (--history), not by default
};
std::vector<QuantityRow> quantity_rows(const ContactModel& m);
std::string quantity_table_text(const ContactModel& m);

// A rigid block's geometry and rocking parameters: p = sqrt(m g R / J_p),
// uplift at a_g = uplift_g g about the right pivot (the devices' held moment
// included), r of Eq. 10.
struct BlockSummary {
  double mass = 0, J_p = 0, H_cg = 0, alpha_cg = 0, R = 0, p = 0, r_eq10 = 0, uplift_g = 0;
  RockingStiffness devices;  // about the right pivot
};
BlockSummary block_summary(const Scene& scene);

// `rocking modal --json`: the modal summary of an elastic scene, or the block
// summary of a rigid one ("rigid": true).
nlohmann::json modal_summary(const Scene& scene);

}  // namespace rocking
